// A test plugin that evaluates nothing: it writes back a digest of what the harness handed it, so
// plugin_test can check the adapter's marshalling (harness/plugins/plugin.cpp) against the Scene
// it started from. Written in C++ against the C header (which is also C++-clean); built as a
// MODULE only for plugin_test.
//   position k = (u_k, v_k, checksum of the surface's arrays, in the order digest() sums them)
//   normal k   = (point_count + 1e3 count_u + 1e6 count_v,
//                 kind + 10 degree_u + 100 degree_v + 1e3 reversed + 1e4 rational,
//                 loops + 1e2 curves + 1e4 trim points)   (only when asked for)
//   inside k   = 1 when every array it was given starts on a 64-byte boundary (the header's
//                promise), else 0                          (only for trimmed surfaces)
// Options: fail=create|prepare|evaluate makes that call fail (prepare: NBE_UNSUPPORTED).
#include <nurbsbench/evaluator.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace {

struct Echo {
  std::string fail;
  const nbe_scene* scene = nullptr;
  const nbe_request* request = nullptr;
  const nbe_samples* samples = nullptr;
};

bool aligned(const void* p) {
  return reinterpret_cast<std::uintptr_t>(p) % 64 == 0;
}

double sum(const double* values, std::size_t n) {
  double s = 0;
  for (std::size_t k = 0; k < n; ++k) s += values[k];
  return s;
}

double digest(const nbe_surface& s, bool& all_aligned) {
  const bool tspline = s.kind == NBE_SURFACE_TSPLINE;
  const std::size_t ku = tspline ? s.point_count * (s.degree_u + 2) : s.count_u + s.degree_u + 1;
  const std::size_t kv = tspline ? s.point_count * (s.degree_v + 2) : s.count_v + s.degree_v + 1;
  double d = sum(s.knots_u, ku) + sum(s.knots_v, kv) + sum(s.points, 3 * s.point_count) +
             sum(s.weights, s.point_count) + sum(s.homogeneous, 4 * s.point_count);
  d += s.u_min + s.u_max + s.v_min + s.v_max + s.trim_tolerance;
  all_aligned = aligned(s.knots_u) && aligned(s.knots_v) && aligned(s.points) &&
                aligned(s.weights) && aligned(s.homogeneous);
  for (std::uint32_t l = 0; l < s.trim_loop_count; ++l)
    for (std::uint32_t c = 0; c < s.trim_loops[l].curve_count; ++c) {
      const nbe_trim_curve& t = s.trim_loops[l].curves[c];
      d += sum(t.knots, t.point_count + t.degree + 1) + sum(t.points, 2 * t.point_count) +
           sum(t.weights, t.point_count);
      all_aligned = all_aligned && aligned(t.knots) && aligned(t.points) && aligned(t.weights);
    }
  return d;
}

std::int32_t failure(nbe_error* error, std::int32_t code, const char* where) {
  std::snprintf(error->message, sizeof error->message, "echo asked to fail in %s", where);
  error->code = code;
  return code;
}

void* create(const nbe_options* options, nbe_error* error) {
  Echo* echo = new Echo;
  for (std::uint32_t k = 0; k < options->option_count; ++k)
    if (std::strcmp(options->options[k].key, "fail") == 0) echo->fail = options->options[k].value;
  if (echo->fail == "create") {
    delete echo;
    failure(error, NBE_ERROR, "create");
    return nullptr;
  }
  return echo;
}

std::int32_t prepare(void* self, const nbe_scene* scene, const nbe_request* request,
                     const nbe_samples* samples, nbe_error* error) {
  Echo* echo = static_cast<Echo*>(self);
  if (echo->fail == "prepare") return failure(error, NBE_UNSUPPORTED, "prepare");
  echo->scene = scene;
  echo->request = request;
  echo->samples = samples;
  return NBE_OK;
}

std::int32_t update(void* self, const nbe_scene* scene, nbe_error*) {
  static_cast<Echo*>(self)->scene = scene;
  return NBE_OK;
}

template <typename T>
void write(nbe_surface_output& out, std::size_t k, const double p[3], const double n[3],
           std::uint8_t inside) {
  for (int c = 0; c < 3; ++c) {
    static_cast<T*>(out.positions)[3 * k + c] = static_cast<T>(p[c]);
    if (out.normals) static_cast<T*>(out.normals)[3 * k + c] = static_cast<T>(n[c]);
  }
  if (out.inside) out.inside[k] = inside;
}

std::int32_t evaluate(void* self, nbe_surface_output* outputs, nbe_error* error) {
  const Echo* echo = static_cast<const Echo*>(self);
  if (echo->fail == "evaluate") return failure(error, NBE_ERROR, "evaluate");
  for (std::uint32_t i = 0; i < echo->scene->surface_count; ++i) {
    const nbe_surface& s = echo->scene->surfaces[i];
    const nbe_samples& p = echo->samples[i];
    nbe_surface_output& out = outputs[i];
    bool all_aligned = false;
    const double d = digest(s, all_aligned);
    all_aligned = all_aligned && aligned(p.u) && aligned(p.v) && aligned(out.positions) &&
                  (!out.normals || aligned(out.normals)) && (!out.inside || aligned(out.inside));
    double curves = 0, trim_points = 0;
    for (std::uint32_t l = 0; l < s.trim_loop_count; ++l) {
      curves += s.trim_loops[l].curve_count;
      for (std::uint32_t c = 0; c < s.trim_loops[l].curve_count; ++c)
        trim_points += s.trim_loops[l].curves[c].point_count;
    }
    const double n[3] = {
        s.point_count + 1e3 * s.count_u + 1e6 * s.count_v,
        s.kind + 10.0 * s.degree_u + 100.0 * s.degree_v + 1e3 * s.reversed + 1e4 * s.rational,
        s.trim_loop_count + 1e2 * curves + 1e4 * trim_points};
    for (std::size_t k = 0; k < p.count; ++k) {
      const double q[3] = {p.tensor ? p.u[k / p.v_count] : p.u[k],
                           p.tensor ? p.v[k % p.v_count] : p.v[k], d};
      if (echo->request->precision == NBE_F32)
        write<float>(out, k, q, n, all_aligned ? 1 : 0);
      else
        write<double>(out, k, q, n, all_aligned ? 1 : 0);
    }
    out.written = p.count;
  }
  return NBE_OK;
}

void release(void* self) {
  delete static_cast<Echo*>(self);
}

const nbe_evaluator table = {
    NBE_ABI_VERSION,
    sizeof(nbe_evaluator),
    "echo",
    "1",
    "echoes what the harness passed (tests/harness/plugin_test)",
    NBE_CAP_F32 | NBE_CAP_F64 | NBE_CAP_NORMALS | NBE_CAP_RATIONAL | NBE_CAP_GRID |
        NBE_CAP_SPAN_GRID | NBE_CAP_EXPLICIT | NBE_CAP_TRIMS | NBE_CAP_TSPLINES |
        NBE_CAP_UPDATES_CONTROL_POINTS,
    0,
    create,
    prepare,
    evaluate,
    update,
    release,
};

}  // namespace

extern "C" NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator(std::uint32_t) {
  return &table;
}
