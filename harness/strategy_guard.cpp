#include "harness/strategy_guard.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "reference/validation.h"

namespace nurbs {

namespace {

constexpr std::size_t kBoardSize = 64;
std::array<char, kBoardSize> local_board{};
char* board = local_board.data();

constexpr std::string_view kFaultVariable = "NURBSBENCH_INJECT_FAULT";
constexpr std::array<std::string_view, 7> kFaultPhases = {
    "setup", "prepare", "evaluate", "read_back", "classify", "render", "update"};
constexpr std::array<std::string_view, 4> kFaultKinds = {"crash", "hang", "throw", "nan"};

std::optional<InjectedFault> parse_fault(std::string_view text) {
  if (text.empty()) return std::nullopt;
  auto fail = [&](std::string_view rule) {
    throw InputError(fmt::format(
        "{}={}: {} (expected <strategy>:<phase>:<kind>, phase one of {}, "
        "kind one of {})",
        kFaultVariable, text, rule, fmt::join(kFaultPhases, "|"), fmt::join(kFaultKinds, "|")));
  };
  const std::size_t first = text.find(':');
  const std::size_t second = first == std::string_view::npos ? first : text.find(':', first + 1);
  if (second == std::string_view::npos) fail("three fields");
  InjectedFault f{std::string(text.substr(0, first)),
                  std::string(text.substr(first + 1, second - first - 1)),
                  std::string(text.substr(second + 1))};
  if (!find_strategy(f.strategy)) fail(fmt::format("'{}' is not a strategy", f.strategy));
  if (std::find(kFaultPhases.begin(), kFaultPhases.end(), f.phase) == kFaultPhases.end())
    fail(fmt::format("unknown phase '{}'", f.phase));
  if (std::find(kFaultKinds.begin(), kFaultKinds.end(), f.kind) == kFaultKinds.end())
    fail(fmt::format("unknown kind '{}'", f.kind));
  if (f.kind == "nan" && f.phase != "read_back") fail("nan corrupts what read_back returns");
  return f;
}

// The fault `kind` in `phase`, when the variable names this strategy and phase. nan is applied
// to the result by the caller.
void inject(std::string_view strategy, std::string_view phase) {
  const auto& fault = injected_fault();
  if (!fault || fault->strategy != strategy || fault->phase != phase) return;
  // A death by signal in every build: a sanitizer's SIGSEGV handler would otherwise turn it into
  // a report and exit status 1.
  if (fault->kind == "crash") {
    std::signal(SIGSEGV, SIG_DFL);
    std::raise(SIGSEGV);
  }
  // Sleeps until killed, like a wait on a driver that never signals: the watchdog's SIGKILL of
  // the process group ends it.
  if (fault->kind == "hang")
    for (;;) ::pause();
  if (fault->kind == "throw")
    throw std::runtime_error(fmt::format("injected fault: throw in {}", phase));
}

class GuardedStrategy final : public Strategy {
 public:
  explicit GuardedStrategy(std::unique_ptr<Strategy> inner) : inner_(std::move(inner)) {}

  std::string_view name() const override { return inner_->name(); }
  Capabilities capabilities() const override { return inner_->capabilities(); }
  DeviceInfo device() const override { return inner_->device(); }
  DeviceTimes device_times() const override { return inner_->device_times(); }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    enter("prepare");
    inner_->prepare(scene, request);
  }
  void evaluate() override {
    enter("evaluate");
    inner_->evaluate();
  }
  EvalResult read_back() override {
    EvalResult result;
    read_back_into(result);
    return result;
  }
  // Forwarded as read_back_into, so the inner strategy reuses the harness's buffers.
  void read_back_into(EvalResult& result) override {
    enter("read_back");
    inner_->read_back_into(result);
    const auto& fault = injected_fault();
    if (fault && fault->kind == "nan" && fault->strategy == name())
      for (SurfaceResult& s : result.surfaces) {
        PointArray poisoned(s.positions.precision(), s.positions.size());
        for (std::size_t k = 0; k < poisoned.size(); ++k)
          poisoned.set(k, std::array<double, 3>{std::numeric_limits<double>::quiet_NaN(),
                                                std::numeric_limits<double>::quiet_NaN(),
                                                std::numeric_limits<double>::quiet_NaN()});
        s.positions = std::move(poisoned);
      }
  }
  void update_control_points(const Scene& scene) override {
    enter("update");
    inner_->update_control_points(scene);
  }
  bool render() override {
    enter("render");
    return inner_->render();
  }
  bool render_via_read_back() override {
    enter("render");
    return inner_->render_via_read_back();
  }
  bool classify() override {
    enter("classify");
    return inner_->classify();
  }
  // Reading the picture back is a driver call like drawing it: a crash there is the render's.
  std::optional<RenderedImage> last_render() override {
    enter("render");
    return inner_->last_render();
  }

 private:
  void enter(std::string_view phase) {
    announce_phase(phase);
    inject(inner_->name(), phase);
  }
  std::unique_ptr<Strategy> inner_;
};

}  // namespace

void announce_phase(std::string_view phase) {
  const std::size_t n = std::min(phase.size(), kBoardSize - 1);
  std::memcpy(board, phase.data(), n);
  board[n] = '\0';
}

std::string current_phase() {
  return std::string(board, ::strnlen(board, kBoardSize));
}

void share_phase_board(const std::filesystem::path& file) {
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0 || ::ftruncate(fd, kBoardSize) != 0)
    throw std::runtime_error(fmt::format("{}: cannot create the phase board", file.string()));
  void* shared = ::mmap(nullptr, kBoardSize, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ::close(fd);
  if (shared == MAP_FAILED)
    throw std::runtime_error(fmt::format("{}: cannot map the phase board", file.string()));
  std::memcpy(shared, board, kBoardSize);
  board = static_cast<char*>(shared);
}

std::string read_phase_board(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::array<char, kBoardSize> text{};
  in.read(text.data(), kBoardSize);
  return std::string(text.data(), ::strnlen(text.data(), static_cast<std::size_t>(in.gcount())));
}

const std::optional<InjectedFault>& injected_fault() {
  static const std::optional<InjectedFault> fault = [] {
    const char* text = std::getenv(std::string(kFaultVariable).c_str());
    return parse_fault(text ? text : "");
  }();
  return fault;
}

std::unique_ptr<Strategy> create_guarded(const StrategyEntry& entry,
                                         const StrategyOptions& options) {
  announce_phase("setup");
  inject(entry.name, "setup");
  return std::make_unique<GuardedStrategy>(entry.create(options));
}

}  // namespace nurbs
