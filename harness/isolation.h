// Process isolation of measurements (docs/design.md §Isolation and result codes; the habit of
// piglit and the Khronos CTS): each measurement -- strategy x scene x sampling with its warm-up and
// repetitions -- runs in a child process under a watchdog, so a strategy that crashes or hangs
// costs only its own record. The parent keeps the results files, the reference cache and the
// progress display; the child runs the strategy's half of the runner (time_measurement) and hands
// back its record and raw result through a private directory, which the parent scores
// (score_measurement). The children are forked by a measurement server, this binary exec'd once
// per run (isolation.cpp says why).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "harness/record.h"
#include "harness/runner.h"

namespace nurbs {

enum class IsolationMode { process, none };
// "process" / "none"; parse throws InputError naming --isolation.
std::string_view to_string(IsolationMode mode);
IsolationMode parse_isolation(std::string_view text);

// Three quarters of this machine's physical memory: a measurement that wants more would push the
// run (and the machine's other work) into swap or the kernel's OOM killer, which picks its victim
// without asking which process misbehaved.
std::size_t default_memory_limit_bytes();
// --memory-limit MIB: a whole number of MiB in 16..the machine's memory; throws InputError naming
// the option, the value and the range.
std::size_t parse_memory_limit(std::string_view text);

struct IsolationSettings {
  IsolationMode mode = IsolationMode::process;
  // The watchdog: the whole measurement (setup, warm-up, repetitions, read back) must end within
  // this; then its process group is killed and the record is timed_out.
  double timeout_s = 600;
  // The most resident memory a child may hold (0: no limit); past it, it is killed like a hang and
  // its record is failed with "out of memory: ...".
  std::size_t memory_limit_bytes = default_memory_limit_bytes();
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
  // `eval`: create, prepare, evaluate, classify, read back once (evaluate_once), nothing timed.
  bool eval_only = false;
};

// measure() / measure_deforming() in-process (mode none) or in a child process; the record's
// status says crashed (with the signal and the phase) or timed_out (with the phase and the limit)
// when the child did not finish.
Record measure_with(const IsolationSettings& isolation, const MeasurementSpec& spec,
                    const Scene& scene, ReferenceCache& references);

// `eval`'s one evaluation, in-process (mode none) or in a child process, unscored: the record says
// how it ended (ok, or failed / refused / crashed / timed_out with the reason) and `result` holds
// the points when it is ok.
struct EvalOutcome {
  Record record;
  std::optional<EvalResult> result;
};
EvalOutcome evaluate_with(const IsolationSettings& isolation, const MeasurementSpec& spec,
                          const Scene& scene);
// create, prepare, evaluate, classify (a strategy that trims, on a trimmed scene), read back; an
// exception is r's status (refused, timed_out on a device wait, failed) and nullopt.
std::optional<EvalResult> evaluate_once(const StrategyEntry& entry, const StrategyOptions& options,
                                        const Scene& scene, const EvalRequest& request, Record& r);

// A private directory for one isolated child's files, removed with its contents.
class IsolationDirectory {
 public:
  IsolationDirectory();
  ~IsolationDirectory();
  IsolationDirectory(const IsolationDirectory&) = delete;
  IsolationDirectory& operator=(const IsolationDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// How an isolated child that did not finish its work ended: the status its record takes
// (crashed, timed_out, failed) and the reason, with the phase it was in.
struct ChildFailure {
  Status status = Status::failed;
  std::string reason;
};
// What the measurement server's children do: measure_child(DIR), or probe_plugin_child(DIR)
// (harness/plugins/plugin.h).
enum class ChildTask { measure, probe };
// Runs `task` on `directory` in a child of the measurement server, under the watchdog and the
// memory limit. nullopt when it exited with status 0; a child that exits otherwise is failed with
// its status and DIR/error.txt.
std::optional<ChildFailure> run_isolated(const IsolationSettings& isolation, ChildTask task,
                                         const std::filesystem::path& directory);

// The server (the hidden `measure-server FD` verb): per request line "TASK\tDIR\tTIMEOUT\tBYTES"
// on FD, forks a child that runs the task on DIR, waits at most TIMEOUT seconds and lets it hold
// at most BYTES of resident memory (0: any), then kills its process group and every descendant
// that left it (the server is their subreaper); answers "timed_out", "out_of_memory" or the
// child's wait status. Returns at end of file.
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
