// The parts of process isolation that need no child process: the raw result across the process
// boundary, the status codes in records, summary counts and gates, the phase board, and a device
// wait that expires inside a strategy (harness/isolation.h, harness/strategy_guard.h,
// strategies/device_wait.h).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "harness/gates.h"
#include "harness/isolation.h"
#include "harness/record.h"
#include "harness/results_writer.h"
#include "harness/runner.h"
#include "harness/strategy_guard.h"
#include "harness/summary_table.h"
#include "scenes/builtin_scenes.h"
#include "strategies/device_wait.h"

namespace nurbs {
namespace {

namespace fs = std::filesystem;

class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_(fs::temp_directory_path() / fmt::format("{}-{}", name, ::getpid())) {}
  ~TempFile() { fs::remove(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Positions, normals and inside masks come back bit for bit, in their own precision, for tensor
// and list samples; NaN included (a broken strategy's output is scored, not lost).
TEST(ResultTransfer, RoundTripIsExact) {
  EvalResult in;
  SurfaceResult tensor;
  tensor.samples = {true, {0.0, 0.1, 1.0 / 3.0}, {0.25, 1.0}};
  tensor.positions = PointArray(Precision::f32, 6);
  for (std::size_t k = 0; k < 6; ++k)
    tensor.positions.set(k, std::array<double, 3>{k * 0.1, -1.0 / (k + 1), 1e30});
  tensor.positions.f32()[4] = std::numeric_limits<float>::quiet_NaN();
  tensor.inside = {1, 0, 1, 1, 0, 0};
  SurfaceResult list;
  list.samples = {false, {0.5, 0.75}, {0.125, std::nextafter(1.0, 0.0)}};
  list.positions = PointArray(Precision::f64, 2);
  list.normals = PointArray(Precision::f64, 2);
  for (std::size_t k = 0; k < 2; ++k) {
    list.positions.set(k, std::array<double, 3>{std::sqrt(2.0) * k, 1e-300, -0.0});
    list.normals.set(k, std::array<double, 3>{0, 0, 1});
  }
  in.surfaces = {tensor, list};

  TempFile file("nurbsbench-result");
  write_eval_result(file.path(), in);
  const EvalResult out = read_eval_result(file.path());
  ASSERT_EQ(out.surfaces.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const SurfaceResult &a = in.surfaces[i], &b = out.surfaces[i];
    EXPECT_EQ(a.samples.tensor, b.samples.tensor);
    EXPECT_EQ(a.samples.u, b.samples.u);
    EXPECT_EQ(a.samples.v, b.samples.v);
    EXPECT_EQ(a.inside, b.inside);
    ASSERT_EQ(a.positions.precision(), b.positions.precision());
    ASSERT_EQ(a.positions.size(), b.positions.size());
    ASSERT_EQ(a.normals.size(), b.normals.size());
    const std::size_t bytes =
        a.positions.size() * 3 * (a.positions.precision() == Precision::f32 ? 4 : 8);
    const void* pa = a.positions.precision() == Precision::f32
                         ? static_cast<const void*>(a.positions.f32())
                         : a.positions.f64();
    const void* pb = b.positions.precision() == Precision::f32
                         ? static_cast<const void*>(b.positions.f32())
                         : b.positions.f64();
    EXPECT_EQ(std::memcmp(pa, pb, bytes), 0) << "surface " << i;
  }
  EXPECT_EQ(out.surfaces[1].normals[1][2], 1.0);
  EXPECT_TRUE(std::isnan(out.surfaces[0].positions[1][1]));
  EXPECT_EQ(out.surfaces[0].positions[5][2], static_cast<double>(1e30f));
}

TEST(ResultTransfer, TruncatedOrForeignFilesAreErrors) {
  EvalResult in;
  in.surfaces.resize(1);
  in.surfaces[0].samples = {true, {0, 1}, {0, 1}};
  in.surfaces[0].positions = PointArray(Precision::f32, 4);
  TempFile file("nurbsbench-result");
  write_eval_result(file.path(), in);
  const auto size = fs::file_size(file.path());
  fs::resize_file(file.path(), size - 1);
  EXPECT_THROW(read_eval_result(file.path()), std::runtime_error);
  { std::ofstream(file.path()) << "not a result"; }
  EXPECT_THROW(read_eval_result(file.path()), std::runtime_error);
}

Record record_of(const std::string& strategy, Status status, const std::string& reason) {
  Record r;
  r.scene = "patch144";
  r.strategy = strategy;
  r.precision = "f32";
  r.samples = "16x16";
  r.status = status;
  r.reason = reason;
  if (status == Status::ok) r.accuracy = Accuracy{};
  return r;
}

// The record strings are exactly the CTS-ordered names, and the order is the enum's.
TEST(Status, NamesInCtsOrderRoundTrip) {
  const std::vector<std::string> names = {
      "ok", "refused", "unavailable", "failed", "out_of_memory", "crashed", "timed_out"};
  ASSERT_EQ(std::size(kAllStatuses), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(to_string(kAllStatuses[k]), names[k]);
    EXPECT_EQ(static_cast<std::size_t>(kAllStatuses[k]), k);
    const Record r = record_of("x", kAllStatuses[k], "why");
    EXPECT_EQ(record_from_json(record_to_json(r)).status, kAllStatuses[k]);
    EXPECT_EQ(record_to_json(r)["status"], names[k]);
  }
  Status s = Status::ok;
  EXPECT_FALSE(parse_status("crash", s));
}

// Results written before isolation existed still read, every status as it was written.
TEST(Status, CommittedResultsStillParse) {
  const ResultsFile file =
      read_results(fs::path(NURBSBENCH_SOURCE_DIR) / "results/canonical/accuracy");
  ASSERT_FALSE(file.records.empty());
  const nlohmann::json raw = nlohmann::json::parse(
      std::ifstream(fs::path(NURBSBENCH_SOURCE_DIR) / "results/canonical/accuracy/results.json"));
  ASSERT_EQ(raw["records"].size(), file.records.size());
  for (std::size_t k = 0; k < file.records.size(); ++k)
    EXPECT_EQ(to_string(file.records[k].status), raw["records"][k]["status"].get<std::string>());
}

TEST(StatusCounts, EveryStatusPresentInOrder) {
  const std::vector<Record> records = {
      record_of("a", Status::timed_out, ""), record_of("b", Status::ok, ""),
      record_of("c", Status::crashed, ""), record_of("d", Status::ok, ""),
      record_of("e", Status::refused, "")};
  EXPECT_EQ(status_counts(records), "statuses: 2 ok, 1 refused, 1 crashed, 1 timed_out\n");
  EXPECT_EQ(status_counts({}), "statuses: none\n");
}

TEST(Gates, CrashedAndTimedOutViolateEveryGateThatMatchesThem) {
  const std::vector<Record> records = {
      record_of("cpu-a", Status::ok, ""),
      record_of("cpu-b", Status::crashed, "SIGSEGV (Segmentation fault) in evaluate"),
      record_of("cpu-c", Status::timed_out, "no answer within 2 s (--timeout) in read_back")};
  const std::vector<std::string> violations =
      check_gates({{"cpu-*", "*", "max_ulp", 1}, {"cpu-c", "patch144", "max_abs", 1}}, records);
  ASSERT_EQ(violations.size(), 3u);
  EXPECT_NE(violations[0].find("cpu-b on patch144 (f32, 16x16): max_ulp <= 1 not measured: "
                               "crashed: SIGSEGV (Segmentation fault) in evaluate"),
            std::string::npos)
      << violations[0];
  EXPECT_NE(violations[1].find("cpu-c on patch144 (f32, 16x16): max_ulp <= 1 not measured: "
                               "timed_out: no answer within 2 s"),
            std::string::npos)
      << violations[1];
  EXPECT_NE(violations[2].find("cpu-c on patch144"), std::string::npos) << violations[2];
  EXPECT_TRUE(check_gates({{"cpu-a", "*", "max_ulp", 1}}, records).empty());
}

TEST(PhaseBoard, SharedFileHoldsTheLastPhase) {
  TempFile file("nurbsbench-phase");
  announce_phase("probe");
  share_phase_board(file.path());
  EXPECT_EQ(read_phase_board(file.path()), "probe") << "carried over when shared";
  announce_phase("evaluate");
  EXPECT_EQ(current_phase(), "evaluate");
  EXPECT_EQ(read_phase_board(file.path()), "evaluate");
  announce_phase(std::string(200, 'x'));  // cut, never overrun
  EXPECT_EQ(read_phase_board(file.path()), std::string(63, 'x'));
}

// A strategy whose device never answers: its bounded wait throws DeviceTimeout, which the runner
// records as timed_out naming the phase, like the watchdog would, but without losing the process.
class LostDevice final : public Strategy {
 public:
  std::string_view name() const override { return "lost-device"; }
  Capabilities capabilities() const override { return {}; }
  DeviceInfo device() const override { return {"test", "gpu", {}}; }
  void prepare_checked(const Scene&, const EvalRequest&) override {}
  void evaluate() override { throw device_timeout("vkWaitForFences"); }
  EvalResult read_back() override { return {}; }
};

TEST(DeviceWait, ExpiredWaitIsTimedOutInItsPhase) {
  const double saved = device_wait_limit_s();
  device_wait_limit_s() = 2.5;
  const StrategyEntry entry{"lost-device",
                            "test",
                            "strategy",
                            [] {
                              return Availability{true, ""};
                            },
                            [] { return Capabilities{}; },
                            [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
                              return std::make_unique<LostDevice>();
                            }};
  ReferenceCache references;
  const Record r = measure(entry, {}, *make_builtin_scene("patch144"),
                           EvalRequest{Sampling{}, Precision::f32, false}, 1, references);
  device_wait_limit_s() = saved;
  EXPECT_EQ(r.status, Status::timed_out);
  EXPECT_EQ(r.reason, "in evaluate: vkWaitForFences: the device did not answer within 2.5 s");
  EXPECT_EQ(device_wait_limit_ns(), 60'000'000'000u);
}

}  // namespace
}  // namespace nurbs
