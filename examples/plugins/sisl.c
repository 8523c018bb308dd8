/* A nurbsbench evaluator plugin wrapping SINTEF SISL (Debian libsisl-dev), the same calls as the
 * built-in peer strategy `sisl` (strategies/sisl/): grids and span grids through s1506, explicit
 * lists per sample through s1424, in double, rounded to float for f32 requests. Its positions
 * equal the built-in's bit for bit (tests/plugins/plugins_test.sh compares `nurbsbench eval`
 * of both). Positions only: the built-in's normals add the project's limit rule where SISL's
 * S_u x S_v vanishes, which this example leaves out.
 *
 * SISL's first parameter direction is our v and its second our u: with the harness's point order
 * (i * count_v + j) and sample order (a * v_count + b) that needs no transposition. */
#include <nurbsbench/evaluator.h>
#include <sisl.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct instance {
  const nbe_request* request;
  const nbe_samples* samples;
  uint32_t count;
  SISLSurf** surfaces;
  double* scratch; /* s1506 / s1424 results in double, for f32 requests */
  size_t scratch_size;
} instance;

/* Debian's static libsisl.a has one object that is not position-independent: s6err.c.o, SISL's
 * error printer (it writes to stderr), which a shared library cannot link. Defining the function
 * here keeps the archive's copy out; SISL's negative status codes, which evaluate() reports, still
 * say what went wrong. */
void s6err(char* routine, int status, int position);
void s6err(char* routine, int status, int position) {
  (void)routine, (void)status, (void)position;
}

static void free_surfaces(instance* self) {
  uint32_t i;
  for (i = 0; i < self->count; ++i) freeSurf(self->surfaces[i]);
  free(self->surfaces);
  self->surfaces = NULL;
  self->count = 0;
}

static void* create(const nbe_options* options, nbe_error* error) {
  instance* self = calloc(1, sizeof *self);
  (void)options;
  if (!self) snprintf(error->message, sizeof error->message, "out of memory");
  return self;
}

static int32_t prepare(void* handle, const nbe_scene* scene, const nbe_request* request,
                       const nbe_samples* samples, nbe_error* error) {
  instance* self = handle;
  uint32_t i;
  size_t largest = 0;
  free_surfaces(self);
  self->surfaces = calloc(scene->surface_count, sizeof *self->surfaces);
  if (!self->surfaces) return NBE_OUT_OF_MEMORY;
  for (i = 0; i < scene->surface_count; ++i) {
    const nbe_surface* s = &scene->surfaces[i];
    if (s->kind != NBE_SURFACE_NURBS) {
      snprintf(error->message, sizeof error->message, "surface %u is not NURBS", i);
      return NBE_UNSUPPORTED;
    }
    /* kind 2: rational, homogeneous coefficients (w x, w y, w z, w); copy flag 1: SISL copies,
     * so the harness's const arrays are never written. */
    self->surfaces[i] =
        newSurf((int)s->count_v, (int)s->count_u, (int)s->degree_v + 1, (int)s->degree_u + 1,
                (double*)s->knots_v, (double*)s->knots_u, (double*)s->homogeneous, 2, 3, 1);
    if (!self->surfaces[i]) {
      snprintf(error->message, sizeof error->message, "SISL newSurf failed on surface %u", i);
      return NBE_ERROR;
    }
    self->count = i + 1;
    if (samples[i].count > largest) largest = samples[i].count;
  }
  free(self->scratch);
  self->scratch_size = 3 * largest;
  self->scratch = malloc((self->scratch_size ? self->scratch_size : 1) * sizeof(double));
  if (!self->scratch) return NBE_OUT_OF_MEMORY;
  self->request = request;
  self->samples = samples;
  return NBE_OK;
}

static int32_t evaluate(void* handle, nbe_surface_output* outputs, nbe_error* error) {
  instance* self = handle;
  uint32_t i;
  for (i = 0; i < self->count; ++i) {
    const nbe_samples* p = &self->samples[i];
    const int f64 = self->request->precision == NBE_F64;
    double* points = f64 ? (double*)outputs[i].positions : self->scratch;
    double unused_normal[3];
    int status = 0;
    size_t k;
    if (p->tensor) {
      s1506(self->surfaces[i], 0, (int)p->v_count, (double*)p->v, (int)p->u_count, (double*)p->u,
            points, unused_normal, &status);
    } else {
      for (k = 0; k < p->count && status >= 0; ++k) {
        double par[2], der[3];
        int left1 = 0, left2 = 0, c;
        par[0] = p->v[k];
        par[1] = p->u[k];
        s1424(self->surfaces[i], 0, 0, par, &left1, &left2, der, &status);
        for (c = 0; c < 3; ++c) points[3 * k + c] = der[c];
      }
    }
    if (status < 0) {
      snprintf(error->message, sizeof error->message, "SISL failed on surface %u: status %d", i,
               status);
      return NBE_ERROR;
    }
    if (!f64)
      for (k = 0; k < 3 * p->count; ++k) ((float*)outputs[i].positions)[k] = (float)points[k];
    outputs[i].written = p->count;
  }
  return NBE_OK;
}

static void release(void* handle) {
  instance* self = handle;
  free_surfaces(self);
  free(self->scratch);
  free(self);
}

static const nbe_evaluator table = {
    NBE_ABI_VERSION,
    sizeof(nbe_evaluator),
    "sisl-plugin",
    "1.0",
    "SINTEF SISL s1506 grids / s1424 lists, as the built-in sisl peer (examples/plugins)",
    NBE_CAP_F32 | NBE_CAP_F64 | NBE_CAP_RATIONAL | NBE_CAP_GRID | NBE_CAP_SPAN_GRID |
        NBE_CAP_EXPLICIT,
    15,
    create,
    prepare,
    evaluate,
    NULL,
    release,
};

NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator(uint32_t harness_abi_version) {
  (void)harness_abi_version;
  return &table;
}
