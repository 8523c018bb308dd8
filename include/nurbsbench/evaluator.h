/* nurbsbench evaluator plugins: the whole contract, in C99.
 *
 * A plugin is a shared library (.so) that exports ONE function, NBE_ENTRY_POINT below, returning a
 * table of functions (nbe_evaluator). The harness loads it with `--plugin PATH.so` on `nurbsbench
 * run`, `eval`, `recommend` and `list`; the table's `name` becomes a strategy name (refused when
 * it is already a built-in strategy's), measured and checked against the extended-precision
 * reference like every built-in strategy, each measurement in its own child process.
 *
 * Life of an instance (one line per call, in this order):
 *   create(options)                 -> instance           (the "setup" phase, with the first
 * prepare) prepare(instance, scene, request, samples)            (again for every upload that is
 * timed) evaluate(instance, outputs)      repeated, timed      (writes into the harness's buffers)
 *   update_control_points(instance, scene)   optional     (deforming surfaces: moved points only)
 *   release(instance)                                     (always, unless the process died)
 *
 * Return values: every function that can fail returns NBE_OK (0) or an nbe_status code and, on
 * failure, writes a one-line reason into the harness's nbe_error (the error channel). The harness
 * records NBE_UNSUPPORTED as `refused` (this request is outside what the plugin does) and every
 * other code as `failed`, with the code and the message.
 *
 * Ownership: everything the harness passes (scene, request, samples, output buffers, options,
 * the nbe_error) is owned by the harness. Scene, request and samples given to prepare() stay
 * valid and unchanged until the next prepare(), update_control_points() or release() of that
 * instance, so a plugin may keep pointers instead of copying. A scene given to
 * update_control_points() has the same shape as the prepared one (same surfaces, counts, knots,
 * trims); only points, homogeneous points and weights differ; it replaces the prepared scene
 * until the next such call. Output buffers are valid only during the evaluate() call that
 * receives them. What the plugin allocates (the instance and anything behind it) is the plugin's
 * and is freed in release(). Strings in the table (name, version, description) are static: they
 * must stay valid as long as the library is loaded.
 *
 * Alignment: every array the harness passes (points, knots, samples, output buffers) starts on
 * a 64-byte boundary or is a sub-range of one that does; doubles and floats are the host's IEEE
 * binary64 / binary32, native byte order.
 *
 * Threads and re-entrancy: the harness calls one instance from one thread at a time and never
 * re-enters a plugin from inside one of its calls. It may create several instances in one process
 * one after another (and, with --isolation none, keep none alive between measurements); the entry
 * point and the table may be read from any thread. A plugin may use threads of its own inside a
 * call (OpenMP, a thread pool); none of its work may still touch output buffers once evaluate()
 * has returned, and evaluate() returns when the results are in the buffers (a GPU plugin waits
 * for its device: the harness times the call).
 *
 * Versioning: NBE_ABI_VERSION is the version of this header. The plugin puts the version it was
 * built against in nbe_evaluator.abi_version and its sizeof(nbe_evaluator) in struct_size. A
 * harness loads a plugin whose abi_version is between 1 and its own NBE_ABI_VERSION (a newer
 * harness loads older plugins: later versions only append fields to the structs below, and
 * struct_size says which of them the plugin has) and refuses any other, with "wrong ABI
 * version". The entry point receives the harness's own version, so a plugin built for a newer
 * header may return a table for an older one (or NULL to say it cannot).
 *
 * What the harness checks (each failure is a record status with a one-line reason): the library
 * loads (dlopen), exports the entry point, the table is not NULL, has a name and create, prepare,
 * evaluate and release; abi_version is supported; every call returns NBE_OK; evaluate() reports
 * exactly `count` points written for every surface; every coordinate is finite (NaN or Inf fails
 * the record); and the results are within the gates `nurbsbench check` is given. A crash or a
 * hang costs only the measurement's child process (`crashed`, `timed_out` after --timeout).
 * The library is never loaded into the harness's own process (unless the user asks for
 * --isolation none): its name and capabilities are read by a probe, a child process that loads it,
 * calls the entry point and reports the table, under the same watchdog; a constructor or entry
 * point that crashes, hangs or exits makes the plugin unusable, with that reason. Strings the
 * plugin returns (name, version, description, error messages) may hold any bytes: the harness
 * makes them valid UTF-8 and one printable line before they reach a record. struct_size must be
 * at least version 1's size and at most sizeof(nbe_evaluator) of the harness's header.
 */
#ifndef NURBSBENCH_EVALUATOR_H
#define NURBSBENCH_EVALUATOR_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NBE_ABI_VERSION 1u

/* The one symbol the harness looks up. Declare it with NBE_EXPORT in the plugin:
 *   NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator(uint32_t harness_abi_version) { ... } */
#define NBE_ENTRY_POINT "nurbsbench_evaluator"
#if defined(_WIN32)
#define NBE_EXPORT __declspec(dllexport)
#else
#define NBE_EXPORT __attribute__((visibility("default")))
#endif

/* ------------------------------------------------------------------------ status and errors */

typedef enum nbe_status {
  NBE_OK = 0,
  NBE_ERROR = 1,       /* anything else: the message says what */
  NBE_UNSUPPORTED = 2, /* this request is outside what the plugin does: recorded `refused` */
  NBE_OUT_OF_MEMORY = 3,
  NBE_INVALID_ARGUMENT = 4 /* the harness passed something the plugin cannot read */
} nbe_status;

#define NBE_ERROR_MESSAGE_SIZE 512
/* Harness-owned, zeroed before every call. On failure the plugin sets `code` (optional: the
 * return value is what counts) and writes a NUL-terminated one-line message, truncated to fit. */
typedef struct nbe_error {
  int32_t code;
  char message[NBE_ERROR_MESSAGE_SIZE];
} nbe_error;

/* ------------------------------------------------------------------------------ capabilities */

/* Bits of nbe_evaluator.capabilities. The harness refuses (status `refused`, never calls the
 * plugin) a request whose precision, sampling, normals or surfaces the bits do not cover, and a
 * degree above max_degree. */
#define NBE_CAP_F32 (1u << 0)       /* single-precision output */
#define NBE_CAP_F64 (1u << 1)       /* double-precision output */
#define NBE_CAP_NORMALS (1u << 2)   /* unit normals, (S_u x S_v) / |S_u x S_v| */
#define NBE_CAP_RATIONAL (1u << 3)  /* weights other than 1 */
#define NBE_CAP_GRID (1u << 4)      /* NBE_SAMPLING_GRID */
#define NBE_CAP_SPAN_GRID (1u << 5) /* NBE_SAMPLING_SPAN_GRID */
#define NBE_CAP_EXPLICIT (1u << 6)  /* NBE_SAMPLING_EXPLICIT */
/* Classifies samples against the trimming loops: fills nbe_surface_output.inside. Without it,
 * trimmed scenes are still evaluated (the whole surface) and recorded "untrimmed". */
#define NBE_CAP_TRIMS (1u << 7)
#define NBE_CAP_TSPLINES (1u << 8)      /* evaluates NBE_SURFACE_TSPLINE surfaces */
#define NBE_CAP_TSPLINES_ONLY (1u << 9) /* ... and nothing else (NURBS scenes are refused) */
/* update_control_points() is implemented; without it the harness calls prepare() again for every
 * deforming frame and records that phase as "frame_prepare". */
#define NBE_CAP_UPDATES_CONTROL_POINTS (1u << 10)
#define NBE_CAP_GPU (1u << 11) /* runs on a GPU (records say kind "gpu"; else "cpu") */

/* ---------------------------------------------------------------------------------- the scene */

/* A 2D NURBS curve in its surface's (u, v) space. knots: point_count + degree + 1, the curve is
 * [knots[degree], knots[point_count]]; points: point_count (u, v) pairs, Cartesian (not
 * multiplied by the weight); weights: point_count, all 1 when the file gave none. */
typedef struct nbe_trim_curve {
  uint32_t degree;
  uint32_t point_count;
  const double* knots;
  const double* points;
  const double* weights;
} nbe_trim_curve;

/* Curves in order, each one's end meeting the next one's start (and the last the first) within
 * nbe_surface.trim_tolerance. */
typedef struct nbe_trim_loop {
  uint32_t curve_count;
  const nbe_trim_curve* curves;
} nbe_trim_loop;

typedef enum nbe_surface_kind { NBE_SURFACE_NURBS = 0, NBE_SURFACE_TSPLINE = 1 } nbe_surface_kind;

/* One surface, as plain arrays.
 *
 * NBE_SURFACE_NURBS: a tensor-product net of count_u x count_v control points (point_count =
 * count_u * count_v), point (i, j) at index i * count_v + j (i along u). knots_u has count_u +
 * degree_u + 1 entries, knots_v count_v + degree_v + 1, non-decreasing; clamped or not. The
 * domain [u_min, u_max] x [v_min, v_max] is [knots_u[degree_u], knots_u[count_u]] x (likewise v).
 *
 * NBE_SURFACE_TSPLINE: the point-based form (Sederberg et al. 2003): point_count control points
 * with weights, point k with its own local knot vectors knots_u[k * (degree_u + 2) ...
 * + degree_u + 1] and knots_v[k * (degree_v + 2) ...]; count_u = count_v = 0; degrees odd;
 *   S(u, v) = sum_k w_k P_k N[u_k](u) N[v_k](v) / sum_k w_k N[u_k](u) N[v_k](v).
 * The domain is stored (a point-based spline does not imply one).
 *
 * Points three ways, the same numbers: `points` Cartesian (x, y, z) per point, `weights` one per
 * point (all 1 when not rational), `homogeneous` (w x, w y, w z, w) per point. */
typedef struct nbe_surface {
  uint32_t kind; /* nbe_surface_kind */
  uint32_t degree_u, degree_v;
  uint32_t count_u, count_v;
  uint32_t point_count;
  const double* knots_u;
  const double* knots_v;
  const double* points;      /* point_count * 3 */
  const double* weights;     /* point_count */
  const double* homogeneous; /* point_count * 4 */
  double u_min, u_max, v_min, v_max;
  uint32_t rational; /* 1 when some weight differs from 1 */
  /* 1 when the face is reversed: the harness flips the normals the plugin returns; the plugin
   * returns S_u x S_v normals regardless. */
  uint32_t reversed;
  /* Trimming loops (NURBS only; none: 0 and NULL): a sample is inside when a ray from it crosses
   * the loops an odd number of times (even-odd; loops may run either way, holes nest). */
  uint32_t trim_loop_count;
  const nbe_trim_loop* trim_loops;
  double trim_tolerance;
} nbe_surface;

typedef struct nbe_scene {
  const char* name;
  uint32_t surface_count;
  const nbe_surface* surfaces;
} nbe_scene;

/* ----------------------------------------------------------------------- request and samples */

typedef enum nbe_precision { NBE_F32 = 1, NBE_F64 = 2 } nbe_precision;
typedef enum nbe_sampling {
  NBE_SAMPLING_GRID = 0,      /* grid_u x grid_v samples over the domain, ends included */
  NBE_SAMPLING_SPAN_GRID = 1, /* every non-empty knot span split into span_steps steps */
  NBE_SAMPLING_EXPLICIT = 2   /* a list of (u, v) per surface */
} nbe_sampling;

typedef struct nbe_request {
  uint32_t precision;      /* nbe_precision: the type of the output buffers */
  uint32_t normals;        /* 1: fill nbe_surface_output.normals */
  uint32_t sampling;       /* nbe_sampling, for plugins that generate their own parameters */
  uint32_t grid_u, grid_v; /* NBE_SAMPLING_GRID */
  uint32_t span_steps;     /* NBE_SAMPLING_SPAN_GRID */
} nbe_request;

/* Where one surface is evaluated, computed by the harness (a plugin need not recompute it, and
 * results are compared with the reference at exactly these parameters).
 * tensor = 1 (grid, span grid): sample (a, b) = (u[a], v[b]) at index a * v_count + b;
 *   count = u_count * v_count.
 * tensor = 0 (explicit): sample k = (u[k], v[k]); u_count = v_count = count. */
typedef struct nbe_samples {
  uint32_t tensor;
  size_t u_count, v_count;
  const double* u;
  const double* v;
  size_t count;
} nbe_samples;

/* ------------------------------------------------------------------------------------ output */

/* Harness-owned buffers for one surface. positions: count * 3 floats (NBE_F32) or doubles
 * (NBE_F64), (x, y, z) per sample in sample order; normals: the same shape, NULL unless the
 * request asked for normals; inside: count bytes (1 inside the trimmed face, 0 outside), NULL
 * unless the plugin has NBE_CAP_TRIMS and the surface has trim loops. The plugin sets `written`
 * to the number of samples it wrote; anything but `count` fails the record ("wrong output
 * count"). */
typedef struct nbe_surface_output {
  size_t count;
  void* positions;
  void* normals;
  uint8_t* inside;
  size_t written;
} nbe_surface_output;

/* ---------------------------------------------------------------------------- create options */

typedef struct nbe_option {
  const char* key;
  const char* value;
} nbe_option;

typedef struct nbe_options {
  int32_t threads; /* --threads: 0 = every core; a single-threaded plugin ignores it */
  /* --strategy-option KEY=VALUE pairs, every one the user gave (each plugin reads what it knows) */
  uint32_t option_count;
  const nbe_option* options;
} nbe_options;

/* ------------------------------------------------------------------------- the function table */

typedef struct nbe_evaluator {
  uint32_t abi_version; /* NBE_ABI_VERSION as the plugin was built */
  uint32_t struct_size; /* sizeof(nbe_evaluator) as the plugin was built */

  /* Identity. name: the strategy name, [a-z0-9._-], 1..64 characters, not a built-in's. */
  const char* name;
  const char* version;     /* the plugin's own version, free form */
  const char* description; /* one line: what it does (shown by `nurbsbench list`) */

  uint32_t capabilities; /* NBE_CAP_* bits */
  uint32_t max_degree;   /* highest degree in u or v (0: 15, the harness's limit) */

  /* Returns a new instance, or NULL with `error` filled. */
  void* (*create)(const nbe_options* options, nbe_error* error);
  /* Uploads the scene for this request (build tables, copy to a device...). samples: one per
   * surface, in scene order. Called again before every timed upload: it must replace, not add. */
  int32_t (*prepare)(void* instance, const nbe_scene* scene, const nbe_request* request,
                     const nbe_samples* samples, nbe_error* error);
  /* Evaluates the prepared request into outputs[0 .. scene->surface_count - 1]; only this is
   * timed as the evaluate phase. */
  int32_t (*evaluate)(void* instance, nbe_surface_output* outputs, nbe_error* error);
  /* Optional (NULL: not offered): re-sends only the control points of the prepared scene. */
  int32_t (*update_control_points)(void* instance, const nbe_scene* scene, nbe_error* error);
  /* Frees the instance; NULL is never passed. */
  void (*release)(void* instance);
} nbe_evaluator;

/* The entry point's type; the plugin exports a function of this type named NBE_ENTRY_POINT. It
 * returns the plugin's table (static storage), or NULL when it cannot serve a harness of
 * harness_abi_version. It must not fail otherwise, allocate per call or do slow work: `list` calls
 * it (in the probe's child, bounded by --timeout, at most 60 s). */
typedef const nbe_evaluator* (*nbe_entry_point)(uint32_t harness_abi_version);

#ifdef __cplusplus
}
#endif

#endif /* NURBSBENCH_EVALUATOR_H */
