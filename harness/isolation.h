// Process isolation of measurements (docs/design.md §Isolation and result codes; the habit of
// piglit and the Khronos CTS): each measurement -- strategy x scene x sampling with its warm-up and
// repetitions -- runs in a child process under a watchdog, so a strategy that crashes or hangs
// costs only its own record. The parent keeps the results files, the reference cache and the
// progress display; the child runs the strategy's half of the runner (time_measurement) and hands
// back its record and raw result through a private directory, which the parent scores
// (score_measurement). The children are forked by a measurement server, this binary exec'd once
// per run (isolation.cpp says why).
#pragma once

#include <filesystem>
#include <string>

#include "harness/record.h"
#include "harness/runner.h"

namespace nurbs {

enum class IsolationMode { process, none };
// "process" / "none"; parse throws InputError naming --isolation.
std::string_view to_string(IsolationMode mode);
IsolationMode parse_isolation(std::string_view text);

struct IsolationSettings {
  IsolationMode mode = IsolationMode::process;
  // The watchdog: the whole measurement (setup, warm-up, repetitions, read back) must end within
  // this; then its process group is killed and the record is timed_out.
  double timeout_s = 600;
  // The binary that understands the hidden `measure-server` verb (this one: /proc/self/exe).
  std::filesystem::path executable = "/proc/self/exe";
};

// One measurement, as `run` and `recommend` describe it.
struct MeasurementSpec {
  const StrategyEntry* entry = nullptr;
  StrategyOptions options;
  EvalRequest request;
  int repetitions = 5;
  int deforming_frames = 0;             // > 0: measure_deforming with this many frames
  double trim_band = kDefaultTrimBand;  // scoring only: the parent's side
  // run --images DIR (empty: none). The child writes the picture (only it holds the strategy);
  // the parent, which scores, writes the trim masks. Not for the deforming benchmark.
  std::filesystem::path images{};
};

// measure() / measure_deforming() in-process (mode none) or in a child process; the record's
// status says crashed (with the signal and the phase) or timed_out (with the phase and the limit)
// when the child did not finish.
Record measure_with(const IsolationSettings& isolation, const MeasurementSpec& spec,
                    const Scene& scene, ReferenceCache& references);

// The server (the hidden `measure-server FD` verb): per request line "DIR\tTIMEOUT" on FD, forks a
// child that runs measure_child(DIR), waits at most TIMEOUT seconds (then kills its process
// group), answers "timed_out" or the child's wait status. Returns at end of file.
int measure_server(int socket);

// The child's side: reads DIR/spec.json and DIR/scene.json, runs
// the strategy's half, writes DIR/record.json and, when there is something to score,
// DIR/result.bin. Exit code 0 whenever the record was written, whatever its status.
int measure_child(const std::filesystem::path& directory);

// The raw result across the process boundary, exactly (positions and normals in their own
// precision, samples in double, inside masks).
void write_eval_result(const std::filesystem::path& file, const EvalResult& result);
EvalResult read_eval_result(const std::filesystem::path& file);

}  // namespace nurbs
