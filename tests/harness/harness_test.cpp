// Metrics, timing statistics, records and gates, on hand-made inputs whose answers are known.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cfloat>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include "harness/atomic_file.h"
#include "harness/gates.h"
#include "harness/metrics.h"
#include "harness/progress.h"
#include "harness/record.h"
#include "harness/results_writer.h"
#include "harness/runner.h"
#include "harness/store_limit.h"
#include "harness/summary_table.h"
#include "harness/timing.h"
#include "scenes/builtin_scenes.h"
#include "tests/harness/plates.h"

namespace nurbs {
namespace {

// A scene of one bilinear patch with corners at (0,0,0)..(3,4,0): largest coordinate 4,
// bounding-box diagonal 5.
Scene flat_scene() {
  return Scene{
      "flat", "", {test::bilinear_patch("flat", {0, 0, 0}, {0, 4, 0}, {3, 0, 0}, {3, 4, 0})}};
}

EvalResult result_with(const std::vector<Point3>& points, Precision precision) {
  EvalResult r;
  r.surfaces.resize(1);
  r.surfaces[0].samples.tensor = false;
  r.surfaces[0].positions = PointArray(precision, points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    r.surfaces[0].samples.u.push_back(0.25 * k);
    r.surfaces[0].samples.v.push_back(0.5);
    r.surfaces[0].positions.set(k, points[k]);
  }
  return r;
}

TEST(Metrics, KnownErrors) {
  const Scene scene = flat_scene();
  std::vector<ReferenceSurface> reference(1);
  reference[0].positions = {{0, 0, 0}, {1, 1, 0}, {2, 2, 0}};
  // errors 0, 0.3 (along x), 0.4 (along z)
  const EvalResult result = result_with({{0, 0, 0}, {1.3, 1, 0}, {2, 2, 0.4}}, Precision::f64);
  const Accuracy acc = measure_accuracy(scene, result, reference);
  EXPECT_NEAR(acc.max_abs, 0.4, 1e-15);
  EXPECT_NEAR(acc.rms_abs, std::sqrt((0.09 + 0.16) / 3), 1e-15);
  EXPECT_NEAR(acc.max_rel, 0.4 / 5, 1e-15);
  EXPECT_NEAR(acc.max_ulp, 0.4 / (FLT_EPSILON * 4), 1e-6);
  EXPECT_EQ(acc.worst_surface, 0);
  EXPECT_EQ(acc.worst_u, 0.5);
  EXPECT_EQ(acc.non_finite, 0u);
}

TEST(Metrics, NaNIsTheWorstError) {
  const Scene scene = flat_scene();
  std::vector<ReferenceSurface> reference(1);
  reference[0].positions = {{0, 0, 0}, {1, 1, 0}, {2, 2, 0}};
  const EvalResult result = result_with({{0, 0, 0.1}, {NAN, 1, 0}, {2, 2, 0.2}}, Precision::f32);
  const Accuracy acc = measure_accuracy(scene, result, reference);
  EXPECT_TRUE(std::isinf(acc.max_abs));
  EXPECT_EQ(acc.non_finite, 1u);
  EXPECT_EQ(acc.worst_u, 0.25);
}

TEST(Metrics, NormalAngles) {
  const Scene scene = flat_scene();
  std::vector<ReferenceSurface> reference(1);
  reference[0].positions = {{0, 0, 0}, {1, 1, 0}};
  reference[0].normals = {{0, 0, 1}, {0, 0, 1}};
  EvalResult result = result_with({{0, 0, 0}, {1, 1, 0}}, Precision::f64);
  result.surfaces[0].normals = PointArray(Precision::f64, 2);
  result.surfaces[0].normals.set(0, std::array<double, 3>{0, 0, 1});
  const double a = 1e-7;  // radians: atan2-based angle must resolve it, acos would not
  result.surfaces[0].normals.set(1, std::array<double, 3>{std::sin(a), 0, std::cos(a)});
  const Accuracy acc = measure_accuracy(scene, result, reference);
  ASSERT_TRUE(acc.max_normal_angle_deg);
  EXPECT_NEAR(*acc.max_normal_angle_deg, a * 180 / M_PI, 1e-15);
}

// A NaN normal beside a right position is a failed sample too (a zero-length normal normalised).
TEST(Metrics, NaNNormalIsNonFinite) {
  const Scene scene = flat_scene();
  std::vector<ReferenceSurface> reference(1);
  reference[0].positions = {{0, 0, 0}, {1, 1, 0}};
  reference[0].normals = {{0, 0, 1}, {0, 0, 1}};
  EvalResult result = result_with({{0, 0, 0}, {1, 1, 0}}, Precision::f32);
  result.surfaces[0].normals = PointArray(Precision::f32, 2);
  result.surfaces[0].normals.set(0, std::array<double, 3>{0, 0, 1});
  result.surfaces[0].normals.set(1, std::array<double, 3>{NAN, NAN, NAN});
  const Accuracy acc = measure_accuracy(scene, result, reference);
  EXPECT_EQ(acc.max_abs, 0);
  EXPECT_EQ(acc.non_finite, 1u);
  EXPECT_EQ(acc.first_non_finite.surface, 0);
  EXPECT_EQ(acc.first_non_finite.u, result.surfaces[0].samples.u_of(1));
  EXPECT_EQ(non_finite_failure(acc, 2),
            fmt::format("1 of 2 samples are not finite (NaN/Inf position or normal); the first at "
                        "surface 0 (u, v) = ({:.17g}, {:.17g})",
                        result.surfaces[0].samples.u_of(1), result.surfaces[0].samples.v_of(1)));
  EXPECT_EQ(
      non_finite_failure(
          measure_accuracy(scene, result_with({{0, 0, 0}, {1, 1, 0}}, Precision::f32), reference),
          2),
      "");
}

TEST(Timing, MedianMinMax) {
  const PhaseStats odd = PhaseStats::of({3, 1, 2});
  EXPECT_EQ(odd.min_s, 1);
  EXPECT_EQ(odd.median_s, 2);
  EXPECT_EQ(odd.max_s, 3);
  EXPECT_EQ(PhaseStats::of({4, 1, 2, 3}).median_s, 2.5);
}

Record sample_record() {
  Record r;
  r.scene = "patch144";
  r.strategy = "cpu-coxdeboor";
  r.role = "strategy";
  r.device = {"host CPU, 1 thread", "cpu", {{"threads", "1"}}};
  r.precision = "f32";
  r.sampling = "grid";
  r.samples = "64x64";
  r.points = 4096;
  r.evaluate = {0.1, 0.2, 0.3};
  r.throughput_pts_per_s = 4096 / 0.2;
  r.accuracy = Accuracy{};
  r.accuracy->max_ulp = 1.5;
  r.accuracy->max_normal_angle_deg = 0.01;
  r.reason = "a, \"quoted\" reason";
  return r;
}

TEST(Record, JsonRoundTrip) {
  const Record r = sample_record();
  const Record back = record_from_json(nlohmann::json::parse(record_to_json(r).dump()));
  EXPECT_EQ(back.scene, r.scene);
  EXPECT_EQ(back.device.details, r.device.details);
  EXPECT_EQ(back.evaluate.median_s, 0.2);
  ASSERT_TRUE(back.accuracy);
  EXPECT_EQ(back.accuracy->max_ulp, 1.5);
  EXPECT_EQ(back.accuracy->max_normal_angle_deg, 0.01);
  EXPECT_EQ(back.reason, r.reason);
}

TEST(Record, ExtraPhasesFiguresAndMissingAccuracyRoundTrip) {
  Record r = sample_record();
  r.extra_phases["render"] = {0.5, 0.75, 1.0};
  r.figures["store_bytes_per_s"] = 1.25e10;
  r.accuracy.reset();
  const nlohmann::json j = record_to_json(r);
  EXPECT_TRUE(j["accuracy"].is_null());
  const Record back = record_from_json(nlohmann::json::parse(j.dump()));
  EXPECT_FALSE(back.accuracy);
  ASSERT_EQ(back.extra_phases.count("render"), 1u);
  EXPECT_EQ(back.extra_phases.at("render").median_s, 0.75);
  EXPECT_EQ(back.figures.at("store_bytes_per_s"), 1.25e10);
  // No accuracy: the CSV's four accuracy cells are empty, the row keeps its columns.
  const std::string row = csv_row(r);
  EXPECT_NE(row.find(",,,,ok,"), std::string::npos) << row;
}

TEST(Record, InfiniteErrorsSurviveJson) {
  Record r = sample_record();
  r.accuracy->max_abs = r.accuracy->max_ulp = INFINITY;
  const Record back = record_from_json(nlohmann::json::parse(record_to_json(r).dump()));
  EXPECT_TRUE(std::isinf(back.accuracy->max_ulp));
}

// The writer serialises each record once and splices the texts into the document; the file must
// be what dumping the whole document gives (what it wrote before, and what readers expect), for
// no record, one, and several with nested, empty and multi-line values.
TEST(ResultsWriter, WritesWhatDumpingTheWholeDocumentWrites) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("nb-writer-{}", ::getpid());
  std::filesystem::remove_all(dir);
  const nlohmann::json machine = {{"cpu_model", "Test CPU"}, {"records", "not the array"}};
  const nlohmann::json settings = {{"scenes", {"patch144"}}, {"empty", nlohmann::json::object()}};
  ResultsWriter writer(dir, machine, settings);
  std::vector<Record> records;
  const auto expected = [&] {
    nlohmann::json document = {{"format", kResultsFormat},
                               {"machine", machine},
                               {"settings", settings},
                               {"records", nlohmann::json::array()}};
    for (const Record& r : records) document["records"].push_back(record_to_json(r));
    return document.dump(1) + "\n";
  };
  const auto written = [&] {
    std::ifstream in(dir / "results.json");
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(written(), expected());
  Record first = sample_record();
  first.reason = "two\nlines, \"quoted\"";
  Record second = sample_record();
  second.extra_phases["render"] = {0.5, 0.75, 1.0};
  second.figures["store_bytes_per_s"] = 1.25e10;
  second.device.details.clear();
  Record third = sample_record();
  third.accuracy.reset();
  for (const Record& r : {first, second, third}) {
    records.push_back(r);
    writer.append(r);
    EXPECT_EQ(written(), expected()) << records.size() << " records";
  }
  EXPECT_EQ(read_results(dir).records.size(), 3u);
  std::filesystem::remove_all(dir);
}

TEST(Record, CsvHasTheIssueColumnsAndQuotes) {
  const std::string header = csv_header();
  EXPECT_EQ(header,
            "scene,strategy,device,precision,sampling,samples,points,setup_s,upload_median_s,"
            "evaluate_min_s,evaluate_median_s,evaluate_max_s,readback_median_s,end_to_end_median_s,"
            "throughput_pts_per_s,max_abs,rms_abs,max_rel,max_ulp,status,reason,trimming,trim_band,"
            "trim_inside_samples,trim_boundary_samples,trim_misclassified,trim_misclassified_rate");
  const std::string row = csv_row(sample_record());
  EXPECT_NE(row.find("\"a, \"\"quoted\"\" reason\""), std::string::npos) << row;
  EXPECT_NE(row.find(",ok,"), std::string::npos);
}

TEST(Gates, ViolationsAreListedWithValues) {
  std::vector<Record> records = {sample_record(), sample_record()};
  records[1].scene = "sphere";
  records[1].accuracy->max_ulp = 40;
  Record failed = sample_record();
  failed.strategy = "gl-pingpong";
  failed.status = Status::failed;
  failed.reason = "shader did not compile";
  records.push_back(failed);
  Record refused = sample_record();
  refused.strategy = "gl-pingpong";
  refused.scene = "degree-12";
  refused.status = Status::refused;
  records.push_back(refused);

  EXPECT_TRUE(check_gates({{"cpu-*", "patch*", "max_ulp", 2}}, records).empty());
  const auto over = check_gates({{"cpu-coxdeboor", "*", "max_ulp", 32}}, records);
  ASSERT_EQ(over.size(), 1u);
  EXPECT_NE(over[0].find("sphere"), std::string::npos);
  EXPECT_NE(over[0].find("40"), std::string::npos);
  const auto failed_gate = check_gates({{"gl-pingpong", "patch144", "max_ulp", 64}}, records);
  ASSERT_EQ(failed_gate.size(), 1u);
  EXPECT_NE(failed_gate[0].find("shader did not compile"), std::string::npos);
  EXPECT_EQ(check_gates({{"gl-pingpong", "degree-12", "max_ulp", 64}}, records).size(), 1u)
      << "a gate matching only refusals matches nothing measured";
  EXPECT_EQ(check_gates({{"nothing", "*", "max_ulp", 1}}, records).size(), 1u);
  EXPECT_EQ(check_gates({{"*", "*", "max_normal_angle_deg", 1}}, {sample_record()}).size(), 0u);
}

TEST(Gates, LimitRowsAreNotGatedAndMissingAccuracyIsAViolation) {
  Record limit = sample_record();
  limit.strategy = "limit-store-bandwidth";
  limit.role = "limit";
  limit.accuracy.reset();
  // A wildcard gate sees the strategy's row and skips the limit row.
  EXPECT_TRUE(check_gates({{"*", "*", "max_ulp", 2}}, {sample_record(), limit}).empty());
  EXPECT_EQ(check_gates({{"limit-*", "*", "max_ulp", 2}}, {limit}).size(), 1u)
      << "a gate matching only a limit row matches nothing measured";
  Record unmeasured = sample_record();
  unmeasured.accuracy.reset();
  const auto violations = check_gates({{"*", "*", "max_ulp", 2}}, {unmeasured});
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_NE(violations[0].find("no accuracy"), std::string::npos) << violations[0];
}

TEST(Gates, PassingNeedsAnApplicableGateHeldByAMeasurement) {
  const std::vector<Gate> gates = {{"cpu-*", "*", "max_ulp", 2},
                                   {"cpu-*", "*", "trim_misclassified_rate", 0}};
  EXPECT_TRUE(passes_gates(gates, sample_record()))
      << "the trim gate does not apply to an untrimmed scene";
  Record over = sample_record();
  over.accuracy->max_ulp = 3;
  EXPECT_FALSE(passes_gates(gates, over));
  Record ungated = sample_record();
  ungated.strategy = "gl-pingpong";
  EXPECT_FALSE(passes_gates(gates, ungated)) << "no gate covers it: it passed none";
  Record refused = sample_record();
  refused.status = Status::refused;
  EXPECT_FALSE(passes_gates(gates, refused));
  Record misclassifying = sample_record();
  misclassifying.trimming = "classified";
  misclassifying.accuracy->trim = TrimAccuracy{};
  misclassifying.accuracy->trim->misclassified = 3;
  misclassifying.accuracy->trim->misclassified_rate = 0.01;
  EXPECT_FALSE(passes_gates(gates, misclassifying));
}

// A record of `strategy` on `scene` at 64x64 f32 with `points_per_s` and max_ulp `ulp`, on the
// host CPU.
Record digest_record(const std::string& strategy, const std::string& scene, double points_per_s,
                     double ulp = 1) {
  Record r = sample_record();
  r.strategy = strategy;
  r.scene = scene;
  r.throughput_pts_per_s = points_per_s;
  r.accuracy->max_ulp = ulp;
  r.device = {"host CPU", "cpu", {}};
  return r;
}

const std::vector<Gate> kDigestGates = {{"*", "*", "max_ulp", 32}};

TEST(SummaryDigest, FastestWithinItsGatesOverTheBaseline) {
  Record gl = digest_record("gl-pingpong", "patch144", 8e6);
  gl.device = {"llvmpipe (LLVM 15.0.6, 256 bits)", "cpu", {}};
  Record limit = digest_record(std::string(kStoreLimitName), "patch144", 1e12);
  limit.role = "limit";
  limit.accuracy.reset();
  const std::vector<std::string> lines = summary_digest(
      {limit, digest_record("cpu-coxdeboor", "patch144", 2e6),
       digest_record("cpu-tensor", "patch144", 1e9, 40),  // fastest, but over its gate
       digest_record("cpu-bezier", "patch144", 5e6), gl},
      kDigestGates);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0],
            "digest: per scene, the fastest strategy within its accuracy gates, evaluate "
            "throughput over cpu-coxdeboor (cpu-tspline on T-spline scenes) at the same "
            "precision:");
  EXPECT_EQ(lines[1],
            "  patch144 64x64: gl-pingpong f32: 4x cpu-coxdeboor, CPU figure (llvmpipe (LLVM "
            "15.0.6, 256 bits))");
}

TEST(SummaryDigest, FailedAndUngatedRecordsAreSkippedAndGpuFiguresSaySo) {
  Record failed = digest_record("cpu-horner", "sphere", 1e9);
  failed.status = Status::failed;
  Record gpu = digest_record("vk-ksquad", "sphere", 3e6);
  gpu.device = {"Some GPU", "gpu", {}};
  const std::vector<std::string> lines =
      summary_digest({digest_record("cpu-coxdeboor", "sphere", 1e6), failed, gpu,
                      digest_record("cpu-bezier", "sphere", 1e8)},
                     {{"cpu-coxdeboor", "*", "max_ulp", 32}, {"vk-*", "*", "max_ulp", 32}});
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1], "  sphere 64x64: vk-ksquad f32: 3x cpu-coxdeboor, GPU (Some GPU)");
}

// A T-spline scene has no cpu-coxdeboor record: cpu-tspline is the baseline there.
TEST(SummaryDigest, TSplineScenesAreMeasuredOverCpuTSpline) {
  const std::vector<std::string> lines =
      summary_digest({digest_record("cpu-tspline", "tsm-fan", 1e6),
                      digest_record("cl-tspline-bezier", "tsm-fan", 3e7),
                      digest_record("cpu-coxdeboor", "patch144", 1e6),
                      digest_record("cpu-tspline", "patch144", 9e6)},
                     kDigestGates);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[1],
            "  tsm-fan 64x64: cl-tspline-bezier f32: 30x cpu-tspline, CPU figure (host CPU)");
  // cpu-coxdeboor stays the baseline wherever it was measured.
  EXPECT_EQ(lines[2], "  patch144 64x64: cpu-tspline f32: 9x cpu-coxdeboor, CPU figure (host CPU)");
}

TEST(SummaryDigest, SceneWithoutTheBaselineSaysSo) {
  Record failed_baseline = digest_record("cpu-coxdeboor", "duck", 1e6);
  failed_baseline.status = Status::crashed;
  const std::vector<std::string> lines = summary_digest(
      {digest_record("cpu-coxdeboor", "patch144", 1e6), digest_record("cpu-tensor", "teapot", 2e6),
       failed_baseline, digest_record("cpu-tensor", "duck", 3e6),
       digest_record("cpu-tensor", "torus", 3e6, 99)},
      kDigestGates);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[1],
            "  patch144 64x64: cpu-coxdeboor f32: 1x cpu-coxdeboor, CPU figure (host CPU)");
  EXPECT_EQ(lines[2],
            "  teapot 64x64: cpu-tensor f32: 2e+06 points/s, no cpu-coxdeboor baseline, CPU figure "
            "(host CPU)");
  EXPECT_EQ(lines[3],
            "  duck 64x64: cpu-tensor f32: 3e+06 points/s, no cpu-coxdeboor baseline, CPU figure "
            "(host CPU)");
  EXPECT_EQ(lines[4], "  torus 64x64: no strategy within its accuracy gates");
}

TEST(SummaryDigest, TiesNameEveryFastest) {
  const std::vector<std::string> lines = summary_digest(
      {digest_record("cpu-coxdeboor", "patch144", 1e6),
       digest_record("cpu-tensor", "patch144", 5e6), digest_record("cpu-bezier", "patch144", 5e6),
       digest_record("cpu-horner", "patch144", 4e6)},
      kDigestGates);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1],
            "  patch144 64x64: tie: cpu-tensor f32: 5x cpu-coxdeboor, CPU figure (host CPU); "
            "cpu-bezier f32: 5x cpu-coxdeboor, CPU figure (host CPU)");
}

TEST(SummaryDigest, BestOverBothPrecisionsAgainstTheSamePrecisionsBaseline) {
  auto f64 = [](Record r) {
    r.precision = "f64";
    return r;
  };
  const std::vector<std::string> lines =
      summary_digest({digest_record("cpu-coxdeboor", "patch144", 4e6),
                      f64(digest_record("cpu-coxdeboor", "patch144", 1e6)),
                      digest_record("cpu-tensor", "patch144", 6e6),
                      f64(digest_record("cpu-tensor", "patch144", 8e6))},
                     kDigestGates);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[0].find("(best of f32, f64)"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[1], "  patch144 64x64: cpu-tensor f64: 8x cpu-coxdeboor, CPU figure (host CPU)");
}

TEST(StoreLimit, RowDescribesTheRequestsOutputStream) {
  const Scene scene = *make_builtin_scene("many-4");
  Sampling grid;
  grid.grid_u = 32;
  grid.grid_v = 16;
  for (const auto& [precision, normals, bytes] :
       {std::tuple{Precision::f32, false, 12}, std::tuple{Precision::f32, true, 24},
        std::tuple{Precision::f64, false, 24}, std::tuple{Precision::f64, true, 48}}) {
    const EvalRequest request{grid, precision, normals};
    EXPECT_EQ(result_bytes_per_point(request), static_cast<std::size_t>(bytes));
    const Record r = measure_store_limit(scene, request, 1);
    EXPECT_EQ(r.status, Status::ok);
    EXPECT_EQ(r.role, "limit");
    EXPECT_FALSE(r.accuracy);
    EXPECT_EQ(r.points, 4u * 32 * 16);
    EXPECT_EQ(r.samples, "32x16");
    EXPECT_LE(r.evaluate.min_s, r.evaluate.median_s);
    EXPECT_GT(r.evaluate.min_s, 0.0);
    EXPECT_DOUBLE_EQ(r.throughput_pts_per_s, r.points / r.evaluate.median_s);
    EXPECT_DOUBLE_EQ(r.figures.at("store_bytes_per_s"), bytes * r.throughput_pts_per_s);
    // 32x16 points write a few KiB; the pass still goes through memory (issue 30).
    EXPECT_EQ(r.figures.at("pass_bytes"), static_cast<double>(store_pass_bytes(r.points * bytes)));
  }
}

// The pass is never cache-sized: at least 64 MiB and 4x the last-level cache when one is known
// (at most 128 MiB of that floor), and the result itself when that is larger.
TEST(StoreLimit, PassIsLargerThanTheCacheOrTheResult) {
  const std::size_t floor = store_pass_bytes(0);
  EXPECT_GE(floor, std::size_t{64} << 20);
  EXPECT_LE(floor, std::size_t{128} << 20);
  EXPECT_GE(floor, std::min<std::size_t>(4 * last_level_cache_bytes(), std::size_t{128} << 20));
  EXPECT_EQ(store_pass_bytes(12), floor);
  EXPECT_EQ(store_pass_bytes(floor + 48), floor + 48);
}

TEST(StoreLimit, FractionOnlyFromAnOutputOfAtLeastTheStatedSize) {
  auto limit_row = [](std::size_t points, double bytes_per_point) {
    Record l;
    l.scene = "patch144";
    l.strategy = std::string(kStoreLimitName);
    l.role = "limit";
    l.precision = "f32";
    l.samples = "64x64";
    l.points = points;
    l.throughput_pts_per_s = 4e9;
    l.figures["bytes_per_point"] = bytes_per_point;
    return l;
  };
  Record strategy = sample_record();  // patch144, 64x64, f32
  strategy.throughput_pts_per_s = 1e9;
  // 64x64 f32 positions: 48 KiB.
  const std::vector<Record> small = {limit_row(4096, 12), strategy};
  EXPECT_FALSE(fraction_of_store_limit(strategy, small));
  EXPECT_TRUE(store_limit_too_small(strategy, small));
  // The stated size exactly, and one point under it.
  const std::size_t at = kStoreLimitMinBytes / 16;
  const std::vector<Record> enough = {limit_row(at, 16), strategy};
  ASSERT_TRUE(fraction_of_store_limit(strategy, enough));
  EXPECT_DOUBLE_EQ(*fraction_of_store_limit(strategy, enough), 0.25);
  EXPECT_FALSE(store_limit_too_small(strategy, enough));
  EXPECT_FALSE(fraction_of_store_limit(strategy, {limit_row(at - 1, 16), strategy}));
  // Not for the limit row itself, a failed record, or another request's limit.
  EXPECT_FALSE(fraction_of_store_limit(enough[0], enough));
  Record failed = strategy;
  failed.status = Status::failed;
  EXPECT_FALSE(fraction_of_store_limit(failed, {limit_row(at, 16), failed}));
  Record f64 = strategy;
  f64.precision = "f64";
  EXPECT_FALSE(fraction_of_store_limit(f64, {limit_row(at, 16), f64}));
  EXPECT_FALSE(store_limit_too_small(f64, {limit_row(4096, 12), f64}));
}

TEST(StoreLimit, StorePassWritesEveryValue) {
  std::vector<double> buffer(1000, 0.0);
  time_store_pass(buffer.data(), buffer.size(), sizeof(double), 6);
  for (double x : buffer) ASSERT_EQ(x, 7.0);
  std::vector<float> floats(999, 0.0f);
  time_store_pass(floats.data(), floats.size(), sizeof(float), 0);
  for (float x : floats) ASSERT_EQ(x, 1.0f);
}

TEST(AtomicFile, ReplacesWholeAndLeavesNoTemporary) {
  const auto dir = std::filesystem::temp_directory_path() / "nurbsbench_atomic_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_file_atomically(dir / "f.txt", "first");
  write_file_atomically(dir / "f.txt", "second");
  std::ifstream in(dir / "f.txt");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, "second");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  EXPECT_THROW(write_file_atomically(dir / "missing" / "f.txt", "x"), std::runtime_error);
  std::filesystem::remove_all(dir);
}

// A strategy that picks its own samples (as glu-nurbs does): three (u, v) per surface whatever
// grid is asked for, positions from the reference there (so correct to float rounding), or
// shifted by `offset` in x.
class OwnSamplesStrategy final : public Strategy {
 public:
  explicit OwnSamplesStrategy(double offset) : offset_(offset) {}
  std::string_view name() const override { return "own-samples"; }
  Capabilities capabilities() const override { return {}; }
  DeviceInfo device() const override { return {"test", "cpu", {}}; }
  void prepare_checked(const Scene& scene, const EvalRequest&) override {
    samples_.clear();
    for (const Surface& s : scene.surfaces)
      samples_.push_back({false,
                          {s.u_min(), 0.3 * s.u_min() + 0.7 * s.u_max(), s.u_max()},
                          {s.v_min(), 0.6 * s.v_min() + 0.4 * s.v_max(), s.v_max()}});
    reference_ = evaluate_reference(scene, samples_, false);
  }
  void evaluate() override {}
  EvalResult read_back() override {
    EvalResult out;
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      SurfaceResult r;
      r.samples = samples_[i];
      r.positions = PointArray(Precision::f32, samples_[i].count());
      for (std::size_t k = 0; k < r.positions.size(); ++k) {
        Point3 p = reference_[i].positions[k];
        p[0] += offset_;
        r.positions.set(k, p);
      }
      out.surfaces.push_back(std::move(r));
    }
    return out;
  }

 private:
  double offset_;
  std::vector<SurfaceSamples> samples_;
  std::vector<ReferenceSurface> reference_;
};

StrategyEntry own_samples_entry(bool declares_it, double offset) {
  Capabilities caps;
  caps.fp64 = false;
  caps.chooses_own_samples = declares_it;
  return {"own-samples",
          "test",
          "baseline",
          [] {
            return Availability{true, ""};
          },
          [caps] { return caps; },
          [offset](const StrategyOptions&) -> std::unique_ptr<Strategy> {
            return std::make_unique<OwnSamplesStrategy>(offset);
          }};
}

TEST(Runner, StrategyChoosingItsSamplesIsMeasuredWhereItSampled) {
  const Scene scene = *make_builtin_scene("many-16");
  Sampling grid;
  grid.grid_u = 9;
  grid.grid_v = 5;
  ReferenceCache references;
  const EvalRequest request{grid, Precision::f32, false};
  const Record exact = measure(own_samples_entry(true, 0.0), {}, scene, request, 2, references);
  ASSERT_EQ(exact.status, Status::ok) << exact.reason;
  EXPECT_EQ(exact.points, 3 * scene.surfaces.size());  // produced, not the 9x5 requested
  EXPECT_EQ(exact.samples, "9x5");
  EXPECT_LE(exact.accuracy->max_ulp, 1.0);  // float rounding of the reference's own values

  // An error at its samples is seen as such, at the sample where it is.
  const Record shifted = measure(own_samples_entry(true, 1e-3), {}, scene, request, 2, references);
  ASSERT_EQ(shifted.status, Status::ok) << shifted.reason;
  EXPECT_NEAR(shifted.accuracy->max_abs, 1e-3, 1e-6);
  const Surface& worst = scene.surfaces[shifted.accuracy->worst_surface];
  EXPECT_TRUE(shifted.accuracy->worst_u == worst.u_min() ||
              shifted.accuracy->worst_u == worst.u_max() ||
              shifted.accuracy->worst_u == 0.3 * worst.u_min() + 0.7 * worst.u_max());
}

TEST(Runner, OtherSamplesThanRequestedFailUnlessDeclared) {
  const Scene scene = *make_builtin_scene("many-16");
  ReferenceCache references;
  const Record r = measure(own_samples_entry(false, 0.0), {}, scene,
                           EvalRequest{Sampling{}, Precision::f32, false}, 1, references);
  EXPECT_EQ(r.status, Status::failed);
  EXPECT_NE(r.reason.find("requested samples"), std::string::npos) << r.reason;
}

// cpu-coxdeboor with a render path that only counts its draws.
class DrawingStrategy final : public Strategy {
 public:
  explicit DrawingStrategy(int& draws)
      : inner_(find_strategy("cpu-coxdeboor")->create({})), draws_(draws) {}
  std::string_view name() const override { return "drawing"; }
  Capabilities capabilities() const override { return inner_->capabilities(); }
  DeviceInfo device() const override { return inner_->device(); }
  void prepare_checked(const Scene& s, const EvalRequest& r) override { inner_->prepare(s, r); }
  void evaluate() override { inner_->evaluate(); }
  EvalResult read_back() override { return inner_->read_back(); }
  bool render() override { return ++draws_ > 0; }

 private:
  std::unique_ptr<Strategy> inner_;
  int& draws_;
};

TEST(Runner, RenderPhaseOnlyForStrategiesThatDraw) {
  const Scene scene = flat_scene();
  ReferenceCache references;
  const EvalRequest request{Sampling{}, Precision::f32, false};
  int draws = 0;
  StrategyEntry drawing = *find_strategy("cpu-coxdeboor");
  drawing.create = [&draws](const StrategyOptions&) -> std::unique_ptr<Strategy> {
    return std::make_unique<DrawingStrategy>(draws);
  };
  const Record r = measure(drawing, {}, scene, request, 3, references);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_EQ(draws, 1 + 3) << "one warm-up draw, then one per repetition";
  ASSERT_EQ(r.extra_phases.size(), 1u);
  EXPECT_EQ(r.extra_phases.count("render"), 1u);
  const Record plain = measure(*find_strategy("cpu-coxdeboor"), {}, scene, request, 3, references);
  EXPECT_TRUE(plain.extra_phases.empty());
}

TEST(Metrics, SameSamplesComparesLayoutAndValues) {
  const std::vector<SurfaceSamples> a = {{true, {0, 1}, {0, 0.5, 1}}};
  std::vector<SurfaceSamples> b = a;
  EXPECT_TRUE(same_samples(a, b));
  b[0].tensor = false;
  EXPECT_FALSE(same_samples(a, b));
  b = a;
  b[0].v[1] = std::nextafter(0.5, 1.0);
  EXPECT_FALSE(same_samples(a, b));
  EXPECT_FALSE(same_samples(a, {}));
}

// ------------------------------------------------------------------------------ progress line

TEST(RunProgress, LineCountsMeasurementsAndEstimatesTheRest) {
  using std::chrono::seconds;
  EXPECT_EQ(RunProgress::line(0, 4, "a on b (8x8)", seconds(0)), "[1/4] a on b (8x8), 0 s");
  // 2 done in 20 s: 10 s each, 2 left.
  EXPECT_EQ(RunProgress::line(2, 4, "x", seconds(20)), "[3/4] x, 20 s, about 20 s left");
  EXPECT_EQ(RunProgress::line(1, 3, "x", seconds(125)),
            "[2/3] x, 2 min 5 s, about 4 min 10 s left");
  EXPECT_EQ(RunProgress::duration_text(seconds(3 * 3600 + 120 + 7)), "3 h 2 min");
}

TEST(RunProgress, TerminalRedrawsOneLineALogGetsPlainLines) {
  std::ostringstream terminal;
  RunProgress redrawn(terminal, 2, true);
  redrawn.start("first");
  redrawn.start("second");
  redrawn.finish();
  EXPECT_EQ(terminal.str().find('\n'), std::string::npos) << terminal.str();
  EXPECT_NE(terminal.str().find("\r[2/2] second, "), std::string::npos) << terminal.str();
  EXPECT_TRUE(terminal.str().ends_with("\r\x1b[K"));

  std::ostringstream log;
  RunProgress every_time(log, 2, false, std::chrono::seconds(0));
  every_time.start("first");
  every_time.start("second");
  every_time.finish();
  EXPECT_EQ(log.str().find('\r'), std::string::npos) << log.str();
  EXPECT_TRUE(log.str().starts_with("[1/2] first, ")) << log.str();
  EXPECT_NE(log.str().find("\n[2/2] second, "), std::string::npos) << log.str();

  // A short run written to a log prints nothing: the first line is due after the interval.
  std::ostringstream quiet;
  RunProgress hourly(quiet, 2, false, std::chrono::hours(1));
  hourly.start("first");
  hourly.finish();
  EXPECT_EQ(quiet.str(), "");
}

// The summary table leaves out refusals by kind; they are told apart by the refusal's own text.
TEST(KindRefusal, OnlyTheSceneKindCounts) {
  const Scene nurbs_scene = *make_builtin_scene("patch144");
  const Scene tspline_scene = *make_builtin_scene("tspline-tjunction");
  const EvalRequest request{Sampling{}, Precision::f32, false};
  Capabilities nurbs_only;
  nurbs_only.max_degree = 1;  // patch144 is bicubic
  Capabilities tsplines_only = nurbs_only;
  tsplines_only.tspline = tsplines_only.tspline_only = true;
  tsplines_only.max_degree = 15;

  const auto tspline_met = refusal_reason(nurbs_only, tspline_scene, request);
  const auto nurbs_met = refusal_reason(tsplines_only, nurbs_scene, request);
  const auto degree = refusal_reason(nurbs_only, nurbs_scene, request);
  ASSERT_TRUE(tspline_met && nurbs_met && degree);
  EXPECT_TRUE(is_kind_refusal(*tspline_met)) << *tspline_met;
  EXPECT_TRUE(is_kind_refusal(*nurbs_met)) << *nurbs_met;
  EXPECT_FALSE(is_kind_refusal(*degree)) << *degree;
  EXPECT_FALSE(is_kind_refusal("normals not supported"));
}

// A strategy that accepts anything in its own prepare: the refusal it meets is the base class's.
class CountingPrepare final : public Strategy {
 public:
  explicit CountingPrepare(Capabilities caps) : caps_(caps) {}
  std::string_view name() const override { return "counting-prepare"; }
  Capabilities capabilities() const override { return caps_; }
  DeviceInfo device() const override { return {"test", "cpu", {}}; }
  void evaluate() override {}
  EvalResult read_back() override { return {}; }
  int prepared = 0;

 protected:
  void prepare_checked(const Scene&, const EvalRequest&) override { ++prepared; }

 private:
  Capabilities caps_;
};

TEST(StrategyPrepare, RefusesOutsideTheCapabilitiesBeforeTheStrategysOwnPrepare) {
  const Scene bicubic = *make_builtin_scene("patch144");
  const EvalRequest request{Sampling{}, Precision::f32, false};
  Capabilities linear_only;
  linear_only.max_degree = 1;
  CountingPrepare refusing(linear_only);
  try {
    refusing.prepare(bicubic, request);
    ADD_FAILURE() << "a degree-3 scene was not refused by a degree-1 strategy";
  } catch (const RefusedError& e) {
    EXPECT_NE(std::string(e.what()).find("counting-prepare: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("degree"), std::string::npos) << e.what();
  }
  EXPECT_EQ(refusing.prepared, 0);

  CountingPrepare accepting{Capabilities{}};
  accepting.prepare(bicubic, request);
  EXPECT_EQ(accepting.prepared, 1);
}

// What docs/strategies.md says each GPU strategy can do, checked on the registry: in a build with
// every API these come from the strategies, in one without (the sanitizer build,
// NURBSBENCH_CPU_ONLY) from the stubs, which used to state default capabilities (normals, f64,
// lists) they do not have.
TEST(Registry, GpuStrategiesStateTheirCapabilitiesWithOrWithoutTheirApi) {
  struct Expected {
    const char* name;
    const char* role;
    bool normals, fp64, explicit_list, trims, tspline_only, chooses_own_samples;
  };
  const Expected expected[] = {
      {"gl-pingpong", "strategy", false, false, false, true, false, false},
      {"gl-pingpong-packed", "strategy", false, false, false, true, false, false},
      {"glsl-deboor", "strategy", false, false, false, true, false, false},
      {"gl-tspline", "strategy", true, false, true, false, true, false},
      {"cl-stair", "strategy", false, true, false, true, false, false},
      {"cl-tspline-bezier", "strategy", true, true, true, false, true, false},
      {"vk-ksquad", "strategy", true, false, false, true, false, true},
      {"vk-bezier", "baseline", true, false, false, false, false, true},
      {"vk-compute", "strategy", true, true, true, true, false, false},
  };
  for (const Expected& e : expected) {
    SCOPED_TRACE(e.name);
    const StrategyEntry* entry = find_strategy(e.name);
    ASSERT_NE(entry, nullptr);
    EXPECT_EQ(entry->role, e.role);
    EXPECT_FALSE(entry->source.empty());
    const Capabilities c = entry->capabilities();
    EXPECT_EQ(c.max_degree, 15);
    EXPECT_EQ(c.normals, e.normals);
    EXPECT_EQ(c.fp64, e.fp64);
    EXPECT_EQ(c.sampling.explicit_list, e.explicit_list);
    EXPECT_EQ(c.trims, e.trims);
    EXPECT_EQ(c.tspline_only, e.tspline_only);
    EXPECT_EQ(c.chooses_own_samples, e.chooses_own_samples);
    EXPECT_TRUE(c.updates_control_points);
  }
}

}  // namespace
}  // namespace nurbs
