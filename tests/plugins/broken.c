/* A deliberately broken evaluator plugin, built once per misbehaviour (one BROKEN_<MODE> macro,
 * name "broken-<mode>"), so that tests/plugins/plugins_test.sh can show the harness gives each its
 * own status and reason while every other record of the same run stays ok:
 *   CRASH    evaluate() raises SIGSEGV              -> crashed
 *   HANG     evaluate() never returns               -> timed_out
 *   NAN      evaluate() writes NaN                  -> failed (non-finite output)
 *   SHORT    evaluate() writes one sample too few   -> failed (wrong output count)
 *   ERROR    evaluate() returns NBE_ERROR           -> failed (error returned, with its message)
 *   VERSION  the table says ABI version 99          -> failed (wrong ABI version)
 *   NOENTRY  no nurbsbench_evaluator symbol         -> failed (missing entry points)
 *   NULLFN   the table has no evaluate()            -> failed (missing entry points)
 * Not an example to copy: examples/plugins/ has those. */
#include <math.h>
#include <nurbsbench/evaluator.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static int32_t prepare(void* self, const nbe_scene* scene, const nbe_request* request,
                       const nbe_samples* samples, nbe_error* error) {
  (void)self, (void)scene, (void)request, (void)samples, (void)error;
  return NBE_OK;
}

static int32_t evaluate(void* self, nbe_surface_output* outputs, nbe_error* error) {
  size_t k;
  (void)self, (void)error, (void)k;
#if defined(BROKEN_CRASH)
  signal(SIGSEGV, SIG_DFL);
  raise(SIGSEGV);
#elif defined(BROKEN_HANG)
  for (;;) pause();
#elif defined(BROKEN_ERROR)
  snprintf(error->message, sizeof error->message, "the broken plugin's deliberate error");
  return NBE_ERROR;
#endif
  /* One surface is enough for the test's scene; the others are left unwritten (and reported). */
  for (k = 0; k < 3 * outputs[0].count; ++k) ((float*)outputs[0].positions)[k] = (float)NAN;
  outputs[0].written = outputs[0].count;
#if defined(BROKEN_SHORT)
  outputs[0].written = outputs[0].count - 1;
#endif
  return NBE_OK;
}

#if defined(BROKEN_NULLFN)
/* Kept referenced, so that only the table's missing pointer differs from the other modes. */
int32_t (*const broken_unused_evaluate)(void*, nbe_surface_output*, nbe_error*) = evaluate;
#endif

static int instance_storage;
static void* create(const nbe_options* options, nbe_error* error) {
  (void)options, (void)error;
  return &instance_storage;
}
static void release(void* self) {
  (void)self;
}

static const nbe_evaluator table = {
#if defined(BROKEN_VERSION)
    99,
#else
    NBE_ABI_VERSION,
#endif
    sizeof(nbe_evaluator),
    BROKEN_NAME,
    "0",
    "a deliberately broken plugin (tests/plugins)",
    NBE_CAP_F32 | NBE_CAP_RATIONAL | NBE_CAP_GRID,
    15,
    create,
    prepare,
#if defined(BROKEN_NULLFN)
    NULL,
#else
    evaluate,
#endif
    NULL,
    release,
};

#if defined(BROKEN_NOENTRY)
/* Exported under another name: the library loads, but has no entry point. */
NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator_misspelt(uint32_t harness_abi_version) {
#else
NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator(uint32_t harness_abi_version) {
#endif
  (void)harness_abi_version;
  return &table;
}
