// T-splines through the harness: the built-in scenes, the scene format's "t-spline" kind, sampling,
// the reference dispatch, refusals, and cpu-tspline (001's method on the CPU). Oracles: a T-spline
// refined from a NURBS surface is that surface (its NURBS reference); a tensor-mesh T-spline's
// cells are the NURBS spans; errors are the exact lines a user sees.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../cli/run_cli.h"
#include "reference/reference_evaluator.h"
#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "scenes/deforming.h"
#include "scenes/scene_json.h"
#include "strategies/registry.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

using test::grid;

using test::Rng;

Scene builtin(std::string_view name) {
  std::optional<Scene> scene = make_builtin_scene(name);
  if (!scene) throw std::logic_error(std::string(name) + " is not built in");
  return std::move(*scene);
}

Scene one_tspline(const Surface& nurbs) {
  Scene scene{"tensor", "", {}};
  scene.surfaces.push_back(make_tspline_surface(infer_tspline(tensor_tmesh(nurbs), "tensor")));
  return scene;
}

double distance(const Point3& a, const Point3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// tspline-refined is tan21x23's surface on a T-mesh with T-junctions: its reference, and its
// normals, are the NURBS reference's at every sample (the refinement rounded its points and
// weights to double once per split and merge).
TEST(TSplineScenes, RefinedPatchIsItsNurbsTwin) {
  const Scene tspline = builtin("tspline-refined"), nurbs = builtin("tan21x23");
  ASSERT_TRUE(tspline.surfaces[0].is_tspline());
  const TSplineSurface& t = *tspline.surfaces[0].tspline;
  EXPECT_EQ(t.count(), 21u * 23u + 6u);  // three face splits, two vertices each
  EXPECT_EQ(analysis_suitability_violation(tensor_tmesh(nurbs.surfaces[0])), "");
  for (const Sampling& sampling : {grid(41, 45), grid(7, 5)}) {
    const auto samples = sample_parameters(nurbs, sampling);
    EXPECT_EQ(sample_parameters(tspline, sampling)[0].u, samples[0].u);
    const auto a = evaluate_reference(tspline, samples, true);
    const auto b = evaluate_reference(nurbs, samples, true);
    const double scale = nurbs.largest_coordinate();
    double worst = 0, worst_normal = 0;
    for (std::size_t k = 0; k < samples[0].count(); ++k) {
      worst = std::max(worst, distance(a[0].positions[k], b[0].positions[k]) / scale);
      worst_normal = std::max(worst_normal, distance(a[0].normals[k], b[0].normals[k]));
    }
    EXPECT_LE(worst, 1e-14);
    EXPECT_LE(worst_normal, 1e-12);
  }
}

// tspline-tjunction moves only the six T-junction points: it leaves its twin by their lift inside
// their supports and nowhere else (the domain's corners are outside every one).
TEST(TSplineScenes, TJunctionSceneMovesOnlyNearItsTJunctions) {
  const Scene moved = builtin("tspline-tjunction"), nurbs = builtin("tan21x23");
  const auto samples = sample_parameters(nurbs, grid(81, 81));
  const auto a = evaluate_reference(moved, samples, false);
  const auto b = evaluate_reference(nurbs, samples, false);
  double most = 0;
  for (std::size_t k = 0; k < samples[0].count(); ++k)
    most = std::max(most, distance(a[0].positions[k], b[0].positions[k]));
  EXPECT_GT(most, 0.1);  // a lift of 1.5 times a blending function's peak (~0.3)
  EXPECT_LT(most, 1.5);  // and never more than the lift (the functions are at most 1)
  for (std::size_t k : {std::size_t{0}, samples[0].count() - 1})
    EXPECT_LE(distance(a[0].positions[k], b[0].positions[k]), 1e-14 * nurbs.largest_coordinate());
}

// The span grid samples a T-spline's cells: for a tensor mesh they are the NURBS spans, so the
// parameters are the NURBS span grid's exactly; the refined patch adds its three new knot columns.
TEST(TSplineScenes, SpanGridSamplesTheCells) {
  const Sampling span = test::span_grid(3);
  const Scene nurbs = builtin("tan21x23");
  const auto expected = sample_parameters(nurbs, span);
  const auto tensor = sample_parameters(one_tspline(nurbs.surfaces[0]), span);
  EXPECT_EQ(tensor[0].u, expected[0].u);
  EXPECT_EQ(tensor[0].v, expected[0].v);
  const auto refined = sample_parameters(builtin("tspline-refined"), span);
  EXPECT_EQ(refined[0].u.size(), expected[0].u.size() + 3 * 4);
  EXPECT_EQ(refined[0].v, expected[0].v);
}

TEST(TSplineScenes, RhinoModelsLoadAndValidate) {
  for (const char* name : {"tsm-simple", "tsm-fan", "tsm-gearbox"}) {
    const Scene scene = builtin(name);
    ASSERT_EQ(scene.surfaces.size(), 1u);
    EXPECT_TRUE(scene.surfaces[0].is_tspline());
    EXPECT_EQ(scene.surfaces[0].name, name);
  }
  // The same model from its file, as a scene path.
  const Scene from_file =
      load_scene(std::string(NURBSBENCH_SOURCE_DIR) + "/scenes/data/tsplines/simple.tsm");
  EXPECT_EQ(from_file.surfaces[0].tspline->points,
            builtin("tsm-simple").surfaces[0].tspline->points);
}

// The scene format's t-spline surface: each malformed field named with its index and value.
TEST(TSplineSceneJson, ErrorsNameTheFieldIndexAndValue) {
  const std::string good = R"({"name": "t", "kind": "t-spline", "degree_u": 1, "degree_v": 1,
      "domain": [0, 1, 0, 1], "points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]],
      "knots_u": [[0,0,1],[0,1,1],[0,0,1],[0,1,1]], "knots_v": [[0,0,1],[0,0,1],[0,1,1],[0,1,1]]})";
  const auto scene_text = [](const std::string& surface, const char* format = "nurbs-scene/2") {
    return fmt::format(R"({{"format": "{}", "surfaces": [{}]}})", format, surface);
  };
  const Scene scene = parse_scene_json(scene_text(good), "f.json");
  ASSERT_TRUE(scene.surfaces[0].is_tspline());
  // A bilinear tensor T-spline: the plane through its four points.
  const auto ref = evaluate_reference(scene, sample_parameters(scene, grid(3, 3)), false);
  EXPECT_EQ(ref[0].positions[4], (Point3{0.5, 0.5, 0}));

  const auto error_of = [&](const std::string& text) -> std::string {
    try {
      parse_scene_json(text, "f.json");
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return scene_text(s);
  };
  EXPECT_EQ(error_of(replaced(R"("t-spline")", R"("tspline")")),
            "f.json: surface 't' (#0): kind = \"tspline\": must be \"nurbs\" or \"t-spline\"");
  EXPECT_EQ(error_of(replaced("[0,1,1],[0,0,1],[0,1,1]]", "[0,1,1],[0,0,\"x\"],[0,1,1]]")),
            "f.json: surface 't' (#0): knots_u[2][2] = \"x\": must be a number");
  EXPECT_EQ(error_of(replaced("[0,1,1],[0,0,1],[0,1,1]]", "[0,1,1],[0,0],[0,1,1]]")),
            "f.json: surface 't' (#0): knots_u[2] = [0,0]: must be degree + 2 = 3 knots");
  EXPECT_EQ(error_of(replaced(", \"knots_v\": [[0,0,1],[0,0,1],[0,1,1],[0,1,1]]", "")),
            "f.json: surface 't' (#0): knots_v = (missing): required field is missing");
  EXPECT_EQ(error_of(replaced("[0, 1, 0, 1]", "[0, 1, 0]")),
            "f.json: surface 't' (#0): domain length = 3: must be [u_min, u_max, v_min, v_max]");
  EXPECT_EQ(error_of(replaced("[[0,0,1],[0,1,1],[0,0,1],[0,1,1]]", "[[0,0,1],[0,1,1],[0,0,1]]")),
            "f.json: surface 't' (#0): knots_u length = 3: need one local knot vector per point "
            "(4)");
  EXPECT_EQ(
      error_of(replaced("[[0,0,1],[0,1,1],[0,0,1],[0,1,1]]", "[[0,0,1],[0,1,1],[0,0,1],[1,0,1]]")),
      "f.json: tspline 't': point 3 knots_u[1] = 0: knots must be non-decreasing (previous "
      "is 1)");
  EXPECT_EQ(error_of(replaced("\"domain\"", "\"count_u\": 2, \"domain\"")),
            "f.json: surface 't' (#0): count_u = 2: unknown key (expected name, kind, degree_u, "
            "degree_v, domain, points, weights, knots_u, knots_v)");
  EXPECT_EQ(error_of(replaced("\"degree_u\": 1", "\"degree_u\": 2")),
            "f.json: surface 't' (#0): knots_u[0] = [0,0,1]: must be degree + 2 = 4 knots");
  EXPECT_EQ(error_of(scene_text(good, "nurbs-scene/1")),
            "f.json: surface 't' (#0): kind = \"t-spline\": needs \"format\": \"nurbs-scene/2\" "
            "(this file is nurbs-scene/1)");
}

// cpu-tspline on tensor-mesh T-splines of random NURBS: the NURBS reference, within float32 /
// float64 rounding. Bounds about 4x the worst measured here (7.3 ulps f32, 5.7 f64, normals
// 5.4e-15), in units of the largest coordinate.
TEST(CpuTSpline, TensorMeshesEvaluateToTheirNurbs) {
  const StrategyEntry* entry = find_strategy("cpu-tspline");
  ASSERT_NE(entry, nullptr);
  Rng rng(2026);
  test::Worst worst32("cpu-tspline f32 max |error| / largest coordinate");
  test::Worst worst64("cpu-tspline f64 max |error| / largest coordinate");
  test::Worst worst_normal("cpu-tspline f64 max normal error");
  for (const auto& [p, q] : {std::pair{3, 3}, {1, 3}, {5, 5}, {3, 7}}) {
    const Surface nurbs = test::random_surface(rng, p, q, p + 5, q + 4, test::Ends::clamped, true);
    const Scene scene = one_tspline(nurbs);
    Scene twin{"twin", "", {nurbs}};
    for (const Precision precision : {Precision::f32, Precision::f64}) {
      EvalRequest request{grid(17, 19), precision, true};
      auto strategy = entry->create({});
      strategy->prepare(scene, request);
      strategy->evaluate();
      const EvalResult result = strategy->read_back();
      const auto ref = evaluate_reference(twin, {result.surfaces[0].samples}, true);
      const double scale = twin.largest_coordinate();
      double error = 0, normal_error = 0;
      for (std::size_t k = 0; k < result.surfaces[0].samples.count(); ++k) {
        error = std::max(error, distance(result.surfaces[0].positions[k], ref[0].positions[k]));
        normal_error =
            std::max(normal_error, distance(result.surfaces[0].normals[k], ref[0].normals[k]));
      }
      error /= scale;
      const auto where = [&, p = p, q = q] { return fmt::format("{}x{}", p, q); };
      if (precision == Precision::f32) {
        worst32.update(error, where);
        EXPECT_LE(error, 32 * 0x1p-24) << p << "x" << q;
      } else {
        worst64.update(error, where);
        worst_normal.update(normal_error, where);
        EXPECT_LE(error, 32 * 0x1p-53) << p << "x" << q;
        EXPECT_LE(normal_error, 2e-14) << p << "x" << q;
      }
    }
  }
}

// A deforming frame re-uploads nothing but the points: update_control_points then evaluate gives
// what a fresh prepare on that frame gives, bit for bit.
TEST(CpuTSpline, UpdateControlPointsEqualsAFreshPrepare) {
  const StrategyEntry* entry = find_strategy("cpu-tspline");
  const Scene base = builtin("tspline-tjunction");
  const Scene frame0 = deformed_scene(base, 0), frame7 = deformed_scene(base, 7);
  const EvalRequest request{grid(23, 29), Precision::f64, true};
  auto updated = entry->create({}), fresh = entry->create({});
  updated->prepare(frame0, request);
  updated->update_control_points(frame7);
  updated->evaluate();
  fresh->prepare(frame7, request);
  fresh->evaluate();
  const EvalResult a = updated->read_back(), b = fresh->read_back();
  const EvalResult before = [&] {
    auto s = entry->create({});
    s->prepare(frame0, request);
    s->evaluate();
    return s->read_back();
  }();
  bool moved = false;
  for (std::size_t k = 0; k < a.surfaces[0].samples.count(); ++k) {
    ASSERT_EQ(a.surfaces[0].positions[k], b.surfaces[0].positions[k]) << k;
    ASSERT_EQ(a.surfaces[0].normals[k], b.surfaces[0].normals[k]) << k;
    moved = moved || a.surfaces[0].positions[k] != before.surfaces[0].positions[k];
  }
  EXPECT_TRUE(moved);
}

TEST(TSplineRefusals, EachKindIsRefusedByTheOtherKindsStrategies) {
  const Scene tspline = builtin("tsm-simple"), nurbs = builtin("patch144");
  const EvalRequest request{grid(4, 4), Precision::f32, false};
  EXPECT_EQ(refusal_reason(find_strategy("cpu-coxdeboor")->capabilities(), tspline, request),
            "surface 'tsm-simple' is a T-spline, the strategy evaluates NURBS only");
  EXPECT_EQ(refusal_reason(find_strategy("cpu-tspline")->capabilities(), nurbs, request),
            "surface 'patch' is a NURBS surface, the strategy evaluates T-splines only");
  EXPECT_EQ(refusal_reason(find_strategy("cpu-tspline")->capabilities(), tspline, request),
            std::nullopt);
  auto strategy = find_strategy("cpu-tspline")->create({});
  EXPECT_THROW(strategy->prepare(nurbs, request), RefusedError);
}

// As a user runs it: built-in T-spline scenes through process isolation (the child reads the scene
// back from JSON), and malformed T-spline inputs refused with exit 2 and one line.
TEST(TSplineCli, RunsTheBuiltinScenesAndRefusesBadFiles) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "nurbsbench-tspline-cli";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const test::CliResult run = test::run_cli(
      {"run", "--scenes", "tspline-refined,tsm-fan", "--strategies", "cpu-tspline,cpu-coxdeboor",
       "--samples", "16x16", "--repetitions", "1", "--normals", "--out", (dir / "out").string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string results = test::read_text(dir / "out" / "results.csv");
  EXPECT_NE(results.find("tspline-refined,cpu-tspline,"), std::string::npos);
  EXPECT_EQ(std::count(results.begin(), results.end(), '\n'), 5);  // header + 4 records
  EXPECT_NE(results.find("ok"), std::string::npos);
  EXPECT_NE(results.find("the strategy evaluates NURBS only"), std::string::npos);

  const std::filesystem::path bad_tsm = dir / "bad.tsm";
  std::ofstream(bad_tsm) << "#TS0200\ndegree 4\n";
  const test::CliResult tsm = test::run_cli({"run", "--scenes", bad_tsm.string(), "--strategies",
                                             "cpu-tspline", "--out", (dir / "bad").string()});
  EXPECT_EQ(tsm.exit_code, 2);
  EXPECT_EQ(std::count(tsm.err.begin(), tsm.err.end(), '\n'), 1) << tsm.err;
  EXPECT_NE(tsm.err.find(bad_tsm.string()), std::string::npos) << tsm.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad" / "results.json"));

  // A T-spline scene file with a negative weight: the validation's line, exit 2.
  const std::filesystem::path bad_json = dir / "bad.json";
  std::ofstream(bad_json)
      << R"({"format": "nurbs-scene/2", "surfaces": [{"name": "t", "kind": "t-spline",
      "degree_u": 1, "degree_v": 1, "domain": [0, 1, 0, 1], "weights": [1, 1, -2, 1],
      "points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]],
      "knots_u": [[0,0,1],[0,1,1],[0,0,1],[0,1,1]], "knots_v": [[0,0,1],[0,0,1],[0,1,1],[0,1,1]]}]})";
  const test::CliResult json = test::run_cli({"eval", "--scene", bad_json.string(), "--strategy",
                                              "cpu-tspline", "--out", (dir / "e.csv").string()});
  EXPECT_EQ(json.exit_code, 2);
  EXPECT_EQ(json.err, "nurbsbench: error: " + bad_json.string() +
                          ": tspline 't': point 2 weight = -2: weights must be finite and > 0\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "e.csv"));

  // A verb that takes NURBS only says so.
  const test::CliResult lod = test::run_cli({"lod", "--scene", "tsm-simple"});
  EXPECT_EQ(lod.exit_code, 2);
  EXPECT_NE(lod.err.find("is a T-spline"), std::string::npos) << lod.err;
}

}  // namespace
}  // namespace nurbs
