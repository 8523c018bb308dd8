/* A hostile evaluator plugin (C style, compiled as C++ like echo_plugin.cpp: the project enables
 * no C), built once per misbehaviour (one HOSTILE_<MODE> macro, name HOSTILE_NAME), for
 * tests/cli/hostile_plugins_test.cpp: what a user's library may do to the
 * harness, from its load-time constructors to what it does inside evaluate(). Apart from its one
 * misbehaviour it is a working plugin that returns (u, v, 0) for every sample, so a test can tell
 * the harness survived *and* still delivered.
 *   CTOR_CRASH / CTOR_HANG / CTOR_EXIT / CTOR_STDOUT   a constructor raises SIGSEGV / never returns
 *                                                      / calls exit(0) / prints to stdout
 *   ENTRY_CRASH / ENTRY_HANG                           the entry point does the same
 *   EVAL_ABORT / EVAL_CRASH / EVAL_EXIT0               evaluate() aborts / raises SIGSEGV / exit(0)
 *   PREPARE_HANG                                       prepare() loops forever
 *   EVAL_CHDIR / EVAL_CLOSE_FDS / EVAL_STDOUT          evaluate() changes the working directory /
 *                                                      closes every descriptor / prints to stdout,
 *                                                      then works
 *   EVAL_BAD_MESSAGE                                   evaluate() fails with a message that is not
 *                                                      UTF-8 and holds a newline and an escape
 *   EVAL_SETSID                                        evaluate() starts a grandchild that leaves
 *                                                      the process group (setsid) and sleeps; its
 *                                                      pid goes to $HOSTILE_PID_FILE
 *   EVAL_MEMORY                                        evaluate() touches memory until killed
 *   BAD_NAME                                           the table's name holds a newline
 *   STRUCT_SIZE                                        struct_size 0xFFFFFFFF
 *   ABI_ZERO                                           abi_version 0
 *   NO_ENTRY                                           no nurbsbench_evaluator symbol
 * Not an example to copy: examples/plugins/ has those. */
#include <nurbsbench/evaluator.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#if defined(HOSTILE_CTOR_CRASH) || defined(HOSTILE_CTOR_HANG) || defined(HOSTILE_CTOR_EXIT) || \
    defined(HOSTILE_CTOR_STDOUT)
__attribute__((constructor)) static void hostile_constructor(void) {
#if defined(HOSTILE_CTOR_CRASH)
  signal(SIGSEGV, SIG_DFL);
  raise(SIGSEGV);
#elif defined(HOSTILE_CTOR_HANG)
  for (;;) pause();
#elif defined(HOSTILE_CTOR_EXIT)
  exit(0);
#else
  printf("a constructor's chatter on stdout\n");
  fflush(stdout);
#endif
}
#endif

typedef struct {
  uint32_t surfaces, precision;
  const nbe_samples* samples;
} instance;

static instance the_instance;

static void* create(const nbe_options* options, nbe_error* error) {
  (void)options, (void)error;
  return &the_instance;
}

static int32_t prepare(void* self, const nbe_scene* scene, const nbe_request* request,
                       const nbe_samples* samples, nbe_error* error) {
  instance* in = (instance*)self;
  (void)error;
#if defined(HOSTILE_PREPARE_HANG)
  {
    /* A busy loop, not a sleep: the watchdog must stop a process that never yields. */
    volatile int spinning = 1;
    while (spinning) {
    }
  }
#endif
  in->surfaces = scene->surface_count;
  in->precision = request->precision;
  in->samples = samples;
  return NBE_OK;
}

static int32_t evaluate(void* self, nbe_surface_output* outputs, nbe_error* error) {
  const instance* in = (const instance*)self;
  uint32_t i;
  size_t k;
#if defined(HOSTILE_EVAL_ABORT)
  abort();
#elif defined(HOSTILE_EVAL_CRASH)
  signal(SIGSEGV, SIG_DFL);
  raise(SIGSEGV);
#elif defined(HOSTILE_EVAL_EXIT0)
  exit(0);
#elif defined(HOSTILE_EVAL_CHDIR)
  if (chdir("/") != 0) return NBE_ERROR;
#elif defined(HOSTILE_EVAL_CLOSE_FDS)
  {
    int fd;
    for (fd = 0; fd < 1024; ++fd) close(fd);
  }
#elif defined(HOSTILE_EVAL_STDOUT)
  printf("evaluate's chatter on stdout\n");
  fflush(stdout);
#elif defined(HOSTILE_EVAL_BAD_MESSAGE)
  snprintf(error->message, sizeof error->message,
           "bad bytes \xff\xfe\xc0\xaf here\nsecond line \x1b[31mred\x1b[0m \xe2\x82");
  return NBE_ERROR;
#elif defined(HOSTILE_EVAL_SETSID)
  {
    /* Each evaluate() starts one: the file is removed first and written whole (a rename), so the
       wait below reads this call's grandchild, never the previous one's or half a write. */
    const char* pid_file = getenv("HOSTILE_PID_FILE");
    if (pid_file) unlink(pid_file);
    const pid_t child = fork();
    if (child == 0) {
      const char* file = getenv("HOSTILE_PID_FILE");
      setsid();
      if (file) {
        char partial[4096];
        snprintf(partial, sizeof partial, "%s.partial", file);
        FILE* f = fopen(partial, "w");
        if (f) {
          fprintf(f, "%d\n", (int)getpid());
          fclose(f);
          rename(partial, file);
        }
      }
      for (;;) pause();
    }
    /* Until the grandchild has said who it is, so the test can look for it afterwards. */
    {
      const char* file = getenv("HOSTILE_PID_FILE");
      int tries;
      for (tries = 0; file && tries < 2000; ++tries) {
        FILE* f = fopen(file, "r");
        int pid = 0;
        if (f) {
          const int got = fscanf(f, "%d", &pid);
          fclose(f);
          if (got == 1 && pid > 0) break;
        }
        usleep(1000);
      }
    }
  }
#elif defined(HOSTILE_EVAL_MEMORY)
  for (;;) {
    char* block = (char*)malloc(64u << 20);
    if (!block) break;
    memset(block, 1, 64u << 20);
  }
#endif
  (void)error;
  for (i = 0; i < in->surfaces; ++i) {
    const nbe_samples* s = &in->samples[i];
    for (k = 0; k < s->count; ++k) {
      const double u = s->tensor ? s->u[k / s->v_count] : s->u[k];
      const double v = s->tensor ? s->v[k % s->v_count] : s->v[k];
      if (in->precision == NBE_F32) {
        float* p = (float*)outputs[i].positions + 3 * k;
        p[0] = (float)u, p[1] = (float)v, p[2] = 0;
      } else {
        double* p = (double*)outputs[i].positions + 3 * k;
        p[0] = u, p[1] = v, p[2] = 0;
      }
    }
    outputs[i].written = s->count;
  }
  return NBE_OK;
}

static void release(void* self) {
  (void)self;
}

static const nbe_evaluator table = {
#if defined(HOSTILE_ABI_ZERO)
    0,
#else
    NBE_ABI_VERSION,
#endif
#if defined(HOSTILE_STRUCT_SIZE)
    0xFFFFFFFFu,
#else
    sizeof(nbe_evaluator),
#endif
#if defined(HOSTILE_BAD_NAME)
    "evil\nname\x1b[2J",
#else
    HOSTILE_NAME,
#endif
    "1.0 \xff",
    "a hostile plugin (tests/harness/hostile_plugin.cpp)",
    NBE_CAP_F32 | NBE_CAP_F64 | NBE_CAP_RATIONAL | NBE_CAP_GRID | NBE_CAP_SPAN_GRID |
        NBE_CAP_EXPLICIT,
    0,
    create,
    prepare,
    evaluate,
    NULL,
    release,
};

#if defined(HOSTILE_NO_ENTRY)
extern "C" NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator_misspelt(
    uint32_t harness_abi_version) {
#else
extern "C" NBE_EXPORT const nbe_evaluator* nurbsbench_evaluator(uint32_t harness_abi_version) {
#endif
  (void)harness_abi_version;
#if defined(HOSTILE_ENTRY_CRASH)
  signal(SIGSEGV, SIG_DFL);
  raise(SIGSEGV);
#elif defined(HOSTILE_ENTRY_HANG)
  for (;;) pause();
#endif
  return &table;
}
