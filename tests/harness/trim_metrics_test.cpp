// Trimmed scenes through the harness: errors over the inside samples only, the boundary band,
// misclassification counts, reversed faces, records, gates, tables and error maps, on the trimmed
// plate of plates.h. Every sample's classification and distance to the trim boundary are known
// in closed form there, so the references below are built by hand, without the classifier.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#ifdef NURBSBENCH_TEST_OIIO
#include <OpenImageIO/imageio.h>
#endif

#include "harness/error_image.h"
#include "harness/gates.h"
#include "harness/metrics.h"
#include "harness/record.h"
#include "harness/report/report.h"
#include "harness/summary_table.h"
#include "tests/harness/plates.h"

namespace nurbs {
namespace {

using test::hand_distance;
using test::hand_inside;
using test::trimmed_plate;

// The 9x9 grid u, v = k/8: the 32 samples on the domain's edges lie outside the outer loop
// (1/16 from it), 9 in the hole ((3..5)/8 in both directions), so 81 - 32 - 9 = 40 are inside.
// The samples nearest the boundary are the 12 beside a side of the hole (u or v = 0.25 or 0.75,
// the other in 3/8..5/8), 0.05 from it; next come the samples 1/16 from the outer loop (0.0625)
// and the 4 diagonal neighbours of the hole's corners (0.0707).
constexpr int kGrid = 9;
constexpr std::size_t kSamples = kGrid * kGrid, kEdge = 32, kHole = 9,
                      kInside = kSamples - kEdge - kHole, kBesideHole = 12;
// 0.04 x sqrt(2) = 0.0566: the band that holds exactly the 12 samples beside the hole.
constexpr double kBand = 0.04;

SurfaceSamples grid_samples(int nu, int nv) {
  SurfaceSamples s;
  for (int a = 0; a < nu; ++a) s.u.push_back(static_cast<double>(a) / (nu - 1));
  for (int b = 0; b < nv; ++b) s.v.push_back(static_cast<double>(b) / (nv - 1));
  return s;
}

// The exact reference of the plate at `samples`: position (u, v, 0), normal +z (-z reversed).
std::vector<ReferenceSurface> hand_reference(const Scene& scene, const SurfaceSamples& samples,
                                             bool normals = false) {
  ReferenceSurface ref;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    const double u = samples.u_of(k), v = samples.v_of(k);
    ref.positions.push_back({u, v, 0});
    if (normals) ref.normals.push_back({0, 0, scene.surfaces[0].reversed ? -1.0 : 1.0});
    ref.inside.push_back(hand_inside(u, v) ? 1 : 0);
    ref.trim_distance.push_back(hand_distance(u, v));
  }
  return {ref};
}

// A result at `samples` equal to the reference, with `inside` as the strategy's mask.
EvalResult exact_result(const SurfaceSamples& samples, Precision precision = Precision::f64) {
  EvalResult result;
  result.surfaces.resize(1);
  SurfaceResult& r = result.surfaces[0];
  r.samples = samples;
  r.positions = PointArray(precision, samples.count());
  for (std::size_t k = 0; k < samples.count(); ++k)
    r.positions.set(k, Point3{samples.u_of(k), samples.v_of(k), 0});
  return result;
}

std::size_t index_of(const SurfaceSamples& s, int a, int b) {
  return static_cast<std::size_t>(a) * s.v.size() + b;
}

TEST(TrimMetrics, HandReferenceCountsAreTheHandCounts) {
  // The closed forms against the counts stated above, so the later tests rest on checked inputs.
  const SurfaceSamples samples = grid_samples(kGrid, kGrid);
  const auto ref = hand_reference(trimmed_plate(), samples)[0];
  std::size_t inside = 0, in_band = 0;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    inside += ref.inside[k];
    in_band += ref.trim_distance[k] < kBand * std::sqrt(2.0);
  }
  EXPECT_EQ(inside, kInside);
  EXPECT_EQ(in_band, kBesideHole);
  EXPECT_DOUBLE_EQ(hand_distance(0.5, 0.5), 0.2);       // hole centre to its sides
  EXPECT_DOUBLE_EQ(hand_distance(0.125, 0.5), 0.0625);  // nearer the outer loop than the hole
  EXPECT_DOUBLE_EQ(hand_distance(0.25, 0.25), std::hypot(0.05, 0.05));  // hole corner
  EXPECT_DOUBLE_EQ(hand_distance(0, 0), std::hypot(0.0625, 0.0625));    // outer corner, outside
  EXPECT_FALSE(hand_inside(0, 0.5));
  EXPECT_FALSE(hand_inside(0.5, 0.5));
  EXPECT_TRUE(hand_inside(0.125, 0.5));
}

TEST(TrimMetrics, ErrorsAreOverTheInsideSamplesOnly) {
  const Scene scene = trimmed_plate();
  const SurfaceSamples samples = grid_samples(kGrid, kGrid);
  const auto reference = hand_reference(scene, samples);
  EvalResult result = exact_result(samples);
  PointArray& p = result.surfaces[0].positions;  // Wildly wrong in the hole and on the domain's
                                                 // edges (some not even finite): none may count.
  for (int a = 3; a <= 5; ++a)
    for (int b = 3; b <= 5; ++b) p.set(index_of(samples, a, b), Point3{1e3, -1e3, 1e3});
  for (int k = 0; k < kGrid; ++k) {
    p.set(index_of(samples, 0, k), Point3{-1e6, 0, 0});
    p.set(index_of(samples, k, kGrid - 1), Point3{0, 0, 5e5});
  }
  p.set(index_of(samples, 4, 4), Point3{NAN, 0, 0});
  p.set(index_of(samples, 8, 0), Point3{INFINITY, 0, 0});
  // One inside sample off by 1e-3 in z: the only error that counts.
  p.set(index_of(samples, 1, 4), Point3{0.125, 0.5, 1e-3});

  const Accuracy acc = measure_accuracy(scene, result, reference);
  EXPECT_DOUBLE_EQ(acc.max_abs, 1e-3);
  EXPECT_DOUBLE_EQ(acc.rms_abs, std::sqrt(1e-6 / kInside));
  EXPECT_EQ(acc.worst_u, 0.125);
  EXPECT_EQ(acc.worst_v, 0.5);
  // Outside the face no error counts, but a NaN anywhere is a failed evaluation (issue 28).
  EXPECT_EQ(acc.non_finite, 2u);
  EXPECT_EQ(acc.first_non_finite.surface, 0);
  EXPECT_EQ(acc.first_non_finite.u, samples.u_of(index_of(samples, 4, 4)));
  EXPECT_EQ(acc.first_non_finite.v, samples.v_of(index_of(samples, 4, 4)));
  EXPECT_NE(non_finite_failure(acc, samples.count()).find("2 of 81 samples are not finite"),
            std::string::npos)
      << non_finite_failure(acc, samples.count());
  ASSERT_TRUE(acc.trim);
  EXPECT_EQ(acc.trim->inside, kInside);
  EXPECT_EQ(acc.trim->boundary, 0u) << "default band 1e-7: no sample that near";
  EXPECT_FALSE(acc.trim->misclassified) << "not scored for a strategy that does not trim";
  EXPECT_FALSE(no_inside_samples(acc));
}

TEST(TrimMetrics, NormalsAreOverTheInsideSamplesOnly) {
  const Scene scene = trimmed_plate();
  const SurfaceSamples samples = grid_samples(kGrid, kGrid);
  const auto reference = hand_reference(scene, samples, true);
  EvalResult result = exact_result(samples);
  PointArray& n = result.surfaces[0].normals;
  n = PointArray(Precision::f64, samples.count());
  for (std::size_t k = 0; k < samples.count(); ++k) n.set(k, Point3{0, 0, 1});
  n.set(index_of(samples, 4, 4), Point3{1, 0, 0});   // 90 degrees off, in the hole
  n.set(index_of(samples, 0, 3), Point3{0, 0, -1});  // reversed, outside the outer loop
  n.set(index_of(samples, 1, 1), Point3{0, std::sin(0.01), std::cos(0.01)});
  const Accuracy acc = measure_accuracy(scene, result, reference);
  ASSERT_TRUE(acc.max_normal_angle_deg);
  EXPECT_NEAR(*acc.max_normal_angle_deg, 0.01 * 180 / M_PI, 1e-12);
}

TEST(TrimMetrics, MisclassifiedCountsOnlyOutsideTheBand) {
  const Scene scene = trimmed_plate();
  const SurfaceSamples samples = grid_samples(kGrid, kGrid);
  const auto reference = hand_reference(scene, samples);
  EvalResult result = exact_result(samples);
  std::vector<std::uint8_t>& mask = result.surfaces[0].inside;
  mask = reference[0].inside;
  EXPECT_EQ(*measure_accuracy(scene, result, reference, {kBand, true}).trim->misclassified, 0u);
  // Three flips away from the boundary -- an inside sample called outside, the hole's centre and
  // a sample beyond the outer loop called inside -- and one 0.05 beside the hole, in the band.
  for (const auto& [a, b] : {std::pair{1, 1}, std::pair{4, 4}, std::pair{0, 5}, std::pair{2, 4}})
    mask[index_of(samples, a, b)] ^= 1;
  const Accuracy acc = measure_accuracy(scene, result, reference, {kBand, true});
  ASSERT_TRUE(acc.trim && acc.trim->misclassified && acc.trim->misclassified_rate);
  EXPECT_EQ(*acc.trim->misclassified, 3u);
  EXPECT_EQ(acc.trim->boundary, kBesideHole);
  EXPECT_DOUBLE_EQ(*acc.trim->misclassified_rate, 3.0 / (kSamples - kBesideHole));
  EXPECT_EQ(acc.trim->band, kBand);
  EXPECT_EQ(acc.trim->inside, kInside) << "the reference's classification decides what is scored";
  // The band is a fraction of the domain diagonal (sqrt 2 here): at 0.035 (0.0495) the sample
  // 0.05 beside the hole is outside it and counts, as at the default band.
  const Accuracy narrower = measure_accuracy(scene, result, reference, {0.035, true});
  EXPECT_EQ(narrower.trim->boundary, 0u);
  EXPECT_EQ(*narrower.trim->misclassified, 4u);
  const Accuracy fine = measure_accuracy(scene, result, reference, {kDefaultTrimBand, true});
  EXPECT_EQ(*fine.trim->misclassified, 4u);
  EXPECT_DOUBLE_EQ(*fine.trim->misclassified_rate, 4.0 / kSamples);
}

TEST(TrimMetrics, TrimmingStrategyWithoutAMaskFails) {
  const Scene scene = trimmed_plate();
  const SurfaceSamples samples = grid_samples(kGrid, kGrid);
  const auto reference = hand_reference(scene, samples);
  const EvalResult result = exact_result(samples);
  try {
    measure_accuracy(scene, result, reference, {kDefaultTrimBand, true});
    FAIL() << "no mask from a strategy that trims";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no inside mask for trimmed surface 'plate'"),
              std::string::npos)
        << e.what();
  }
  EvalResult short_mask = exact_result(samples);
  short_mask.surfaces[0].inside.assign(5, 1);
  EXPECT_THROW(measure_accuracy(scene, short_mask, reference, {kDefaultTrimBand, true}),
               std::runtime_error);
}

TEST(TrimMetrics, NoInsideSampleIsSaidNotScoredAsPerfect) {
  const Scene scene = trimmed_plate();
  // Every sample in the hole.
  SurfaceSamples hole{false, {0.4, 0.5, 0.6}, {0.45, 0.5, 0.55}};
  const auto reference = hand_reference(scene, hole);
  EvalResult result = exact_result(hole);
  for (std::size_t k = 0; k < hole.count(); ++k)
    result.surfaces[0].positions.set(k, Point3{9, 9, 9});
  const Accuracy acc = measure_accuracy(scene, result, reference);
  EXPECT_EQ(acc.trim->inside, 0u);
  EXPECT_EQ(acc.max_abs, 0);
  EXPECT_TRUE(no_inside_samples(acc));

  Record r;
  r.scene = "trimmed";
  r.strategy = "cpu-tensor";
  r.trimming = "untrimmed";
  r.accuracy = acc;
  const auto violations = check_gates({{"*", "*", "max_ulp", 1}}, {r});
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_NE(violations[0].find("over no sample"), std::string::npos) << violations[0];
  EXPECT_NE(summary_table({r}).find("- (0 inside)"), std::string::npos) << summary_table({r});
}

TEST(TrimMetrics, UntrimmedSceneHasNoTrimFigures) {
  Scene scene = trimmed_plate();
  scene.surfaces[0].trim.reset();
  const SurfaceSamples samples = grid_samples(3, 3);
  auto reference = hand_reference(scene, samples);
  reference[0].inside.clear();
  reference[0].trim_distance.clear();
  const Accuracy acc = measure_accuracy(scene, exact_result(samples), reference, {0.5, true});
  EXPECT_FALSE(acc.trim);
  EXPECT_EQ(trimming_of(Capabilities{}, scene), "");
  Capabilities trims;
  trims.trims = true;
  EXPECT_EQ(trimming_of(trims, trimmed_plate()), "classified");
  EXPECT_EQ(trimming_of(Capabilities{}, trimmed_plate()), "untrimmed");
}

TEST(TrimMetrics, ReversedFacesFlipTheStrategysNormals) {
  Scene scene = trimmed_plate();
  scene.surfaces[0].reversed = true;
  scene.surfaces.push_back(scene.surfaces[0]);
  scene.surfaces[1].reversed = false;
  EvalResult result;
  result.surfaces.resize(2);
  result.surfaces[0].normals = PointArray(Precision::f32, 2);
  result.surfaces[0].normals.set(0, Point3{0, 0, 1});
  result.surfaces[0].normals.set(1, Point3{0.6, -0.8, 0});
  result.surfaces[1].normals = PointArray(Precision::f64, 1);
  result.surfaces[1].normals.set(0, Point3{0, 0, 1});
  orient_normals(scene, result);
  EXPECT_EQ(result.surfaces[0].normals[0], (std::array<double, 3>{0, 0, -1}));
  EXPECT_EQ(result.surfaces[0].normals[1][0], -0.6f);
  EXPECT_EQ(result.surfaces[0].normals[1][1], 0.8f);
  EXPECT_EQ(result.surfaces[1].normals[0], (std::array<double, 3>{0, 0, 1})) << "not reversed";

  // Scored against the reference's flipped normal, the oriented normal is exact.
  Scene one = trimmed_plate();
  one.surfaces[0].reversed = true;
  const SurfaceSamples samples = grid_samples(3, 3);
  EvalResult plate = exact_result(samples);
  plate.surfaces[0].normals = PointArray(Precision::f64, samples.count());
  for (std::size_t k = 0; k < samples.count(); ++k)
    plate.surfaces[0].normals.set(k, Point3{0, 0, 1});  // S_u x S_v
  orient_normals(one, plate);
  EXPECT_EQ(*measure_accuracy(one, plate, hand_reference(one, samples, true)).max_normal_angle_deg,
            0.0);
}

Record trimmed_record(std::string trimming) {
  Record r;
  r.scene = "trimmed-plate";
  r.strategy = trimming == "classified" ? "cpu-coxdeboor" : "cpu-tensor";
  r.role = "strategy";
  r.precision = "f32";
  r.sampling = "grid";
  r.samples = "9x9";
  r.points = kSamples;
  r.trimming = trimming;
  r.accuracy = Accuracy{};
  r.accuracy->max_ulp = 1;
  TrimAccuracy t;
  t.band = 2.5e-7;
  t.inside = kInside;
  t.boundary = kBesideHole;
  if (trimming == "classified") {
    t.misclassified = 3;
    t.misclassified_rate = 3.0 / 69;
  }
  r.accuracy->trim = t;
  return r;
}

TEST(TrimRecord, JsonRoundTrip) {
  for (const char* trimming : {"classified", "untrimmed"}) {
    const Record r = trimmed_record(trimming);
    const nlohmann::json j = record_to_json(r);
    EXPECT_EQ(j["trimming"], trimming);
    const Record back = record_from_json(nlohmann::json::parse(j.dump()));
    EXPECT_EQ(back.trimming, trimming);
    ASSERT_TRUE(back.accuracy && back.accuracy->trim);
    const TrimAccuracy& t = *back.accuracy->trim;
    EXPECT_EQ(t.band, 2.5e-7);
    EXPECT_EQ(t.inside, kInside);
    EXPECT_EQ(t.boundary, kBesideHole);
    EXPECT_EQ(t.misclassified, r.accuracy->trim->misclassified);
    EXPECT_EQ(t.misclassified_rate, r.accuracy->trim->misclassified_rate);
  }
  Record plain = trimmed_record("");
  plain.accuracy->trim.reset();
  const nlohmann::json j = record_to_json(plain);
  EXPECT_FALSE(j.contains("trimming"));
  EXPECT_FALSE(j["accuracy"].contains("trim"));
  const Record back = record_from_json(j);
  EXPECT_EQ(back.trimming, "");
  EXPECT_FALSE(back.accuracy->trim);
}

TEST(TrimRecord, CsvTrimColumnsComeLast) {
  const std::string header = csv_header();
  EXPECT_TRUE(
      header.ends_with(",status,reason,trimming,trim_band,trim_inside_samples,"
                       "trim_boundary_samples,trim_misclassified,trim_misclassified_rate"))
      << header;
  Record r = trimmed_record("classified");
  r.status = Status::ok;
  EXPECT_TRUE(csv_row(r).ends_with(",ok,,classified,2.5e-07,40,12,3,0.043478260869565216"))
      << csv_row(r);
  EXPECT_TRUE(csv_row(trimmed_record("untrimmed")).ends_with(",ok,,untrimmed,2.5e-07,40,12,,"))
      << csv_row(trimmed_record("untrimmed"));
  Record plain = trimmed_record("");
  plain.accuracy->trim.reset();
  EXPECT_TRUE(csv_row(plain).ends_with(",ok,,,,,,,")) << csv_row(plain);
  // As many cells as header columns (no quoted commas in these records).
  const auto cells = [](const std::string& line) {
    return std::count(line.begin(), line.end(), ',');
  };
  EXPECT_EQ(cells(csv_row(r)), cells(header));
}

TEST(TrimGates, MisclassificationGatesApplyOnlyWhereTheStrategyClassified) {
  const Record classified = trimmed_record("classified");  // rate 3/69 = 0.0435
  const Record untrimmed = trimmed_record("untrimmed");
  Record plain_scene = trimmed_record("");
  plain_scene.scene = "patch144";
  plain_scene.accuracy->trim.reset();
  const std::vector<Record> records = {classified, untrimmed, plain_scene};

  EXPECT_TRUE(check_gates({{"*", "*", "trim_misclassified_rate", 0.05}}, records).empty())
      << "the untrimmed and untrimmed-scene records are not applicable, not violations";
  const auto over = check_gates({{"*", "*", "trim_misclassified_rate", 0.04}}, records);
  ASSERT_EQ(over.size(), 1u);
  EXPECT_NE(over[0].find("cpu-coxdeboor on trimmed-plate"), std::string::npos) << over[0];
  EXPECT_NE(over[0].find("0.0434783"), std::string::npos) << over[0];
  EXPECT_EQ(check_gates({{"*", "*", "trim_misclassified", 2}}, records).size(), 1u);
  EXPECT_TRUE(check_gates({{"*", "*", "trim_misclassified", 3}}, records).empty());
  // A gate that only meets records without a classification has measured nothing.
  const auto nothing = check_gates({{"cpu-tensor", "*", "trim_misclassified_rate", 1}}, records);
  ASSERT_EQ(nothing.size(), 1u);
  EXPECT_NE(nothing[0].find("matched no measured result"), std::string::npos) << nothing[0];
  // A classifying strategy that failed is a violation, not a pass.
  Record failed = classified;
  failed.status = Status::failed;
  failed.reason = "the strategy trims but returned no inside mask";
  EXPECT_EQ(check_gates({{"*", "*", "trim_misclassified_rate", 1}}, {failed}).size(), 1u);
  EXPECT_TRUE(is_known_metric("trim_misclassified"));
  EXPECT_TRUE(is_known_metric("trim_misclassified_rate"));
}

TEST(TrimTables, SummaryShowsATrimColumnOnlyForTrimmedScenes) {
  Record plain = trimmed_record("");
  plain.scene = "patch144";
  plain.accuracy->trim.reset();
  EXPECT_EQ(summary_table({plain}).find("trim"), std::string::npos);
  const std::string table =
      summary_table({plain, trimmed_record("classified"), trimmed_record("untrimmed")});
  EXPECT_NE(table.find("  trim  "), std::string::npos) << table;
  EXPECT_NE(table.find("3 misclassified (0.0435), 12 boundary"), std::string::npos) << table;
  EXPECT_NE(table.find("untrimmed"), std::string::npos) << table;
  Record failed = trimmed_record("untrimmed");
  failed.status = Status::failed;
  EXPECT_EQ(trim_text(failed), "untrimmed") << "a label, whatever the status";
}

TEST(TrimTables, ReportShowsTrimFiguresAndStacksClassify) {
  ResultSet set;
  set.tag = "trim";
  set.results.machine = set.results.settings = nlohmann::json::object();
  Record classified = trimmed_record("classified");
  classified.evaluate = classified.upload = classified.read_back = {1e-3, 1e-3, 1e-3};
  classified.extra_phases["classify"] = {2e-4, 2e-4, 2e-4};
  classified.end_to_end = {3.2e-3, 3.2e-3, 3.2e-3};
  Record untrimmed = trimmed_record("untrimmed");
  untrimmed.evaluate = untrimmed.upload = untrimmed.read_back = {1e-3, 1e-3, 1e-3};
  untrimmed.end_to_end = {3e-3, 3e-3, 3e-3};
  set.results.records = {classified, untrimmed};
  const Report report = build_report({set});

  const auto measurements =
      std::find_if(report.sections.begin(), report.sections.end(),
                   [](const ReportSection& s) { return s.id == "measurements"; });
  ASSERT_NE(measurements, report.sections.end());
  const ReportTable& table = measurements->tables.at(0);
  const auto column = std::find(table.header.begin(), table.header.end(), "trim");
  ASSERT_NE(column, table.header.end());
  const std::size_t c = column - table.header.begin();
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[0][c], "3 misclassified (0.0435), 12 boundary");
  EXPECT_EQ(table.rows[1][c], "untrimmed");

  const auto chart = std::find_if(report.charts["charts"].begin(), report.charts["charts"].end(),
                                  [](const nlohmann::json& j) { return j["id"] == "phases"; });
  ASSERT_NE(chart, report.charts["charts"].end());
  std::vector<std::string> stacks;
  for (const auto& stack : (*chart)["stacks"]) stacks.push_back(stack["label"]);
  EXPECT_EQ(stacks, (std::vector<std::string>{"upload", "evaluate", "classify", "read_back"}));
  EXPECT_EQ((*chart)["stacks"][2]["values"], nlohmann::json::parse("[0.0002, 0.0]"));
}

TEST(TrimErrorImage, GridCarriesTheReferenceClassificationInPixelOrder) {
  const Scene scene = trimmed_plate();
  const SurfaceSamples samples = grid_samples(kGrid, 5);  // not square: catches a transposition
  const auto reference = hand_reference(scene, samples);
  EvalResult result = exact_result(samples);
  const std::vector<ErrorGrid> grids = error_grids(scene, result, reference);
  ASSERT_EQ(grids.size(), 1u);
  const ErrorGrid& g = grids[0];
  ASSERT_EQ(g.inside.size(), samples.count());
  for (int x = 0; x < g.width; ++x)
    for (int y = 0; y < g.height; ++y)
      EXPECT_EQ(g.inside[static_cast<std::size_t>(y) * g.width + x],
                hand_inside(samples.u[x], samples.v[y]) ? 1 : 0)
          << x << "," << y;
  Scene untrimmed = scene;
  untrimmed.surfaces[0].trim.reset();
  auto plain_reference = reference;
  plain_reference[0].inside.clear();
  EXPECT_TRUE(error_grids(untrimmed, result, plain_reference)[0].inside.empty());
}

#ifdef NURBSBENCH_TEST_OIIO
// The files as written: the EXR's second channel and the PNG's grey, read back with OpenImageIO.
TEST(TrimErrorImage, ExrHasAnInsideChannelAndPngGreysTheOutside) {
  const Scene scene = trimmed_plate();
  const SurfaceSamples samples = grid_samples(kGrid, kGrid);
  const auto reference = hand_reference(scene, samples);
  EvalResult result = exact_result(samples);
  for (std::size_t k = 0; k < samples.count(); ++k)  // 1e-3 off everywhere, inside or not
    result.surfaces[0].positions.set(k, Point3{samples.u_of(k), samples.v_of(k), 1e-3});
  const auto grids = error_grids(scene, result, reference);
  const auto dir = std::filesystem::temp_directory_path() / "nurbsbench_trim_image_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);

  write_error_images(dir / "e.exr", grids, "trim test");
  auto exr = OIIO::ImageInput::open((dir / "e.exr").string());
  ASSERT_TRUE(exr) << OIIO::geterror();
  ASSERT_EQ(exr->spec().nchannels, 2);
  EXPECT_EQ(exr->spec().channelnames[0], "error");
  EXPECT_EQ(exr->spec().channelnames[1], "inside");
  std::vector<float> pixels(2 * kSamples);
  ASSERT_TRUE(exr->read_image(0, 0, 0, 2, OIIO::TypeDesc::FLOAT, pixels.data()));
  exr->close();
  for (int x = 0; x < kGrid; ++x)
    for (int y = 0; y < kGrid; ++y) {
      const std::size_t pixel = static_cast<std::size_t>(y) * kGrid + x;
      EXPECT_FLOAT_EQ(pixels[2 * pixel], 1e-3f) << "the error channel keeps every sample's error";
      EXPECT_EQ(pixels[2 * pixel + 1], hand_inside(samples.u[x], samples.v[y]) ? 1.0f : 0.0f)
          << x << "," << y;
    }

  write_error_images(dir / "e.png", grids, "trim test");
  auto png = OIIO::ImageInput::open((dir / "e.png").string());
  ASSERT_TRUE(png) << OIIO::geterror();
  const int w = png->spec().width, h = png->spec().height, scale = 256 / kGrid;
  std::vector<unsigned char> rgb(static_cast<std::size_t>(w) * h * 3);
  ASSERT_TRUE(png->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
  png->close();
  auto grey = [&](int px, int py) {
    const unsigned char* c = &rgb[(static_cast<std::size_t>(py) * w + px) * 3];
    return c[0] == 153 && c[1] == 153 && c[2] == 153;  // 0.6 x 255
  };
  // Sample (a, b) is drawn around x = a * scale + scale / 2, v upwards.
  auto centre_grey = [&](int a, int b) {
    return grey(a * scale + scale / 2, kGrid * scale - 1 - (b * scale + scale / 2));
  };
  for (int a = 0; a < kGrid; ++a)
    for (int b = 0; b < kGrid; ++b)
      EXPECT_EQ(centre_grey(a, b), !hand_inside(samples.u[a], samples.v[b])) << a << "," << b;
  EXPECT_TRUE(grey(kGrid * scale + 10 + 8, h - 8)) << "the legend's outside swatch";
  std::filesystem::remove_all(dir);
}
#endif

}  // namespace
}  // namespace nurbs
