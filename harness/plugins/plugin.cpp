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
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "harness/atomic_file.h"
#include "harness/strategy_guard.h"
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

// A library and, once opened in this process (its handle is never closed), a copy of its table,
// zero past the plugin's struct_size so that fields a newer header appends read as absent.
struct Library {
  fs::path path;
  std::string sha256;
  nbe_evaluator table{};
  // Opened at most once per process: by the measurement child that loads it, or by the first
  // create() of `--isolation none`; `problem` is why it cannot be used ("" when it can).
  std::once_flag opened;
  std::string problem;
};

// What the table says it does: its capability bits, max_degree and whether it offers
// update_control_points.
struct TableCapabilities {
  std::uint32_t flags = 0, max_degree = 0;
  bool update_control_points = false;
};

Capabilities capabilities_of(const TableCapabilities& t) {
  const std::uint32_t f = t.flags;
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
  c.updates_control_points = (f & NBE_CAP_UPDATES_CONTROL_POINTS) && t.update_control_points;
  return c;
}

TableCapabilities table_capabilities(const nbe_evaluator& t) {
  return {t.capabilities, t.max_degree, t.update_control_points != nullptr};
}

// A string of the table (version, description): any bytes, made printable; absent is "".
std::string table_text(const char* text, std::size_t max_bytes) {
  return text ? plugin_text(std::string_view(text, strnlen(text, max_bytes)), max_bytes) : "";
}

// The strategy over a plugin's table: converts the scene and samples to plain arrays once per
// prepare, hands the plugin 64-byte aligned output buffers, checks what it says it wrote.
class PluginStrategy final : public Strategy {
 public:
  PluginStrategy(std::shared_ptr<const Library> library, const StrategyOptions& options)
      : library_(std::move(library)),
        table_(library_->table),
        caps_(capabilities_of(table_capabilities(table_))) {
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
    const std::string version = table_text(table_.version, 64);
    return {fmt::format("{} (plugin {} {})", gpu ? "GPU" : "host CPU", table_.name, version),
            gpu ? "gpu" : "cpu",
            {{"plugin_version", version},
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
    // made one line of valid UTF-8 (the records are JSON, the table a terminal's).
    const std::string message =
        plugin_text(std::string_view(error.message, strnlen(error.message, sizeof error.message)),
                    sizeof error.message);
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

// The name a library that cannot tell its own goes by: its file name without "lib" and ".so...",
// held to the name rule like a table's (lower case; any other character becomes '-'), so that it
// is a name every output can print and every option can take.
std::string file_name_of(const fs::path& path) {
  std::string name = path.filename().string();
  if (name.starts_with("lib") && name.size() > 3) name.erase(0, 3);
  if (const std::size_t so = name.find(".so"); so != std::string::npos && so > 0) name.erase(so);
  for (char& c : name) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    const bool allowed =
        (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
    if (!allowed) c = '-';
  }
  if (name.size() > 64) name.resize(64);
  return name.empty() ? "plugin" : name;
}

// Phases of loading, on the phase board, so that a crash or hang says where it happened.
constexpr std::string_view kLoadPhase = "dlopen (the library's constructors)";
constexpr std::string_view kEntryPhase = "nurbsbench_evaluator()";

// Opens the library and reads its table; the reason it cannot be used otherwise. Runs the
// plugin's code (constructors, the entry point): only in an isolated child, or in-process under
// --isolation none.
std::string open_library(Library& library) {
  announce_phase(kLoadPhase);
  void* handle = ::dlopen(library.path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    return fmt::format("fails to load: {}", why ? plugin_text(why, 512) : "dlopen failed");
  }
  void* symbol = ::dlsym(handle, NBE_ENTRY_POINT);
  if (!symbol)
    return fmt::format("missing entry points: the library exports no {}()", NBE_ENTRY_POINT);
  nbe_entry_point entry = nullptr;
  std::memcpy(&entry, &symbol, sizeof entry);  // object to function pointer, as POSIX allows
  announce_phase(kEntryPhase);
  const nbe_evaluator* table = entry(NBE_ABI_VERSION);
  announce_phase("reading the table");
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
  // A table of a version up to this header's is at most this header's size: a larger struct_size
  // is a wrong (or hostile) value, not a newer plugin (that has a larger abi_version).
  if (table->struct_size > sizeof(nbe_evaluator))
    return fmt::format(
        "wrong ABI version: struct_size {} is above version {}'s {} bytes for abi_version {}",
        table->struct_size, NBE_ABI_VERSION, sizeof(nbe_evaluator), table->abi_version);
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
                       plugin_text(std::string_view(t.name, strnlen(t.name, 80)), 80));
  return {};
}

// Why each plugin that cannot be used cannot, by strategy name.
std::map<std::string, std::string, std::less<>>& problems() {
  static std::map<std::string, std::string, std::less<>> by_name;
  return by_name;
}

const StrategyEntry& add_plugin(StrategyEntry entry, const Library& library,
                                const fs::path& given) {
  try {
    return add_strategy(std::move(entry), {library.path.string(), library.sha256});
  } catch (const std::invalid_argument& e) {
    throw InputError(
        fmt::format("--plugin = {}: strategy name {}", plugin_text(given.string(), 256), e.what()));
  }
}

// The entry of a plugin that cannot be used: named after its file, every measurement of it a
// `failed` record with `reason` (a broken plugin is the plugin's fault, not a missing device, and
// must not pass a gate by vanishing); `list` says unavailable, with no capabilities.
const StrategyEntry& add_unusable(std::shared_ptr<Library> library, const fs::path& given,
                                  const std::string& problem) {
  StrategyEntry entry;
  entry.role = "plugin";
  entry.name = file_name_of(library->path);
  entry.source = "plugin (unusable)";
  entry.probe = [] { return Availability{true, ""}; };
  entry.capabilities = [] { return Capabilities{}; };
  const std::string reason =
      fmt::format("plugin {}: {}", plugin_text(library->path.string(), 256), problem);
  entry.create = [reason](const StrategyOptions&) -> std::unique_ptr<Strategy> {
    throw std::runtime_error(reason);
  };
  const std::string name = entry.name;
  const StrategyEntry& added = add_plugin(std::move(entry), *library, given);
  problems()[name] = reason;
  return added;
}

// The entry of a usable plugin, from what its table says. Its create() opens the library in the
// calling process first (once): the measurement's child, or this one under --isolation none.
const StrategyEntry& add_usable(std::shared_ptr<Library> library, const fs::path& given,
                                const std::string& name, const std::string& version,
                                const std::string& description, const TableCapabilities& table) {
  StrategyEntry entry;
  entry.role = "plugin";
  entry.name = name;
  entry.source =
      fmt::format("plugin {}{}{}", version, description.empty() ? "" : ": ", description);
  const Capabilities caps = capabilities_of(table);
  entry.probe = [] { return Availability{true, ""}; };
  entry.capabilities = [caps] { return caps; };
  entry.create = [library, name](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
    std::call_once(library->opened, [&] { library->problem = open_library(*library); });
    if (!library->problem.empty())
      throw std::runtime_error(
          fmt::format("plugin {}: {}", plugin_text(library->path.string(), 256), library->problem));
    // The file may have changed since it was probed.
    if (library->table.name != name)
      throw std::runtime_error(fmt::format("plugin {} no longer names strategy {}",
                                           plugin_text(library->path.string(), 256), name));
    return std::make_unique<PluginStrategy>(library, options);
  };
  return add_plugin(std::move(entry), *library, given);
}

// The library a --plugin names, checked to be a readable regular file (a directory, a device or a
// missing file is bad input, said as what it is), with its hash.
std::shared_ptr<Library> library_file(const fs::path& given) {
  std::error_code ec;
  const fs::file_status status = fs::status(given, ec);
  const std::string shown = plugin_text(given.string(), 256);
  // The path goes into the records, the spec a measurement child reads and list --json: JSON
  // holds only valid UTF-8, and a control character would move the terminal.
  if (plugin_text(given.string(), given.string().size() + 1) != given.string())
    throw InputError(fmt::format(
        "--plugin = {}: the path is not valid UTF-8 or holds control characters (rename the file)",
        shown));
  if (!fs::exists(status)) throw InputError(fmt::format("--plugin = {}: no such file", shown));
  if (fs::is_directory(status))
    throw InputError(fmt::format("--plugin = {}: is a directory, not a shared library", shown));
  if (!fs::is_regular_file(status))
    throw InputError(
        fmt::format("--plugin = {}: is not a regular file (a device, a pipe or a socket), not a "
                    "shared library",
                    shown));
  auto library = std::make_shared<Library>();
  library->path = fs::absolute(given).lexically_normal();
  try {
    library->sha256 = file_sha256(library->path);
  } catch (const std::runtime_error&) {
    throw InputError(fmt::format("--plugin = {}: cannot be read", shown));
  }
  return library;
}

// The probe's bound: a library's load and its entry point must be quick (the header says so), and
// `list` waits for them.
constexpr double kProbeTimeoutCap = 60;

}  // namespace

std::string plugin_text(std::string_view bytes, std::size_t max_bytes) {
  std::string out;
  std::size_t k = 0;
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(bytes[i]); };
  while (k < bytes.size()) {
    if (out.size() >= max_bytes) {
      out += "...";
      break;
    }
    const unsigned char c = byte(k);
    if (c < 0x80) {
      if (c == '\n')
        out += "\\n";
      else if (c == '\r')
        out += "\\r";
      else if (c == '\t')
        out += "\\t";
      else if (c < 0x20 || c == 0x7f)
        out += fmt::format("\\x{:02x}", c);
      else
        out += static_cast<char>(c);
      ++k;
      continue;
    }
    // A well-formed UTF-8 sequence (RFC 3629: no overlong forms, no surrogates, at most U+10FFFF)
    // is kept; anything else becomes U+FFFD, one per maximal invalid prefix (Unicode's practice).
    std::size_t length = 0;
    unsigned char low = 0x80, high = 0xbf;
    if (c >= 0xc2 && c <= 0xdf) {
      length = 2;
    } else if (c >= 0xe0 && c <= 0xef) {
      length = 3;
      if (c == 0xe0) low = 0xa0;
      if (c == 0xed) high = 0x9f;
    } else if (c >= 0xf0 && c <= 0xf4) {
      length = 4;
      if (c == 0xf0) low = 0x90;
      if (c == 0xf4) high = 0x8f;
    }
    std::size_t valid = length == 0 ? 0 : 1;
    for (; valid > 0 && valid < length && k + valid < bytes.size(); ++valid) {
      const unsigned char next = byte(k + valid);
      if (next < (valid == 1 ? low : 0x80) || next > (valid == 1 ? high : 0xbf)) break;
    }
    if (length > 0 && valid == length) {
      // C1 controls (U+0080..U+009F) move a terminal as the C0 ones do.
      if (c == 0xc2 && byte(k + 1) < 0xa0)
        out += fmt::format("\\u{:04x}", byte(k + 1));
      else
        out.append(bytes.substr(k, length));
      k += length;
    } else {
      out += "\xef\xbf\xbd";
      k += std::max<std::size_t>(valid, 1);
    }
  }
  return out;
}

std::optional<std::string> plugin_problem(const StrategyEntry& entry) {
  if (!strategy_library(entry)) return std::nullopt;
  const auto it = problems().find(entry.name);
  if (it == problems().end()) return std::nullopt;
  return it->second;
}

int probe_plugin_child(const fs::path& directory) {
  share_phase_board(directory / "phase");
  auto library = std::make_shared<Library>();
  std::ifstream in(directory / "library", std::ios::binary);
  std::ostringstream path;
  path << in.rdbuf();
  library->path = path.str();
  const std::string problem = open_library(*library);
  nlohmann::json answer = {{"problem", problem}};
  if (problem.empty()) {
    const nbe_evaluator& t = library->table;
    answer.update({{"name", t.name},
                   {"version", table_text(t.version, 256)},
                   {"description", table_text(t.description, 1024)},
                   {"capabilities", t.capabilities},
                   {"max_degree", t.max_degree},
                   {"update_control_points", t.update_control_points != nullptr}});
  }
  write_file_atomically(directory / "probe.json", answer.dump());
  return 0;
}

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

const StrategyEntry& load_plugin(const fs::path& given, const IsolationSettings& isolation) {
  std::shared_ptr<Library> library = library_file(given);
  IsolationSettings probe = isolation;
  probe.timeout_s = std::min(isolation.timeout_s, kProbeTimeoutCap);
  IsolationDirectory dir;
  write_file_atomically(dir.path() / "library", library->path.string());
  const std::optional<ChildFailure> failure = run_isolated(probe, ChildTask::probe, dir.path());
  if (failure) {
    const std::string_view what = failure->status == Status::crashed     ? "crashed"
                                  : failure->status == Status::timed_out ? "timed out"
                                                                         : "failed";
    return add_unusable(library, given,
                        fmt::format("{} while it was probed: {}", what, failure->reason));
  }
  const fs::path answer_file = dir.path() / "probe.json";
  if (!fs::exists(answer_file)) {
    // Exit status 0 without an answer: the library ended the process itself (exit() in a
    // constructor or the entry point).
    const std::string phase = read_phase_board(dir.path() / "phase");
    return add_unusable(library, given,
                        fmt::format("the probe's process exited with status 0 in {} before it "
                                    "answered (the library called exit?)",
                                    phase.empty() ? "its start" : phase));
  }
  // The answer was written in a process the library ran in: read as untrusted as the library.
  std::string problem, name, version, description;
  TableCapabilities table;
  try {
    const nlohmann::json answer = nlohmann::json::parse(read_whole_file(answer_file));
    problem = answer.at("problem");
    if (problem.empty()) {
      name = answer.at("name");
      version = plugin_text(answer.at("version").get<std::string>(), 256);
      description = plugin_text(answer.at("description").get<std::string>(), 1024);
      table = {answer.at("capabilities"), answer.at("max_degree"),
               answer.at("update_control_points")};
    }
  } catch (const std::exception& e) {
    problem = plugin_text(fmt::format("the probe's answer cannot be read: {}", e.what()), 512);
  }
  if (problem.empty() && !valid_name(name.c_str()))
    problem =
        fmt::format("invalid name '{}' (1..64 characters of a-z 0-9 . _ -)", plugin_text(name, 80));
  if (!problem.empty()) return add_unusable(library, given, plugin_text(problem, 1024));
  return add_usable(library, given, name, version, description, table);
}

void load_plugins(const std::vector<std::string>& paths, const IsolationSettings& isolation) {
  for (const std::string& path : paths) load_plugin(path, isolation);
}

const StrategyEntry& load_plugin_in_process(const fs::path& given) {
  std::shared_ptr<Library> library = library_file(given);
  std::call_once(library->opened, [&] { library->problem = open_library(*library); });
  if (!library->problem.empty()) return add_unusable(library, given, library->problem);
  const nbe_evaluator& t = library->table;
  return add_usable(library, given, t.name, table_text(t.version, 256),
                    table_text(t.description, 1024), table_capabilities(t));
}

}  // namespace nurbs
