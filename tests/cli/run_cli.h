// Runs the `nurbsbench` binary as a user would (fork + exec, no shell) and captures its exit code,
// stdout and stderr; plus the small file helpers the CLI tests share. Header-only: each test
// executable includes it.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

// ASan reserves terabytes of address space for its shadow memory, so an address-space limit
// cannot be applied to a sanitized binary. There an attempted huge allocation aborts the child
// instead (allocator_may_return_null=0), which the exit-code assertions catch just the same.
#if defined(__SANITIZE_ADDRESS__)
#define NURBSBENCH_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NURBSBENCH_TEST_ASAN 1
#endif
#endif

namespace nurbs::test {

struct CliResult {
  int exit_code = -1;  // the exit status, or 128 + signal when the child was killed
  std::string out, err;
};

struct CliLimits {
  // RLIMIT_AS for the child, in bytes (0: none): bad input must be refused before anything big
  // is allocated, so a rejected file has to be rejected under a small limit too.
  std::size_t address_space = 0;
};

// 1 GiB: far above what the CLI needs to start and reject input (tens of MiB), far below what
// an absurd control-point count would cost (4e9 points = 96 GiB).
inline constexpr std::size_t kRejectionMemoryLimit = std::size_t{1} << 30;

inline bool memory_limit_supported() {
#ifdef NURBSBENCH_TEST_ASAN
  return false;
#else
  return true;
#endif
}

inline CliResult run_cli(const std::vector<std::string>& args, const CliLimits& limits = {}) {
  std::vector<std::string> argv_text{NURBSBENCH_CLI};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);

  int out_pipe[2], err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0 || ::pipe2(err_pipe, O_CLOEXEC) != 0)
    throw std::runtime_error("pipe failed");
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    // Only async-signal-safe calls between fork and exec.
    if (limits.address_space > 0 && memory_limit_supported()) {
      const rlimit limit{limits.address_space, limits.address_space};
      ::setrlimit(RLIMIT_AS, &limit);
    }
    const int devnull = ::open("/dev/null", O_RDONLY);
    ::dup2(devnull, STDIN_FILENO);
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::dup2(err_pipe[1], STDERR_FILENO);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);

  CliResult result;
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&result.out, &result.err};
  int open_count = 2;
  char buffer[65536];
  while (open_count > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        sinks[i]->append(buffer, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_count;
      }
    }
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

// A fresh directory under $TMPDIR (or /tmp), removed with everything in it.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base && *base ? base : "/tmp") + "/nurbsbench-test-XXXXXX";
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string operator/(std::string_view name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// The output directory of `nurbsbench <args> --out DIR`, made once per build of the CLI and shared
// by every test process that asks for the same arguments. CTest runs each test case in a process of
// its own, so a suite's SetUpTestSuite would otherwise repeat the same multi-second run for every
// case. The directory lives under the build tree (NURBSBENCH_TEST_CACHE), keyed by the arguments
// and the CLI binary's size and modification time (a rebuilt CLI makes it again and removes the old
// one). It is made under an exclusive lock into a temporary directory and renamed into place, so
// test processes running in parallel wait for one maker and never read a half-written directory.
// A failed run is returned, not kept: `result.exit_code` says which. Callers only read it.
struct SharedCliOutput {
  CliResult result;  // of the run that made the directory; exit 0 and empty output when reused
  std::filesystem::path directory;
};

inline SharedCliOutput shared_cli_output(const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  struct stat binary {};
  if (::stat(NURBSBENCH_CLI, &binary) != 0) throw std::runtime_error("cannot stat the CLI binary");
  const std::string binary_stamp = std::to_string(binary.st_size) + " " +
                                   std::to_string(binary.st_mtim.tv_sec) + "." +
                                   std::to_string(binary.st_mtim.tv_nsec);
  std::string args_text;
  for (const std::string& a : args) args_text += a + "\n";
  const fs::path root = NURBSBENCH_TEST_CACHE;
  fs::create_directories(root);
  const std::string name = "run-" + std::to_string(std::hash<std::string>{}(args_text));
  const fs::path directory =
      root / (name + "-" + std::to_string(std::hash<std::string>{}(binary_stamp)));

  const int lock = ::open((root / (name + ".lock")).c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock < 0) throw std::runtime_error("cannot open the lock of " + directory.string());
  while (::flock(lock, LOCK_EX) != 0)
    if (errno != EINTR) throw std::runtime_error("cannot lock " + directory.string());
  SharedCliOutput out{{0, "", ""}, directory};
  if (!fs::exists(directory)) {
    std::error_code ignored;
    // What an earlier build of the CLI made for these arguments is stale now.
    for (const fs::directory_entry& e : fs::directory_iterator(root))
      if (e.path().filename().string().starts_with(name + "-")) fs::remove_all(e.path(), ignored);
    const fs::path making = directory.string() + ".making";
    std::vector<std::string> full = args;
    full.insert(full.end(), {"--out", making.string()});
    out.result = run_cli(full);
    if (out.result.exit_code == 0)
      fs::rename(making, directory);
    else
      fs::remove_all(making, ignored);
  }
  ::close(lock);  // releases the lock
  return out;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void write_text(const std::filesystem::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Lines without their '\n'; a final line without '\n' counts too.
inline std::vector<std::string> split_lines(std::string_view text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) {
      lines.emplace_back(text.substr(start));
      break;
    }
    lines.emplace_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

// One CSV record: commas split fields except inside double quotes ("" is a quote).
inline std::vector<std::string> split_csv(std::string_view line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted && c == '"' && k + 1 < line.size() && line[k + 1] == '"') {
      fields.back() += '"';
      ++k;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// The contract for bad input (docs/design.md §The CLI): exactly one line on stderr, prefixed.
inline bool is_one_error_line(const std::string& err) {
  return err.starts_with("nurbsbench: ") && err.ends_with("\n") && err.find('\n') == err.size() - 1;
}

}  // namespace nurbs::test
