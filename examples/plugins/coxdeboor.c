/* A nurbsbench evaluator plugin in plain C99: Cox-de Boor evaluation of rational tensor-product
 * NURBS surfaces (Piegl & Tiller, The NURBS Book: A2.1 span search, A2.2 basis functions, then the
 * homogeneous sum and the divide), in double, rounded to float for f32 requests.
 * Everything it relies on is in nurbsbench/evaluator.h.
 *
 *   cmake -S examples/plugins -B build-plugins -DCMAKE_PREFIX_PATH=<nurbsbench prefix>
 *   cmake --build build-plugins
 *   nurbsbench run --plugin build-plugins/libcoxdeboor_plugin.so --strategies c-coxdeboor
 */
#include <nurbsbench/evaluator.h>
#include <stdio.h>
#include <stdlib.h>

#define MAX_ORDER 16 /* degree 15, the harness's limit, + 1 */

/* The prepared request: the harness keeps these alive until the next prepare() or release(). */
typedef struct instance {
  const nbe_scene* scene;
  const nbe_request* request;
  const nbe_samples* samples;
} instance;

/* A2.1: the span s with knots[s] <= t < knots[s + 1], in [degree, count - 1]; the domain's end
 * belongs to the last non-empty span. */
static uint32_t find_span(uint32_t count, uint32_t degree, double t, const double* knots) {
  uint32_t low = degree, high = count, mid;
  if (t >= knots[count]) {
    mid = count - 1;
    while (mid > degree && knots[mid] == knots[count]) --mid;
    return mid;
  }
  if (t <= knots[degree]) return degree;
  mid = (low + high) / 2;
  while (t < knots[mid] || t >= knots[mid + 1]) {
    if (t < knots[mid])
      high = mid;
    else
      low = mid;
    mid = (low + high) / 2;
  }
  return mid;
}

/* A2.2: the degree + 1 non-zero basis functions at t in span s. */
static void basis(uint32_t s, double t, uint32_t degree, const double* knots, double* n) {
  double left[MAX_ORDER], right[MAX_ORDER];
  uint32_t j, r;
  n[0] = 1.0;
  for (j = 1; j <= degree; ++j) {
    double saved = 0.0;
    left[j] = t - knots[s + 1 - j];
    right[j] = knots[s + j] - t;
    for (r = 0; r < j; ++r) {
      const double temp = n[r] / (right[r + 1] + left[j - r]);
      n[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    n[j] = saved;
  }
}

/* S(u, v) = sum N_i(u) N_j(v) w_ij P_ij / sum N_i(u) N_j(v) w_ij, from the homogeneous points. */
static void evaluate_point(const nbe_surface* s, double u, double v, double out[3]) {
  double nu[MAX_ORDER], nv[MAX_ORDER], h[4] = {0, 0, 0, 0};
  const uint32_t su = find_span(s->count_u, s->degree_u, u, s->knots_u);
  const uint32_t sv = find_span(s->count_v, s->degree_v, v, s->knots_v);
  uint32_t a, b, c;
  basis(su, u, s->degree_u, s->knots_u, nu);
  basis(sv, v, s->degree_v, s->knots_v, nv);
  for (a = 0; a <= s->degree_u; ++a)
    for (b = 0; b <= s->degree_v; ++b) {
      const size_t k = (size_t)(su - s->degree_u + a) * s->count_v + (sv - s->degree_v + b);
      for (c = 0; c < 4; ++c) h[c] += nu[a] * nv[b] * s->homogeneous[4 * k + c];
    }
  for (c = 0; c < 3; ++c) out[c] = h[c] / h[3];
}

static void* create(const nbe_options* options, nbe_error* error) {
  instance* self = calloc(1, sizeof *self);
  (void)options; /* single-threaded: --threads does not concern it */
  if (!self) snprintf(error->message, sizeof error->message, "out of memory");
  return self;
}

static int32_t prepare(void* handle, const nbe_scene* scene, const nbe_request* request,
                       const nbe_samples* samples, nbe_error* error) {
  instance* self = handle;
  uint32_t i;
  for (i = 0; i < scene->surface_count; ++i)
    if (scene->surfaces[i].kind != NBE_SURFACE_NURBS) {
      snprintf(error->message, sizeof error->message, "surface %u is not NURBS", i);
      return NBE_UNSUPPORTED;
    }
  /* Nothing to build: evaluate() reads the harness's arrays in place. */
  self->scene = scene;
  self->request = request;
  self->samples = samples;
  return NBE_OK;
}

static int32_t evaluate(void* handle, nbe_surface_output* outputs, nbe_error* error) {
  const instance* self = handle;
  uint32_t i;
  (void)error;
  for (i = 0; i < self->scene->surface_count; ++i) {
    const nbe_surface* s = &self->scene->surfaces[i];
    const nbe_samples* p = &self->samples[i];
    nbe_surface_output* out = &outputs[i];
    size_t k;
    for (k = 0; k < p->count; ++k) {
      const double u = p->tensor ? p->u[k / p->v_count] : p->u[k];
      const double v = p->tensor ? p->v[k % p->v_count] : p->v[k];
      double x[3];
      int c;
      evaluate_point(s, u, v, x);
      for (c = 0; c < 3; ++c) {
        if (self->request->precision == NBE_F32)
          ((float*)out->positions)[3 * k + c] = (float)x[c];
        else
          ((double*)out->positions)[3 * k + c] = x[c];
      }
    }
    out->written = p->count;
  }
  return NBE_OK;
}

static void release(void* handle) {
  free(handle);
}

static const nbe_evaluator table = {
    NBE_ABI_VERSION,
    sizeof(nbe_evaluator),
    "c-coxdeboor",
    "1.0",
    "plain C Cox-de Boor (P&T A2.1/A2.2), double, positions only (examples/plugins)",
    NBE_CAP_F32 | NBE_CAP_F64 | NBE_CAP_RATIONAL | NBE_CAP_GRID | NBE_CAP_SPAN_GRID |
        NBE_CAP_EXPLICIT,
    15,
    create,
    prepare,
    evaluate,
    NULL, /* update_control_points: prepare() is cheap enough */
    release,
};

NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator(uint32_t harness_abi_version) {
  (void)harness_abi_version; /* version 1 is the first: every harness that calls this has it */
  return &table;
}
