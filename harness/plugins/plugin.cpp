#include "harness/plugins/plugin.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nettle/sha2.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <deque>
#include <fstream>
#include <memory>
#include <new>
#include <stdexcept>

#include "nurbsbench/evaluator.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "strategies/aligned_vector.h"

namespace nurbs {

namespace fs = std::filesystem;

namespace {

// The header promises 64-byte alignment of every array the harness passes: AlignedVector.

// The scene as the header's plain arrays, with the storage they point into. Containers whose
// elements are pointed at are deques or are filled before the pointers are taken.
class PlainScene {
 public:
  explicit PlainScene(const Scene& scene) : name_(scene.name) {
    for (const Surface& s : scene.surfaces) surfaces_.push_back(convert(s));
    scene_ = {name_.c_str(), static_cast<std::uint32_t>(surfaces_.size()), surfaces_.data()};
  }
  PlainScene(const PlainScene&) = delete;
  PlainScene& operator=(const PlainScene&) = delete;
  const nbe_scene* get() const { return &scene_; }

 private:
  const double* keep(AlignedVector<double> values) {
    return arrays_.emplace_back(std::move(values)).data();
  }
  template <class Range>
  const double* keep_range(const Range& r) {
    return keep(AlignedVector<double>(r.begin(), r.end()));
  }

  nbe_surface convert(const Surface& s) {
    nbe_surface out{};
    out.degree_u = static_cast<std::uint32_t>(s.degree_u);
    out.degree_v = static_cast<std::uint32_t>(s.degree_v);
    const std::vector<Point3>& points = s.control_points();
    const std::vector<double>& weights = s.control_weights();
    out.point_count = static_cast<std::uint32_t>(points.size());
    if (s.is_tspline()) {
      out.kind = NBE_SURFACE_TSPLINE;
      out.knots_u = keep_range(s.tspline->knots_u);
      out.knots_v = keep_range(s.tspline->knots_v);
    } else {
      out.kind = NBE_SURFACE_NURBS;
      out.count_u = static_cast<std::uint32_t>(s.count_u);
      out.count_v = static_cast<std::uint32_t>(s.count_v);
      out.knots_u = keep_range(s.knots_u);
      out.knots_v = keep_range(s.knots_v);
    }
    AlignedVector<double> cartesian, homogeneous;
    cartesian.reserve(points.size() * 3);
    homogeneous.reserve(points.size() * 4);
    for (std::size_t k = 0; k < points.size(); ++k) {
      const double w = weights[k];
      cartesian.insert(cartesian.end(), points[k].begin(), points[k].end());
      homogeneous.insert(homogeneous.end(),
                         {points[k][0] * w, points[k][1] * w, points[k][2] * w, w});
    }
    out.points = keep(std::move(cartesian));
    out.homogeneous = keep(std::move(homogeneous));
    out.weights = keep_range(weights);
    out.u_min = s.u_min();
    out.u_max = s.u_max();
    out.v_min = s.v_min();
    out.v_max = s.v_max();
    out.rational = s.is_rational() ? 1 : 0;
    out.reversed = s.reversed ? 1 : 0;
    if (s.trim) {
      std::vector<nbe_trim_loop>& loops = loops_.emplace_back();
      for (const TrimLoop& loop : s.trim->loops) {
        std::vector<nbe_trim_curve>& curves = curves_.emplace_back();
        for (const TrimCurve& c : loop.curves) {
          AlignedVector<double> uv;
          for (const Point2& p : c.points) uv.insert(uv.end(), p.begin(), p.end());
          curves.push_back({static_cast<std::uint32_t>(c.degree),
                            static_cast<std::uint32_t>(c.points.size()), keep_range(c.knots),
                            keep(std::move(uv)), keep_range(c.weights)});
        }
        loops.push_back({static_cast<std::uint32_t>(curves.size()), curves.data()});
      }
      out.trim_loop_count = static_cast<std::uint32_t>(loops.size());
      out.trim_loops = loops.data();
      out.trim_tolerance = s.trim->tolerance;
    }
    return out;
  }

  std::string name_;
  std::deque<AlignedVector<double>> arrays_;
  std::deque<std::vector<nbe_trim_curve>> curves_;
  std::deque<std::vector<nbe_trim_loop>> loops_;
  std::vector<nbe_surface> surfaces_;
  nbe_scene scene_{};
};

// A loaded library (its handle is never closed) and a copy of its table, zero past the plugin's
// struct_size so that fields a newer header appends read as absent.
struct Library {
  fs::path path;
  std::string sha256;
  nbe_evaluator table{};
};

Capabilities capabilities_of(const nbe_evaluator& t) {
  const std::uint32_t f = t.capabilities;
  Capabilities c;
  c.max_degree = t.max_degree == 0
                     ? kMaxDegree
                     : static_cast<int>(std::min<std::uint32_t>(t.max_degree, kMaxDegree));
  c.rational = f & NBE_CAP_RATIONAL;
  c.normals = f & NBE_CAP_NORMALS;
  c.fp32 = f & NBE_CAP_F32;
  c.fp64 = f & NBE_CAP_F64;
  c.sampling = {static_cast<bool>(f & NBE_CAP_GRID), static_cast<bool>(f & NBE_CAP_SPAN_GRID),
                static_cast<bool>(f & NBE_CAP_EXPLICIT)};
  c.trims = f & NBE_CAP_TRIMS;
  c.tspline = f & (NBE_CAP_TSPLINES | NBE_CAP_TSPLINES_ONLY);
  c.tspline_only = f & NBE_CAP_TSPLINES_ONLY;
  c.updates_control_points =
      (f & NBE_CAP_UPDATES_CONTROL_POINTS) && t.update_control_points != nullptr;
  return c;
}

// The strategy over a plugin's table: converts the scene and samples to plain arrays once per
// prepare, hands the plugin 64-byte aligned output buffers, checks what it says it wrote.
class PluginStrategy final : public Strategy {
 public:
  PluginStrategy(std::shared_ptr<const Library> library, const StrategyOptions& options)
      : library_(std::move(library)), table_(library_->table), caps_(capabilities_of(table_)) {
    std::vector<nbe_option> pairs;
    for (const auto& [key, value] : options.extra) pairs.push_back({key.c_str(), value.c_str()});
    const nbe_options o{options.threads, static_cast<std::uint32_t>(pairs.size()), pairs.data()};
    nbe_error error{};
    instance_ = table_.create(&o, &error);
    if (!instance_) fail("create", NBE_ERROR, error);
  }
  ~PluginStrategy() override {
    if (instance_) table_.release(instance_);
  }

  std::string_view name() const override { return table_.name; }
  Capabilities capabilities() const override { return caps_; }
  DeviceInfo device() const override {
    const bool gpu = table_.capabilities & NBE_CAP_GPU;
    return {fmt::format("{} (plugin {} {})", gpu ? "GPU" : "host CPU", table_.name,
                        table_.version ? table_.version : ""),
            gpu ? "gpu" : "cpu",
            {{"plugin_version", table_.version ? table_.version : ""},
             {"library", library_->path.string()},
             {"library_sha256", library_->sha256}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    plain_ = std::make_unique<PlainScene>(scene);
    const std::vector<SurfaceSamples> samples = sample_parameters(scene, request.sampling);
    samples_.clear();
    parameters_.clear();
    outputs_.clear();
    buffers_.clear();
    trimmed_.clear();
    const std::size_t scalar = request.precision == Precision::f32 ? sizeof(float) : sizeof(double);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const SurfaceSamples& s = samples[i];
      const double* u = parameters_.emplace_back(s.u.begin(), s.u.end()).data();
      const double* v = parameters_.emplace_back(s.v.begin(), s.v.end()).data();
      samples_.push_back({s.tensor ? 1u : 0u, s.u.size(), s.v.size(), u, v, s.count()});
      nbe_surface_output out{};
      out.count = s.count();
      out.positions = buffers_.emplace_back(out.count * 3 * scalar).data();
      if (request.normals) out.normals = buffers_.emplace_back(out.count * 3 * scalar).data();
      const bool trimmed = caps_.trims && scene.surfaces[i].trim.has_value();
      trimmed_.push_back(trimmed);
      if (trimmed)
        out.inside = reinterpret_cast<std::uint8_t*>(buffers_.emplace_back(out.count).data());
      outputs_.push_back(out);
    }
    result_samples_ = samples;
    nbe_request r{};
    r.precision = request.precision == Precision::f32 ? NBE_F32 : NBE_F64;
    r.normals = request.normals ? 1 : 0;
    r.sampling = request.sampling.mode == SamplingMode::grid        ? NBE_SAMPLING_GRID
                 : request.sampling.mode == SamplingMode::span_grid ? NBE_SAMPLING_SPAN_GRID
                                                                    : NBE_SAMPLING_EXPLICIT;
    r.grid_u = static_cast<std::uint32_t>(request.sampling.grid_u);
    r.grid_v = static_cast<std::uint32_t>(request.sampling.grid_v);
    r.span_steps = static_cast<std::uint32_t>(request.sampling.span_steps);
    plain_request_ = r;
    nbe_error error{};
    check("prepare",
          table_.prepare(instance_, plain_->get(), &plain_request_, samples_.data(), &error),
          error);
  }

  void evaluate() override {
    for (nbe_surface_output& out : outputs_) out.written = 0;
    nbe_error error{};
    check("evaluate", table_.evaluate(instance_, outputs_.data(), &error), error);
    for (std::size_t i = 0; i < outputs_.size(); ++i)
      if (outputs_[i].written != outputs_[i].count)
        throw std::runtime_error(
            fmt::format("plugin {}: wrong output count: surface {}: {} of {} samples written",
                        table_.name, i, outputs_[i].written, outputs_[i].count));
  }

  EvalResult read_back() override {
    EvalResult result;
    result.surfaces.resize(outputs_.size());
    for (std::size_t i = 0; i < outputs_.size(); ++i) {
      SurfaceResult& r = result.surfaces[i];
      const nbe_surface_output& out = outputs_[i];
      r.samples = result_samples_[i];
      r.positions = copy_points(out.positions, out.count);
      if (out.normals) r.normals = copy_points(out.normals, out.count);
      if (trimmed_[i]) r.inside.assign(out.inside, out.inside + out.count);
    }
    return result;
  }

  void update_control_points(const Scene& scene) override {
    if (!caps_.updates_control_points) return;
    auto moved = std::make_unique<PlainScene>(scene);
    nbe_error error{};
    check("update_control_points", table_.update_control_points(instance_, moved->get(), &error),
          error);
    plain_ = std::move(moved);
  }

 private:
  PointArray copy_points(const void* data, std::size_t count) const {
    PointArray p(request_.precision, count);
    if (request_.precision == Precision::f32)
      std::memcpy(p.f32(), data, count * 3 * sizeof(float));
    else
      std::memcpy(p.f64(), data, count * 3 * sizeof(double));
    return p;
  }

  void check(const char* function, std::int32_t status, const nbe_error& error) const {
    if (status != NBE_OK) fail(function, status, error);
  }
  [[noreturn]] void fail(const char* function, std::int32_t status, const nbe_error& error) const {
    // The message is the plugin's: bounded by its buffer even when it forgot the terminator, and
    // kept to one line.
    std::string message(error.message, strnlen(error.message, sizeof error.message));
    std::replace(message.begin(), message.end(), '\n', ' ');
    const std::string text = fmt::format("plugin {}: {} returned error {}{}", table_.name, function,
                                         status, message.empty() ? "" : ": " + message);
    if (status == NBE_UNSUPPORTED) throw RefusedError(text);
    throw std::runtime_error(text);
  }

  std::shared_ptr<const Library> library_;
  const nbe_evaluator& table_;
  Capabilities caps_;
  void* instance_ = nullptr;
  EvalRequest request_;
  nbe_request plain_request_{};
  std::unique_ptr<PlainScene> plain_;
  std::deque<AlignedVector<double>> parameters_;
  std::deque<AlignedVector<std::byte>> buffers_;
  std::vector<nbe_samples> samples_;
  std::vector<SurfaceSamples> result_samples_;
  std::vector<nbe_surface_output> outputs_;
  std::vector<bool> trimmed_;
};

bool valid_name(const char* name) {
  if (!name) return false;
  const std::size_t n = strnlen(name, 65);
  if (n == 0 || n > 64) return false;
  return std::all_of(name, name + n, [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
  });
}

// The name a library that cannot tell its own goes by: its file name without "lib" and ".so...".
std::string file_name_of(const fs::path& path) {
  std::string name = path.filename().string();
  if (name.starts_with("lib") && name.size() > 3) name.erase(0, 3);
  if (const std::size_t so = name.find(".so"); so != std::string::npos && so > 0) name.erase(so);
  return name;
}

// Opens the library and reads its table; the reason it cannot be used otherwise.
std::string open_library(Library& library) {
  void* handle = ::dlopen(library.path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    return fmt::format("fails to load: {}", why ? why : "dlopen failed");
  }
  void* symbol = ::dlsym(handle, NBE_ENTRY_POINT);
  if (!symbol)
    return fmt::format("missing entry points: the library exports no {}()", NBE_ENTRY_POINT);
  nbe_entry_point entry = nullptr;
  std::memcpy(&entry, &symbol, sizeof entry);  // object to function pointer, as POSIX allows
  const nbe_evaluator* table = entry(NBE_ABI_VERSION);
  if (!table)
    return fmt::format("wrong ABI version: {}() returned no table for this harness's version {}",
                       NBE_ENTRY_POINT, NBE_ABI_VERSION);
  if (table->abi_version < 1 || table->abi_version > NBE_ABI_VERSION)
    return fmt::format("wrong ABI version {} (this harness loads 1..{})", table->abi_version,
                       NBE_ABI_VERSION);
  // Version 1's table ends with release; a later header only appends, so an older plugin's
  // smaller table is read up to its struct_size and the fields it lacks stay zero (absent).
  constexpr std::size_t kVersion1Size = offsetof(nbe_evaluator, release) + sizeof(table->release);
  if (table->struct_size < kVersion1Size)
    return fmt::format("wrong ABI version: struct_size {} is below version 1's {} bytes",
                       table->struct_size, kVersion1Size);
  std::memcpy(&library.table, table,
              std::min<std::size_t>(table->struct_size, sizeof(nbe_evaluator)));
  const nbe_evaluator& t = library.table;
  std::vector<std::string> missing;
  if (!t.name) missing.push_back("name");
  if (!t.create) missing.push_back("create");
  if (!t.prepare) missing.push_back("prepare");
  if (!t.evaluate) missing.push_back("evaluate");
  if (!t.release) missing.push_back("release");
  if (!missing.empty()) return fmt::format("missing entry points: {}", fmt::join(missing, ", "));
  if (!valid_name(t.name))
    return fmt::format("invalid name '{}' (1..64 characters of a-z 0-9 . _ -)",
                       std::string(t.name, strnlen(t.name, 80)));
  return {};
}

}  // namespace

std::string file_sha256(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read", path.string()));
  sha256_ctx ctx;
  sha256_init(&ctx);
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    sha256_update(&ctx, static_cast<std::size_t>(in.gcount()),
                  reinterpret_cast<const std::uint8_t*>(chunk.data()));
  }
  std::uint8_t digest[SHA256_DIGEST_SIZE];
  sha256_digest(&ctx, sizeof digest, digest);
  std::string hex;
  for (std::uint8_t byte : digest) hex += fmt::format("{:02x}", byte);
  return hex;
}

const StrategyEntry& load_plugin(const fs::path& given) {
  std::error_code ec;
  if (!fs::is_regular_file(given, ec))
    throw InputError(fmt::format("--plugin = {}: no such file", given.string()));
  auto library = std::make_shared<Library>();
  library->path = fs::absolute(given);
  library->sha256 = file_sha256(library->path);
  const std::string problem = open_library(*library);

  StrategyEntry entry;
  entry.role = "plugin";
  if (problem.empty()) {
    const nbe_evaluator& t = library->table;
    entry.name = t.name;
    entry.source = fmt::format("plugin {}{}{}", t.version ? t.version : "",
                               t.description ? ": " : "", t.description ? t.description : "");
    const Capabilities caps = capabilities_of(t);
    entry.probe = [] { return Availability{true, ""}; };
    entry.capabilities = [caps] { return caps; };
    entry.create = [library](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
      return std::make_unique<PluginStrategy>(library, options);
    };
  } else {
    // Available, so that every measurement of it is a `failed` record with the reason (a broken
    // plugin is the plugin's fault, not a missing device); the default capabilities let each
    // request reach create(), which fails.
    entry.name = file_name_of(library->path);
    entry.source = fmt::format("plugin (unusable: {})", problem);
    entry.probe = [] { return Availability{true, ""}; };
    entry.capabilities = [] { return Capabilities{}; };
    const std::string reason = fmt::format("plugin {}: {}", library->path.string(), problem);
    entry.create = [reason](const StrategyOptions&) -> std::unique_ptr<Strategy> {
      throw std::runtime_error(reason);
    };
  }
  try {
    return add_strategy(std::move(entry), {library->path.string(), library->sha256});
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("--plugin = {}: strategy name {}", given.string(), e.what()));
  }
}

void load_plugins(const std::vector<std::string>& paths) {
  for (const std::string& path : paths) load_plugin(path);
}

}  // namespace nurbs
