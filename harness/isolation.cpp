#include "harness/isolation.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "harness/atomic_file.h"
#include "harness/plugins/plugin.h"
#include "harness/strategy_guard.h"
#include "reference/error_text.h"
#include "reference/validation.h"
#include "scenes/scene_json.h"
#include "strategies/device_wait.h"

namespace nurbs {

namespace fs = std::filesystem;
using nlohmann::json;

std::string_view to_string(IsolationMode mode) {
  return mode == IsolationMode::process ? "process" : "none";
}

IsolationMode parse_isolation(std::string_view text) {
  if (text == "process") return IsolationMode::process;
  if (text == "none") return IsolationMode::none;
  throw InputError(fmt::format("--isolation = '{}': must be process or none", text));
}

namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;
// Below this a child cannot even start: the binary and its libraries are some 30 MiB resident.
constexpr std::size_t kMinMemoryLimitMiB = 64;

std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page)
                               : 0;
}

}  // namespace

std::size_t default_memory_limit_bytes() {
  return physical_memory_bytes() / 4 * 3;
}

std::size_t parse_memory_limit(std::string_view text) {
  const std::size_t most = std::max(physical_memory_bytes() / kMiB, kMinMemoryLimitMiB);
  std::size_t mib = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), mib);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() ||
      mib < kMinMemoryLimitMiB || mib > most)
    throw InputError(
        fmt::format("--memory-limit = '{}': must be a whole number of MiB in {}..{} "
                    "(this machine's memory)",
                    printable(text, kQuotedValueBytes), kMinMemoryLimitMiB, most));
  return mib * kMiB;
}

namespace {

// ------------------------------------------------------------------ the raw result, in binary
// Little more than the vectors' bytes: the two processes are the same binary on the same machine.

constexpr std::string_view kResultMagic = "nurbsbench-result/1";

template <typename T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}
template <typename T>
void put_vector(std::string& out, const T* data, std::size_t count) {
  put(out, static_cast<std::uint64_t>(count));
  out.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}
void put_points(std::string& out, const PointArray& p) {
  put(out, static_cast<std::uint8_t>(p.precision() == Precision::f64));
  if (p.precision() == Precision::f32)
    put_vector(out, p.f32(), p.size() * 3);
  else
    put_vector(out, p.f64(), p.size() * 3);
}

class Reader {
 public:
  Reader(std::string text, std::string origin) : text_(std::move(text)), origin_(origin) {}
  template <typename T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  template <typename T>
  std::vector<T> get_vector() {
    const auto count = get<std::uint64_t>();
    if (count > (text_.size() - at_) / sizeof(T)) truncated();
    std::vector<T> v(count);
    if (count > 0) std::memcpy(v.data(), take(count * sizeof(T)), count * sizeof(T));
    return v;
  }
  PointArray get_points() {
    const bool f64 = get<std::uint8_t>() != 0;
    if (f64) {
      const auto values = get_vector<double>();
      PointArray p(Precision::f64, values.size() / 3);
      std::copy(values.begin(), values.end(), p.f64());
      return p;
    }
    const auto values = get_vector<float>();
    PointArray p(Precision::f32, values.size() / 3);
    std::copy(values.begin(), values.end(), p.f32());
    return p;
  }
  const char* take(std::size_t n) {
    if (n > text_.size() - at_) truncated();
    const char* p = text_.data() + at_;
    at_ += n;
    return p;
  }
  bool at_end() const { return at_ == text_.size(); }

 private:
  [[noreturn]] void truncated() const {
    throw std::runtime_error(fmt::format("{}: truncated result", origin_));
  }
  std::string text_, origin_;
  std::size_t at_ = 0;
};

// ------------------------------------------------------------------------------- the spec

json sampling_to_json(const Sampling& s) {
  return {{"mode", sampling_mode_name(s.mode)},
          {"grid_u", s.grid_u},
          {"grid_v", s.grid_v},
          {"span_steps", s.span_steps},
          {"explicit_uv", s.explicit_uv}};
}

Sampling sampling_from_json(const json& j) {
  Sampling s;
  for (SamplingMode mode :
       {SamplingMode::grid, SamplingMode::span_grid, SamplingMode::explicit_list})
    if (sampling_mode_name(mode) == j.at("mode").get<std::string>()) s.mode = mode;
  s.grid_u = j.at("grid_u");
  s.grid_v = j.at("grid_v");
  s.span_steps = j.at("span_steps");
  s.explicit_uv = j.at("explicit_uv").get<std::vector<std::vector<std::array<double, 2>>>>();
  return s;
}

json spec_to_json(const MeasurementSpec& spec) {
  return {{"strategy", spec.entry->name},
          {"plugin", strategy_library(*spec.entry) ? strategy_library(*spec.entry)->path : ""},
          {"threads", spec.options.threads},
          {"extra", spec.options.extra},
          {"sampling", sampling_to_json(spec.request.sampling)},
          {"precision", to_string(spec.request.precision)},
          {"normals", spec.request.normals},
          {"repetitions", spec.repetitions},
          {"deforming_frames", spec.deforming_frames},
          {"images", spec.images.string()},
          {"eval_only", spec.eval_only},
          {"device_wait_s", device_wait_limit_s()}};
}

// What the scene file must carry beyond nurbs-scene/1, per surface, so the child can tell when it
// did not (a writer that predates trims would hand the strategy an untrimmed face silently).
json surface_extras(const Scene& scene) {
  json extras = json::array();
  for (const Surface& s : scene.surfaces)
    extras.push_back({{"trim_loops", s.trim ? s.trim->loops.size() : 0}, {"reversed", s.reversed}});
  return extras;
}

MeasurementSpec spec_from_json(const json& j) {
  MeasurementSpec spec;
  // A plugin is loaded here again, in the child that measures it: its load is part of what may
  // crash, and the server that forked the child never loads one.
  const std::string plugin = j.value("plugin", "");
  spec.entry = find_strategy(j.at("strategy").get<std::string>());
  if (!spec.entry && !plugin.empty()) spec.entry = &load_plugin_in_process(plugin);
  if (spec.entry && spec.entry->name != j.at("strategy").get<std::string>())
    throw std::runtime_error(
        fmt::format("{} no longer holds strategy {}", plugin, j.at("strategy").get<std::string>()));
  if (!spec.entry) throw std::runtime_error("measurement spec: unknown strategy");
  spec.options.threads = j.at("threads");
  spec.options.extra = j.at("extra").get<std::map<std::string, std::string>>();
  spec.request.sampling = sampling_from_json(j.at("sampling"));
  spec.request.precision = j.at("precision") == "f64" ? Precision::f64 : Precision::f32;
  spec.request.normals = j.at("normals");
  spec.repetitions = j.at("repetitions");
  spec.deforming_frames = j.at("deforming_frames");
  spec.images = j.at("images").get<std::string>();
  spec.eval_only = j.at("eval_only");
  device_wait_limit_s() = j.at("device_wait_s");
  return spec;
}

Record spec_record(const MeasurementSpec& spec, const Scene& scene) {
  return measurement_record(*spec.entry, scene, spec.request,
                            spec.deforming_frames > 0 ? spec.deforming_frames : spec.repetitions,
                            spec.deforming_frames);
}

// ------------------------------------------------------------------------- the parent's side

// The server's end of the socket, in the server process.
constexpr int kServerFd = 3;

// "SIGSEGV (Segmentation fault)".
std::string signal_text(int sig) {
  const char* abbrev = ::sigabbrev_np(sig);
  const char* description = ::strsignal(sig);
  return fmt::format("SIG{} ({})", abbrev ? abbrev : std::to_string(sig).c_str(),
                     description ? description : "unknown signal");
}

struct ChildEnd {
  bool timed_out = false;
  bool out_of_memory = false;  // killed for holding more than the memory limit
  bool server_lost = false;    // the server died or stopped answering (not the measurement's doing)
  int status = 0;              // waitpid's, when the child ended in time
};

// The child's resident memory, from /proc/PID/statm (0 when it cannot be read: the child is gone).
std::size_t resident_bytes(pid_t pid) {
  const std::string file = fmt::format("/proc/{}/statm", pid);
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  char text[128] = {};
  const ssize_t n = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (n <= 0) return 0;
  unsigned long long size = 0, resident = 0;
  if (std::sscanf(text, "%llu %llu", &size, &resident) != 2) return 0;
  return static_cast<std::size_t>(resident) * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

// How often the watchdog looks at a child's memory: a child that allocates as fast as it can
// (several GiB/s) overshoots the limit by at most that much in between.
constexpr int kMemoryPollMs = 20;

// Waits for the child until the deadline, or until it holds more than `memory_limit` bytes
// resident (0: no limit); then kills the child's process group (the child and any helper process
// a driver started) and reaps it.
ChildEnd wait_for(pid_t pid, double timeout_s, std::size_t memory_limit = 0) {
  using clock = std::chrono::steady_clock;
  const auto deadline = clock::now() + std::chrono::duration_cast<clock::duration>(
                                           std::chrono::duration<double>(timeout_s));
  // pidfd: sleeping in poll() until the child ends or the deadline passes, with no SIGCHLD handler
  // and no polling latency added to every measurement.
  const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
  ChildEnd end;
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now());
    if (left.count() <= 0) {
      end.timed_out = true;
      break;
    }
    if (memory_limit > 0 && resident_bytes(pid) > memory_limit) {
      end.out_of_memory = true;
      break;
    }
    const long long wait_ms =
        std::min<long long>(left.count(), memory_limit > 0 ? kMemoryPollMs : 1 << 30);
    if (pidfd >= 0) {
      pollfd p{pidfd, POLLIN, 0};
      const int ready = ::poll(&p, 1, static_cast<int>(wait_ms));
      if (ready > 0) break;
      if (ready < 0 && errno != EINTR) throw std::runtime_error("poll on the measurement failed");
    } else {
      // Kernels before 5.3 have no pidfd: a short sleep between looks.
      siginfo_t info{};
      if (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
          info.si_pid == pid)
        break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  // The child is a zombie or alive, so its pid (and group id) cannot have been reused yet. The
  // child itself too: one that called setsid() or setpgid() is no longer in its group.
  ::kill(-pid, SIGKILL);
  ::kill(pid, SIGKILL);
  while (::waitpid(pid, &end.status, 0) < 0 && errno == EINTR) {
  }
  if (pidfd >= 0) ::close(pidfd);
  return end;
}

// This process's children (the server's: only what it adopted as subreaper once a measurement
// ended), from /proc; empty when there are none.
std::vector<pid_t> own_children() {
  std::vector<pid_t> children;
  const pid_t self = ::getpid();
  // The kernel's own list (CONFIG_PROC_CHILDREN); the server is single-threaded, so its one task
  // has them all. Else every process's parent, from /proc/PID/stat.
  if (std::ifstream list(fmt::format("/proc/self/task/{}/children", self)); list) {
    for (long pid = 0; list >> pid;) children.push_back(static_cast<pid_t>(pid));
    return children;
  }
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
    std::ifstream stat(e.path() / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    // "pid (comm) state ppid ...": comm may hold spaces and parentheses, so read after the last
    // ')'.
    const std::size_t close = line.rfind(')');
    if (close == std::string::npos) continue;
    char state = 0;
    long ppid = 0;
    if (std::sscanf(line.c_str() + close + 1, " %c %ld", &state, &ppid) == 2 && ppid == self)
      children.push_back(static_cast<pid_t>(std::stol(name)));
  }
  return children;
}

// A child that left the measurement's process group (setsid(), setpgid()) is not reached by the
// group kill; the server, as the children's subreaper, adopts every such descendant once its
// parent dies, so killing and reaping its own children until none is left ends them all.
void kill_descendants(pid_t group) {
  using clock = std::chrono::steady_clock;
  const auto give_up = clock::now() + std::chrono::seconds(5);
  // Once the group is empty its id may be reused by an unrelated process group: it is signalled
  // only until the first time it is found gone.
  bool group_alive = true;
  while (clock::now() < give_up) {
    if (group_alive && ::kill(-group, SIGKILL) != 0 && errno == ESRCH) group_alive = false;
    int status = 0;
    const pid_t reaped = ::waitpid(-1, &status, WNOHANG);
    if (reaped > 0) continue;
    if (reaped < 0) {
      // No child left and none of the group alive: the group's last members are gone and whatever
      // they had started has been adopted (and reaped) here. The usual case, in two system calls.
      if (errno == ECHILD && !group_alive) return;
    } else {
      // Adopted children still alive: only now is /proc read for them.
      for (const pid_t child : own_children()) ::kill(child, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// One line from fd (without '\n'); nullopt at end of file or error.
std::optional<std::string> read_line(int fd) {
  std::string line;
  char c = 0;
  for (;;) {
    const ssize_t n = ::read(fd, &c, 1);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return std::nullopt;
    if (c == '\n') return line;
    line += c;
  }
}

bool write_all(int fd, std::string_view text) {
  while (!text.empty()) {
    const ssize_t n = ::write(fd, text.data(), text.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    text.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

// The measurement server. Why a server and not one fork + exec per measurement: starting this
// binary costs about 0.1 s of CPU (it links some 50 shared libraries: OpenCASCADE, the GPU
// drivers' loaders; OpenImageIO is a module loaded only to write images), more on a loaded machine,
// which would dominate a 16x16 measurement. Why not a bare fork of the run itself: its OpenMP pool
// (the reference) and any driver threads do not exist in a forked child, whose next parallel region
// or driver call can hang. So the run fork + execs this binary once (`measure-server`), before the
// server has run a parallel region or touched a driver, and the server forks one child per
// measurement from that clean, single-threaded state (Android's zygote, Python's forkserver). The
// watchdog runs in the server; the run waits for the server's one-line answer, with a margin, in
// case the server itself is lost.
class MeasurementServer {
 public:
  ~MeasurementServer() { stop(); }

  ChildEnd measure(const fs::path& executable, ChildTask task, const fs::path& directory,
                   double timeout_s, std::size_t memory_limit) {
    if (pid_ <= 0) start(executable);
    ChildEnd end;
    if (!write_all(socket_,
                   fmt::format("{}\t{}\t{}\t{}\n", task == ChildTask::probe ? "probe" : "measure",
                               directory.string(), timeout_s, memory_limit))) {
      stop();
      end.server_lost = true;
      return end;
    }
    pollfd p{socket_, POLLIN, 0};
    const double margin_s = 30;
    const int ready = ::poll(&p, 1, static_cast<int>(std::min(timeout_s + margin_s, 2e6) * 1000));
    const auto answer = ready > 0 ? read_line(socket_) : std::nullopt;
    if (!answer) {
      stop();
      end.server_lost = true;
    } else if (*answer == "timed_out") {
      end.timed_out = true;
    } else if (*answer == "out_of_memory") {
      end.out_of_memory = true;
    } else {
      end.status = std::stoi(*answer);
    }
    return end;
  }

 private:
  void start(const fs::path& executable) {
    int pair[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, pair) != 0)
      throw std::runtime_error(fmt::format("socketpair: {}", std::strerror(errno)));
    const std::string path = executable.string();
    const std::string fd_text = std::to_string(kServerFd);
    std::vector<char*> argv = {const_cast<char*>("nurbsbench"), const_cast<char*>("measure-server"),
                               const_cast<char*>(fd_text.c_str()), nullptr};
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error(fmt::format("fork: {}", std::strerror(errno)));
    if (pid == 0) {
      // Only async-signal-safe calls between fork and exec. The server dies with the run; its
      // stdout goes to stderr so a verb's own output (recommend --json) stays clean.
      // Its own process group, so stop() can kill it like a measurement.
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      ::setpgid(0, 0);
      // dup2 clears close-on-exec on the copy; when the end already is kServerFd, fcntl does.
      if (pair[1] == kServerFd)
        ::fcntl(kServerFd, F_SETFD, 0);
      else
        ::dup2(pair[1], kServerFd);
      ::dup2(STDERR_FILENO, STDOUT_FILENO);
      ::execv(path.c_str(), argv.data());
      ::_exit(127);
    }
    ::close(pair[1]);
    socket_ = pair[0];
    pid_ = pid;
  }

  void stop() {
    if (socket_ >= 0) ::close(socket_);  // the server reads end of file and exits
    socket_ = -1;
    // A server that read end of file exits on its own; one that does not is killed.
    if (pid_ > 0) wait_for(pid_, 5);
    pid_ = -1;
  }

  int socket_ = -1;
  pid_t pid_ = -1;
};

// One per process: the run's measurements share it.
MeasurementServer& measurement_server() {
  static MeasurementServer server;
  return server;
}

// The strategy's half in a child: the record it wrote and its result, or the record of how the
// child ended. nullopt result: the record is final.
EvalOutcome run_spec_in_child(const IsolationSettings& isolation, const MeasurementSpec& spec,
                              const Scene& scene) {
  EvalOutcome out{spec_record(spec, scene), std::nullopt};
  Record& r = out.record;
  if (refused_by_kind(*spec.entry, scene, spec.request, r)) return out;
  // A plugin the probe found unusable is not loaded again: its record is the probe's reason.
  if (const std::optional<std::string> problem = plugin_problem(*spec.entry)) {
    r.status = Status::failed;
    r.reason = *problem;
    return out;
  }
  IsolationDirectory dir;
  write_file_atomically(dir.path() / "scene.json", scene_to_json(scene));
  json spec_json = spec_to_json(spec);
  spec_json["surfaces"] = surface_extras(scene);
  write_file_atomically(dir.path() / "spec.json", spec_json.dump());
  if (const auto failure = run_isolated(isolation, ChildTask::measure, dir.path())) {
    r.status = failure->status;
    r.reason = failure->reason;
    return out;
  }
  const fs::path record_file = dir.path() / "record.json";
  if (!fs::exists(record_file)) {
    // Exit status 0 without the record: the strategy ended the process itself (exit(0)).
    const std::string phase = read_phase_board(dir.path() / "phase");
    r.status = Status::failed;
    r.reason = fmt::format(
        "the measurement process exited with status 0 {} before its record was "
        "written (the strategy called exit?)",
        phase.empty() ? "before any phase" : "in " + phase);
    return out;
  }
  try {
    r = record_from_json(json::parse(read_whole_file(record_file)));
    const fs::path result_file = dir.path() / "result.bin";
    if (r.status == Status::ok && fs::exists(result_file))
      out.result = read_eval_result(result_file);
  } catch (const std::exception& e) {
    r.status = Status::failed;
    r.reason =
        plugin_text(fmt::format("the measurement's record could not be read: {}", e.what()), 1024);
    out.result.reset();
  }
  return out;
}

Record measure_in_child(const IsolationSettings& isolation, const MeasurementSpec& spec,
                        const Scene& scene, ReferenceCache& references) {
  EvalOutcome outcome = run_spec_in_child(isolation, spec, scene);
  Record& r = outcome.record;
  if (!outcome.result) return r;
  std::optional<EvalResult>& result = outcome.result;
  if (spec.deforming_frames > 0)
    score_deforming(*spec.entry, scene, spec.request, spec.deforming_frames, *result,
                    references.precision(), spec.trim_band, r);
  else
    score_measurement(*spec.entry, scene, spec.request, *result, references, spec.trim_band, r,
                      spec.images);
  return r;
}

// In a fresh fork of the server: one measurement (or plugin probe), then _exit (the server's own
// state, copied, is not this process's to tear down; the record is already on disk).
[[noreturn]] void run_measurement_child(int socket, ChildTask task, const std::string& directory) {
  ::close(socket);
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  // Its own process group, so the watchdog kills the drivers' helpers with it; no core files from
  // the crashes a benchmark of drivers expects (--isolation none reproduces one in a debugger).
  ::setpgid(0, 0);
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  int code = 0;
  try {
    code = task == ChildTask::probe ? probe_plugin_child(directory) : measure_child(directory);
  } catch (const std::exception& e) {
    // An error of the harness's side (spec, scene), not the strategy's: the parent reports it.
    std::ofstream(fs::path(directory) / "error.txt") << e.what();
    code = 2;
  }
  std::fflush(nullptr);
  ::_exit(code);
}

}  // namespace

IsolationDirectory::IsolationDirectory() {
  const char* base = std::getenv("TMPDIR");
  std::string pattern = std::string(base && *base ? base : "/tmp") + "/nurbsbench-measure-XXXXXX";
  if (!::mkdtemp(pattern.data()))
    throw std::runtime_error(fmt::format("{}: cannot create: {}", pattern, std::strerror(errno)));
  // Absolute: the child may change its working directory before it writes its answer.
  path_ = fs::absolute(pattern);
}

IsolationDirectory::~IsolationDirectory() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

std::optional<ChildFailure> run_isolated(const IsolationSettings& isolation, ChildTask task,
                                         const fs::path& directory) {
  const ChildEnd end = measurement_server().measure(
      isolation.executable, task, directory, isolation.timeout_s, isolation.memory_limit_bytes);
  const std::string phase = read_phase_board(directory / "phase");
  const std::string in_phase = phase.empty() ? "before any phase" : "in " + phase;
  if (end.server_lost)
    return ChildFailure{Status::failed,
                        fmt::format("the measurement server was lost {}", in_phase)};
  if (end.timed_out)
    return ChildFailure{Status::timed_out, fmt::format("no answer within {:g} s (--timeout) {}",
                                                       isolation.timeout_s, in_phase)};
  if (end.out_of_memory)
    return ChildFailure{Status::out_of_memory,
                        fmt::format("held more than {} MiB resident (--memory-limit) {}",
                                    isolation.memory_limit_bytes / kMiB, in_phase)};
  if (WIFSIGNALED(end.status))
    return ChildFailure{Status::crashed,
                        fmt::format("{} {}", signal_text(WTERMSIG(end.status)), in_phase)};
  if (WEXITSTATUS(end.status) == 0) return std::nullopt;
  const fs::path error_file = directory / "error.txt";
  std::string error;
  if (fs::exists(error_file)) error = ": " + read_whole_file(error_file);
  return ChildFailure{Status::failed,
                      plugin_text(fmt::format("measurement process exited with status {} {}{}",
                                              WEXITSTATUS(end.status), in_phase, error),
                                  1024)};
}

std::optional<EvalResult> evaluate_once(const StrategyEntry& entry, const StrategyOptions& options,
                                        const Scene& scene, const EvalRequest& request, Record& r) {
  std::optional<EvalResult> result;
  try {
    std::unique_ptr<Strategy> strategy = create_guarded(entry, options);
    strategy->prepare(scene, request);
    strategy->evaluate();
    if (entry.capabilities().trims && scene.has_trims()) strategy->classify();
    result = strategy->read_back();
    r.device = strategy->device();
  } catch (const RefusedError& e) {
    r.status = Status::refused;
    r.reason = plugin_text(e.what(), 1024);
  } catch (const DeviceTimeout& e) {
    r.status = Status::timed_out;
    r.reason = plugin_text(fmt::format("in {}: {}", current_phase(), e.what()), 1024);
  } catch (const std::exception& e) {
    r.status = Status::failed;
    r.reason = plugin_text(e.what(), 1024);
  }
  if (r.status != Status::ok) result.reset();
  return result;
}

EvalOutcome evaluate_with(const IsolationSettings& isolation, const MeasurementSpec& spec,
                          const Scene& scene) {
  if (isolation.mode == IsolationMode::process) return run_spec_in_child(isolation, spec, scene);
  EvalOutcome out{spec_record(spec, scene), std::nullopt};
  if (refused_by_kind(*spec.entry, scene, spec.request, out.record)) return out;
  out.result = evaluate_once(*spec.entry, spec.options, scene, spec.request, out.record);
  return out;
}

void write_eval_result(const fs::path& file, const EvalResult& result) {
  std::string out(kResultMagic);
  put(out, static_cast<std::uint64_t>(result.surfaces.size()));
  for (const SurfaceResult& s : result.surfaces) {
    put(out, static_cast<std::uint8_t>(s.samples.tensor));
    put_vector(out, s.samples.u.data(), s.samples.u.size());
    put_vector(out, s.samples.v.data(), s.samples.v.size());
    put_points(out, s.positions);
    put_points(out, s.normals);
    put_vector(out, s.inside.data(), s.inside.size());
  }
  write_file_atomically(file, out);
}

EvalResult read_eval_result(const fs::path& file) {
  Reader in(read_whole_file(file), file.string());
  if (std::string_view(in.take(kResultMagic.size()), kResultMagic.size()) != kResultMagic)
    throw std::runtime_error(fmt::format("{}: not a {} file", file.string(), kResultMagic));
  EvalResult result;
  result.surfaces.resize(in.get<std::uint64_t>());
  for (SurfaceResult& s : result.surfaces) {
    s.samples.tensor = in.get<std::uint8_t>() != 0;
    s.samples.u = in.get_vector<double>();
    s.samples.v = in.get_vector<double>();
    s.positions = in.get_points();
    s.normals = in.get_points();
    s.inside = in.get_vector<std::uint8_t>();
  }
  if (!in.at_end()) throw std::runtime_error(fmt::format("{}: trailing bytes", file.string()));
  return result;
}

Record measure_with(const IsolationSettings& isolation, const MeasurementSpec& spec,
                    const Scene& scene, ReferenceCache& references) {
  if (isolation.mode == IsolationMode::process)
    return measure_in_child(isolation, spec, scene, references);
  return spec.deforming_frames > 0
             ? measure_deforming(*spec.entry, spec.options, scene, spec.request,
                                 spec.deforming_frames, references.precision(), spec.trim_band)
             : measure(*spec.entry, spec.options, scene, spec.request, spec.repetitions, references,
                       spec.trim_band, spec.images);
}

int measure_server(int socket) {
  // Orphans of the measurements (a helper that called setsid()) are re-parented here, not to init,
  // so kill_descendants can end them.
  ::prctl(PR_SET_CHILD_SUBREAPER, 1);
  for (;;) {
    const auto request = read_line(socket);
    if (!request) return 0;
    std::vector<std::string> fields;
    std::istringstream line(*request);
    for (std::string field; std::getline(line, field, '\t');) fields.push_back(field);
    if (fields.size() != 4) return 2;
    const ChildTask task = fields[0] == "probe" ? ChildTask::probe : ChildTask::measure;
    const std::string& directory = fields[1];
    const double timeout_s = std::stod(fields[2]);
    const std::size_t memory_limit = std::stoull(fields[3]);
    const pid_t pid = ::fork();
    if (pid < 0) return 2;
    if (pid == 0) run_measurement_child(socket, task, directory);
    // Both sides set the group: whichever runs first, the watchdog's kill(-pid) finds it.
    ::setpgid(pid, pid);
    const ChildEnd end = wait_for(pid, timeout_s, memory_limit);
    kill_descendants(pid);
    const std::string answer = end.timed_out       ? "timed_out"
                               : end.out_of_memory ? "out_of_memory"
                                                   : std::to_string(end.status);
    if (!write_all(socket, answer + "\n")) return 0;
  }
}

int measure_child(const fs::path& directory) {
  share_phase_board(directory / "phase");
  injected_fault();
  const json spec_json = json::parse(read_whole_file(directory / "spec.json"));
  const MeasurementSpec spec = spec_from_json(spec_json);
  const Scene scene = load_scene_file(directory / "scene.json");
  if (surface_extras(scene) != spec_json.at("surfaces"))
    throw std::runtime_error(
        "the scene's trims or face orientation did not survive its transfer as nurbs-scene JSON "
        "(--isolation none measures it in one process)");
  Record r = spec_record(spec, scene);
  const std::optional<EvalResult> result =
      spec.eval_only ? evaluate_once(*spec.entry, spec.options, scene, spec.request, r)
      : spec.deforming_frames > 0
          ? time_deforming(*spec.entry, spec.options, scene, spec.request, spec.deforming_frames, r)
          : time_measurement(*spec.entry, spec.options, scene, spec.request, spec.repetitions, r,
                             spec.images);
  if (result) write_eval_result(directory / "result.bin", *result);
  // Last: its presence says the child finished.
  write_file_atomically(directory / "record.json", record_to_json(r).dump());
  return 0;
}

}  // namespace nurbs
