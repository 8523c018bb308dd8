// The verbs of the `nurbsbench` CLI. Each returns the process exit code: 0 success, 1 a
// check/gate failed, 2 bad usage or bad input (one line on stderr naming what and where).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/cli/parsing.h"
#include "harness/isolation.h"
#include "reference/reference_evaluator.h"
#include "reference/sampling.h"
#include "reference/scalar.h"

namespace nurbs::cli {

struct ListOptions {
  std::vector<std::string> plugins;  // --plugin PATH (repeatable): harness/plugins/plugin.h
  bool json = false;
  double timeout_s = 60;  // --timeout: the bound on each plugin's probe
};
int list_command(const ListOptions& options);

struct SceneOptions {
  std::string scene;
  std::string out;
};
int scene_command(const SceneOptions& options);

struct ImportOptions {
  std::string model;  // .stp/.step, .igs/.iges, .brep
  std::string out;    // default: stdout
  bool strict = false;
};
int import_command(const ImportOptions& options);

// --isolation, --timeout, --device-timeout, --memory-limit: how `run`, `recommend` and `eval`
// survive their strategies (harness/isolation.h).
struct IsolationOptions {
  std::string isolation = "process";
  double timeout_s = 600;
  double device_timeout_s = 60;
  std::string memory_limit;  // MiB; empty: default_memory_limit_bytes()
};

struct EvalOptions {
  std::vector<std::string> plugins;  // --plugin PATH (repeatable): harness/plugins/plugin.h
  std::string scene, strategy;
  std::string samples = "64x64";
  std::string span_samples;
  bool span_given = false;  // --span-samples was on the command line (an empty value is an error)
  std::string uv_file;
  bool normals = false;
  std::string precision = "f32";
  std::string reference = "long-double";
  std::string out;
  int threads = 0;
  std::string gl;      // --gl osmesa|egl for the GL strategies (StrategyOptions.extra["gl"])
  std::string device;  // --device N for the OpenCL strategies (StrategyOptions.extra["device"])
  std::vector<std::string> strategy_options;  // --strategy-option KEY=VALUE (extra[KEY] = VALUE)
  std::string error_image;                    // --error-image F.exr|F.png (harness/error_image.h)
  std::optional<std::string> trim_band;       // --trim-band FRACTION (absent: kDefaultTrimBand)
  IsolationOptions isolation;
};
int eval_command(const EvalOptions& options);

struct RunOptions {
  std::vector<std::string> plugins;  // --plugin PATH (repeatable): harness/plugins/plugin.h
  std::string scenes = "default";
  std::string strategies = "all";
  std::string samples = "64x64,256x256";
  std::string span_samples;
  // Which of --samples / --span-samples were on the command line (an empty value is an error):
  // both measure the grids, then the span grids; --span-samples alone only the span grids.
  bool samples_given = false, span_given = false;
  std::string precision = "f32";
  bool normals = false;
  int repetitions = 5;
  int deforming = 0;  // --deforming FRAMES: the deforming-surface benchmark (0: off)
  std::string reference = "long-double";
  std::string out = "results/latest";
  int threads = 0;
  std::string gl;      // --gl osmesa|egl for the GL strategies (StrategyOptions.extra["gl"])
  std::string device;  // --device N for the OpenCL strategies (StrategyOptions.extra["device"])
  std::vector<std::string> strategy_options;  // --strategy-option KEY=VALUE (extra[KEY] = VALUE)
  IsolationOptions isolation;
  std::optional<std::string> trim_band;  // --trim-band FRACTION (absent: kDefaultTrimBand)
  std::string images;                    // --images DIR (empty: no pictures)
};
int run_command(const RunOptions& options);

struct LodOptions {
  std::string scene = "tan21x23";
  std::string samples = "128x128,512x512,1024x1024";
  int levels = 3;
  int repetitions = 7;
  std::string out = "results/latest";
  int threads = 0;
  std::string gl;
  std::string images;  // --images DIR (empty: no pictures)
};
int lod_command(const LodOptions& options);

// 000 §3.2 along a fly-in (harness/cli/camera_path.cpp).
struct CameraPathOptions {
  std::string scenes = "teapot";
  int frames = 60;
  std::string viewport = "640x480";
  double pixels_per_sample = 4;
  int min_samples = 4, max_samples = 256;
  std::string fixed_samples = "64x64";  // the baseline: 000 §5's Fig 1 grid, every surface
  std::string out = "results/latest";
  int threads = 0;
  std::string gl;
  std::string images;  // --images DIR (empty: no pictures)
};
int camera_path_command(const CameraPathOptions& options);

struct CheckOptions {
  std::string gates;
  std::string results = "results/latest";
};
int check_command(const CheckOptions& options);

struct MemoryOptions {
  std::string scenes = "default";
  bool json = false;
};
int memory_command(const MemoryOptions& options);

struct ReportOptions {
  std::vector<std::string> results;  // results directories (or results.json files)
  std::string out;                   // default: <first results>/report
  std::string python = "/usr/bin/python3";
  int error_images = 3;  // heat maps of the N worst (strategy, scene) pairs, re-evaluated here
  int trim_masks = 3;    // trim masks of the N pairs with the most misclassified samples
};
int report_command(const ReportOptions& options);

struct RecommendOptions {
  std::vector<std::string> plugins;  // --plugin PATH (repeatable): harness/plugins/plugin.h
  std::string results;               // empty: measure the workload here (a quick run)
  std::string scene, samples, precision, control_net, tolerance;
  int degree = -1, surfaces = -1;  // -1: not given
  bool deforming = false, json = false;
  int repetitions = 3, threads = 0;
  IsolationOptions isolation;
};
int recommend_command(const RecommendOptions& options);

struct GbenchOptions {
  std::string results = "results/latest";
  std::string out;  // default: stdout
};
int gbench_command(const GbenchOptions& options);

// Checks the isolation options and applies --device-timeout (process-wide, before any strategy).
IsolationSettings isolation_settings(const IsolationOptions& options);

}  // namespace nurbs::cli
