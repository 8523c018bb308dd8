// scenes/: the nurbs-scene/1 and /2 writer reads back exactly (every double equal), the reader
// names every flaw by its field path (trims included) and refuses duplicated keys and deep nesting,
// and the built-in scenes have the shapes the papers' experiments need (docs/design.md §Scene file
// format; builtin_scenes.h).
#include "scenes/scene_json.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "../cli/run_cli.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "scenes/json_strict.h"

namespace nurbs {
namespace {

using test::CliResult;
using test::run_cli;
using test::TempDir;

// Doubles compared with == (all equal; +0 and -0 count as equal: the writer prints -0.0 as "-0",
// which JSON readers take for the integer 0).
std::vector<double> coordinates(const std::vector<Point3>& points) {
  std::vector<double> out;
  for (const Point3& p : points) out.insert(out.end(), p.begin(), p.end());
  return out;
}

void expect_identical(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  for (std::size_t i = 0; i < a.surfaces.size(); ++i) {
    SCOPED_TRACE(i);
    const Surface &s = a.surfaces[i], &t = b.surfaces[i];
    EXPECT_EQ(s.name, t.name);
    EXPECT_EQ(s.degree_u, t.degree_u);
    EXPECT_EQ(s.degree_v, t.degree_v);
    EXPECT_EQ(s.count_u, t.count_u);
    EXPECT_EQ(s.count_v, t.count_v);
    EXPECT_EQ(s.knots_u, t.knots_u);
    EXPECT_EQ(s.knots_v, t.knots_v);
    EXPECT_EQ(coordinates(s.points), coordinates(t.points));
    EXPECT_EQ(s.weights, t.weights);
    EXPECT_EQ(s.reversed, t.reversed);
    ASSERT_EQ(s.is_tspline(), t.is_tspline());
    if (s.is_tspline()) {
      const TSplineSurface &x = *s.tspline, &y = *t.tspline;
      EXPECT_EQ(x.name, y.name);
      EXPECT_EQ(x.degree_u, y.degree_u);
      EXPECT_EQ(x.degree_v, y.degree_v);
      EXPECT_EQ(coordinates(x.points), coordinates(y.points));
      EXPECT_EQ(x.weights, y.weights);
      EXPECT_EQ(x.knots_u, y.knots_u);
      EXPECT_EQ(x.knots_v, y.knots_v);
      EXPECT_EQ((std::array{x.u_min, x.u_max, x.v_min, x.v_max}),
                (std::array{y.u_min, y.u_max, y.v_min, y.v_max}));
    }
    ASSERT_EQ(s.trim.has_value(), t.trim.has_value());
    if (!s.trim) continue;
    EXPECT_EQ(s.trim->rule, t.trim->rule);
    EXPECT_EQ(s.trim->tolerance, t.trim->tolerance);
    ASSERT_EQ(s.trim->loops.size(), t.trim->loops.size());
    for (std::size_t l = 0; l < s.trim->loops.size(); ++l) {
      const std::vector<TrimCurve>&a_curves = s.trim->loops[l].curves,
            &b_curves = t.trim->loops[l].curves;
      ASSERT_EQ(a_curves.size(), b_curves.size());
      for (std::size_t c = 0; c < a_curves.size(); ++c) {
        SCOPED_TRACE(testing::Message() << "loop " << l << " curve " << c);
        EXPECT_EQ(a_curves[c].degree, b_curves[c].degree);
        EXPECT_EQ(a_curves[c].knots, b_curves[c].knots);
        EXPECT_EQ(a_curves[c].points, b_curves[c].points);
        EXPECT_EQ(a_curves[c].weights, b_curves[c].weights);
      }
    }
  }
}

Scene builtin(std::string_view name) {
  std::optional<Scene> scene = make_builtin_scene(name);
  if (!scene) ADD_FAILURE() << name << " is not a built-in scene";
  return scene ? std::move(*scene) : Scene{};
}

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const BuiltinSceneInfo& s : builtin_scenes()) names.push_back(s.name);
  names.push_back("many-7");  // any N, not only the listed ones
  return names;
}

class BuiltinScene : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinScene, RoundTripsThroughJsonBitIdentically) {
  const Scene scene = builtin(GetParam());
  const std::string text = scene_to_json(scene);
  expect_identical(parse_scene_json(text, "round trip"), scene);
}

TEST_P(BuiltinScene, IsDeterministic) {
  expect_identical(builtin(GetParam()), builtin(GetParam()));
}

TEST_P(BuiltinScene, IsValid) {
  const Scene scene = builtin(GetParam());
  EXPECT_EQ(scene.name, GetParam());
  EXPECT_FALSE(scene.surfaces.empty());
  EXPECT_NO_THROW(validate_scene(scene, GetParam()));
}

INSTANTIATE_TEST_SUITE_P(All, BuiltinScene, ::testing::ValuesIn(builtin_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(SceneJson, WeightsAreOmittedWhenAllOne) {
  const std::string polynomial = scene_to_json(builtin("tan16"));
  EXPECT_EQ(polynomial.find("\"weights\""), std::string::npos);
  const Scene read = parse_scene_json(polynomial, "tan16.json");
  for (double w : read.surfaces[0].weights) EXPECT_EQ(w, 1.0);
  EXPECT_EQ(read.surfaces[0].weights.size(), 256u);

  EXPECT_NE(scene_to_json(builtin("patch144")).find("\"weights\""), std::string::npos);
  EXPECT_NE(scene_to_json(builtin("sphere")).find("\"weights\""), std::string::npos);
}

TEST(SceneJson, ShortestNumbersReadBackExactly) {
  Scene scene = builtin("patch144");
  // Values whose shortest form needs 17 digits, subnormals, the largest finite double; == on
  // these is a bitwise comparison (no zeros, no NaN).
  scene.surfaces[0].points[0] = {0.1 + 0.2, 5e-324, 1.7976931348623157e308};
  scene.surfaces[0].points[1] = {-1e-310, 1.0 / 3.0, -2.5e-300};
  scene.surfaces[0].weights[2] = 1.0 + 0x1p-52;
  expect_identical(parse_scene_json(scene_to_json(scene), "numbers"), scene);
}

TEST(SceneJson, OriginNamesTheFileInErrors) {
  try {
    parse_scene_json(R"({"format": "nurbs-scene/1", "surfaces": [], "extra": 1})", "my/scene.json");
    FAIL() << "accepted an unknown key";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("my/scene.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("extra"), std::string::npos) << e.what();
  }
}

TEST(SceneJson, ValidationErrorCarriesItsParts) {
  const std::string text = scene_to_json(builtin("patch144"));
  std::string bad = text;
  const std::string knots = "0, 0, 0, 0, 0.1, 0.25, 0.3, 0.5";
  ASSERT_NE(bad.find(knots), std::string::npos) << text.substr(0, 400);
  bad.replace(bad.find(knots), knots.size(), "0, 0, 0, 0, 0.1, 0.25, 0.3, 0.2");
  try {
    parse_scene_json(bad, "p.json");
    FAIL() << "accepted decreasing knots";
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.origin(), "p.json");
    EXPECT_EQ(e.surface(), "patch");
    EXPECT_EQ(e.surface_index(), 0);
    EXPECT_EQ(e.field(), "knots_u");
    EXPECT_EQ(e.index(), "7");
    EXPECT_EQ(e.value(), "0.2");
  }
}

// The file a user gets from `nurbsbench scene` evaluates exactly like the built-in scene.
TEST(SceneJson, CliSceneFileEvaluatesLikeTheBuiltin) {
  TempDir tmp;
  const std::string file = tmp / "patch144.json";
  const CliResult written = run_cli({"scene", "patch144", "--out", file});
  ASSERT_EQ(written.exit_code, 0) << written.err;
  EXPECT_EQ(test::read_text(file), scene_to_json(builtin("patch144")));

  const std::vector<std::string> common = {"--strategy", "cpu-coxdeboor", "--samples", "9x7",
                                           "--normals"};
  std::vector<std::string> from_file = {"eval", "--scene", file, "--out", tmp / "file.csv"};
  std::vector<std::string> from_name = {"eval", "--scene", "patch144", "--out", tmp / "name.csv"};
  from_file.insert(from_file.end(), common.begin(), common.end());
  from_name.insert(from_name.end(), common.begin(), common.end());
  const CliResult a = run_cli(from_file), b = run_cli(from_name);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const std::string csv = test::read_text(tmp / "file.csv");
  EXPECT_EQ(test::split_lines(csv).size(), 1u + 63u);
  EXPECT_EQ(csv, test::read_text(tmp / "name.csv"));

  // Without --out the scene goes to stdout.
  const CliResult printed = run_cli({"scene", "patch144"});
  ASSERT_EQ(printed.exit_code, 0) << printed.err;
  EXPECT_EQ(printed.out, scene_to_json(builtin("patch144")));
}

// ----------------------------------------------------------------------------- nurbs-scene/2

// A bilinear patch on [0, u_max] x [0, 1], so a trim's domain check reads the knots, not [0, 1]^2.
Surface plane(std::string name, double u_max) {
  Surface s;
  s.name = std::move(name);
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = {0, 0, u_max, u_max};
  s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {0, 1, 0}, {u_max, 0, 0}, {u_max, 1, 0.5}};
  s.weights = {1, 1, 1, 1};
  return s;
}

TrimCurve segment(Point2 a, Point2 b) {
  return TrimCurve{1, {0, 0, 1, 1}, {a, b}, {1, 1}};
}

TrimLoop polygon(const std::vector<Point2>& corners) {
  TrimLoop loop;
  for (std::size_t k = 0; k < corners.size(); ++k)
    loop.curves.push_back(segment(corners[k], corners[(k + 1) % corners.size()]));
  return loop;
}

// The exact circle of centre (cu, cv) and radius r: four rational quadratic arcs in one curve
// (The NURBS Book, Ex 7.2: corner weights sqrt(1/2), double interior knots).
TrimCurve circle(double cu, double cv, double r) {
  const double s = std::sqrt(0.5);
  TrimCurve c;
  c.degree = 2;
  c.knots = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
  c.points = {{cu + r, cv},     {cu + r, cv + r}, {cu, cv + r},     {cu - r, cv + r}, {cu - r, cv},
              {cu - r, cv - r}, {cu, cv - r},     {cu + r, cv - r}, {cu + r, cv}};
  c.weights = {1, s, 1, s, 1, s, 1, s, 1};
  return c;
}

// Uniform quadratic B-spline (unclamped): on [2, 3] it runs from the midpoint of P0 P1 to the
// midpoint of P1 P2, here (0.375, 0.5) to (0.625, 0.5); every value is exact in binary.
TrimCurve unclamped_arch() {
  return TrimCurve{2, {0, 1, 2, 3, 4, 5}, {{0.25, 0.25}, {0.5, 0.75}, {0.75, 0.25}}, {1, 1, 1}};
}

Scene trimmed_scene() {
  Scene scene{"trimmed", "a reversed face and a face with three trim loops", {}};
  Surface reversed = plane("reversed", 1);
  reversed.reversed = true;
  scene.surfaces.push_back(reversed);
  Surface face = plane("face", 2);
  Trim trim;
  trim.tolerance = 1e-7;
  trim.loops.push_back(TrimLoop{{circle(1, 0.5, 0.4)}});
  trim.loops.push_back(polygon({{0.875, 0.375}, {1.125, 0.375}, {1.125, 0.625}, {0.875, 0.625}}));
  trim.loops.push_back(TrimLoop{{unclamped_arch(), segment({0.625, 0.5}, {0.375, 0.5})}});
  trim.loops[2].curves[1].weights = {0.5, 3};  // a rational line: the weights still round-trip
  face.trim = trim;
  scene.surfaces.push_back(face);
  return scene;
}

TEST(SceneJsonV2, TrimsAndOrientationRoundTripExactly) {
  const Scene scene = trimmed_scene();
  ASSERT_NO_THROW(validate_scene(scene, "trimmed"));
  const std::string text = scene_to_json(scene);
  EXPECT_NE(text.find("\"format\": \"nurbs-scene/2\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"orientation\": \"reversed\""), std::string::npos) << text;
  const Scene read = parse_scene_json(text, "trimmed.json");
  expect_identical(read, scene);
  EXPECT_TRUE(read.surfaces[0].reversed);
  EXPECT_FALSE(read.surfaces[0].trim.has_value());
  EXPECT_FALSE(read.surfaces[1].reversed);
  // Written again, the text is the same: nothing is lost or reordered.
  EXPECT_EQ(scene_to_json(read), text);
}

TEST(SceneJsonV2, DefaultsAreEvenOddTolerance1e9AndUnitWeights) {
  const Scene scene = parse_scene_json(R"({"format": "nurbs-scene/2", "surfaces": [{
      "degree_u": 1, "degree_v": 1, "count_u": 2, "count_v": 2,
      "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
      "points": [[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0]],
      "orientation": "forward",
      "trim": {"loops": [{"curves": [
        {"degree": 1, "knots": [0, 0, 1, 1], "points": [[0.25, 0.25], [0.75, 0.25]]},
        {"degree": 1, "knots": [0, 0, 1, 1], "points": [[0.75, 0.25], [0.25, 0.25]]}]}]}}]})",
                                       "defaults.json");
  const Surface& s = scene.surfaces.at(0);
  EXPECT_FALSE(s.reversed);
  ASSERT_TRUE(s.trim.has_value());
  EXPECT_EQ(s.trim->rule, "even-odd");
  EXPECT_EQ(s.trim->tolerance, 1e-9);
  EXPECT_EQ(s.trim->loops.at(0).curves.at(1).weights, (std::vector<double>{1, 1}));
  // Unit weights are not written, a forward orientation neither.
  const std::string text = scene_to_json(scene);
  EXPECT_EQ(text.find("\"weights\""), std::string::npos) << text;
  EXPECT_EQ(text.find("\"orientation\""), std::string::npos) << text;
}

// A scene /1 can hold is written as /1, exactly as before /2 existed (expected text by hand).
TEST(SceneJsonV2, UntrimmedScenesAreWrittenAsVersion1ByteForByte) {
  const Scene scene{"tiny", "one bilinear patch", {plane("p", 2)}};
  EXPECT_EQ(scene_to_json(scene), R"({
  "format": "nurbs-scene/1",
  "name": "tiny",
  "description": "one bilinear patch",
  "surfaces": [
    {
      "name": "p",
      "degree_u": 1, "degree_v": 1,
      "count_u": 2, "count_v": 2,
      "knots_u": [0, 0, 2, 2],
      "knots_v": [0, 0, 1, 1],
      "points": [
        [0, 0, 0],
        [0, 1, 0],
        [2, 0, 0],
        [2, 1, 0.5]
      ]
    }
  ]
}
)");
  // Every built-in scene without a trim, a reversed face or a T-spline is written as /1
  // (trimmed-plate and the tspline-* / tsm-* scenes are /2).
  for (const std::string& name : builtin_names()) {
    SCOPED_TRACE(name);
    const Scene scene = builtin(name);
    const bool needs_v2 =
        scene.has_trims() ||
        std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                    [](const Surface& s) { return s.reversed || s.is_tspline(); });
    const std::string text = scene_to_json(scene);
    EXPECT_TRUE(
        text.starts_with(fmt::format("{{\n  \"format\": \"nurbs-scene/{}\",\n", needs_v2 ? 2 : 1)))
        << text.substr(0, 80);
    if (!needs_v2) {
      EXPECT_EQ(text.find("\"trim\""), std::string::npos);
    }
  }
}

// The ValidationError of parsing `scene` written out, for tests of one flaw.
std::optional<ValidationError> validation_error(const Scene& scene) {
  try {
    parse_scene_json(scene_to_json(scene), "bad.json");
  } catch (const ValidationError& e) {
    return e;
  }
  return std::nullopt;
}

TEST(SceneJsonV2, TrimErrorsNameTheFieldPath) {
  Scene scene{"faces", "", {}};
  for (int k = 0; k < 3; ++k) scene.surfaces.push_back(plane(fmt::format("face-{}", k), 1));
  Surface face = plane("face-3", 1);
  TrimLoop loop = polygon({{0.25, 0.25}, {0.75, 0.25}, {0.5, 0.75}});
  loop.curves[2] =
      TrimCurve{2, {0, 0, 0, 0.5, 0.3, 1}, {{0.5, 0.75}, {0.4, 0.5}, {0.25, 0.25}}, {1, 1, 1}};
  face.trim = Trim{"even-odd", 1e-9, {loop}};
  scene.surfaces.push_back(face);
  const std::optional<ValidationError> e = validation_error(scene);
  ASSERT_TRUE(e.has_value());
  EXPECT_STREQ(e->what(),
               "bad.json: surface 'face-3' (#3): trim.loops[0].curves[2].knots[4] = 0.3: knots "
               "must be non-decreasing (previous is 0.5)");
  EXPECT_EQ(e->surface_index(), 3);
  EXPECT_EQ(e->field(), "trim.loops[0].curves[2].knots");
  EXPECT_EQ(e->index(), "4");
  EXPECT_EQ(e->value(), "0.3");
}

// The surface's knot rules apply to trim curves word for word (one implementation).
TEST(SceneJsonV2, TrimKnotsFollowTheSurfaceRules) {
  Surface face = plane("face", 1);
  TrimLoop loop = polygon({{0.25, 0.25}, {0.75, 0.25}, {0.5, 0.75}});
  // Degree 1 with an interior double knot: the curve would jump there.
  loop.curves[0] = TrimCurve{1,
                             {0, 0, 0.5, 0.5, 1, 1},
                             {{0.25, 0.25}, {0.5, 0.25}, {0.6, 0.25}, {0.75, 0.25}},
                             {1, 1, 1, 1}};
  face.trim = Trim{"even-odd", 1e-9, {loop}};
  const std::optional<ValidationError> e = validation_error(Scene{"s", "", {face}});
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field(), "trim.loops[0].curves[0].knots");
  EXPECT_EQ(e->index(), "2");
  EXPECT_NE(e->rule().find("multiplicity 2 exceeds 1 (interior knots"), std::string::npos)
      << e->what();
}

// The end of an unclamped curve is evaluated: the midpoints of its control polygon's legs.
TEST(SceneJsonV2, UnclampedCurveEndsAreEvaluatedForClosure) {
  Surface face = plane("face", 1);
  face.trim =
      Trim{"even-odd", 1e-9, {TrimLoop{{unclamped_arch(), segment({0.625, 0.5}, {0.375, 0.5})}}}};
  EXPECT_NO_THROW(validate_surface(face, 0, "arch"));

  // Closing from the last control point instead of the curve's end leaves a gap there.
  face.trim->loops[0].curves[1] = segment({0.75, 0.25}, {0.375, 0.5});
  std::optional<ValidationError> e = validation_error(Scene{"s", "", {face}});
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field(), "trim.loops[0].curves[0].end");
  EXPECT_EQ(e->value(), "[0.625, 0.5]");
  EXPECT_NE(e->rule().find("start of curve 1 is [0.75, 0.25]"), std::string::npos) << e->what();

  // And back to the first control point instead of the curve's start.
  face.trim->loops[0].curves[1] = segment({0.625, 0.5}, {0.25, 0.25});
  e = validation_error(Scene{"s", "", {face}});
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field(), "trim.loops[0].curves[1].end");
  EXPECT_EQ(e->value(), "[0.25, 0.25]");
  EXPECT_NE(e->rule().find("start of curve 0 is [0.375, 0.5]"), std::string::npos) << e->what();
  // gap = |(0.25, 0.25) - (0.375, 0.5)| = sqrt(0.125^2 + 0.25^2) = sqrt(0.078125)
  EXPECT_NE(e->rule().find(fmt::format("a gap of {}", std::sqrt(0.078125))), std::string::npos)
      << e->what();
}

// The tolerance bounds both the gaps between curves and how far a control point may leave the
// domain.
TEST(SceneJsonV2, TheToleranceIsHonoured) {
  const auto with = [](double tolerance, double gap, double outside) {
    Surface face = plane("face", 1);
    TrimLoop loop = polygon({{-outside, 0.25}, {0.75, 0.25}, {0.5, 0.75}});
    loop.curves[2].points[1][1] += gap;  // the last curve ends `gap` above the first one's start
    face.trim = Trim{"even-odd", tolerance, {loop}};
    return validation_error(Scene{"s", "", {face}});
  };
  EXPECT_FALSE(with(1e-9, 5e-10, 0).has_value());
  EXPECT_FALSE(with(1e-9, 0, 5e-10).has_value());
  std::optional<ValidationError> e = with(1e-9, 2e-9, 0);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field(), "trim.loops[0].curves[2].end");
  e = with(1e-9, 0, 2e-9);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field(), "trim.loops[0].curves[0].points");
  EXPECT_EQ(e->index(), "0");
  EXPECT_FALSE(with(4e-9, 2e-9, 2e-9).has_value());
}

// ----------------------------------------------------------------------------- hardened input

std::string input_error(std::string_view text) {
  try {
    parse_scene_json(text, "in.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(SceneJsonInput, DuplicateKeysAreRefusedWithTheirPath) {
  const std::string surface = R"({"degree_u": 1, "degree_v": 1, "count_u": 2, "count_v": 2,
      "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
      "points": [[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0]]})";
  // The same keys in sibling objects are no duplicates.
  const std::string two =
      R"({"format": "nurbs-scene/1", "surfaces": [)" + surface + ", " + surface + "]}";
  EXPECT_EQ(parse_scene_json(two, "two.json").surfaces.size(), 2u);

  EXPECT_EQ(input_error(R"({"format": "nurbs-scene/1", "format": "nurbs-scene/1"})"),
            "in.json: format: duplicate key (each key may appear once)");
  std::string bad = two;
  bad.replace(bad.rfind("\"count_v\": 2"), 12, "\"count_v\": 2, \"count_v\": 3");
  EXPECT_EQ(input_error(bad),
            "in.json: surfaces[1].count_v: duplicate key (each key may appear once)");

  const std::string trimmed = scene_to_json(trimmed_scene());
  bad = trimmed;
  // The second loop's first curve: its "degree" again, after the arrays of the loops before it.
  const std::size_t second_loop = bad.find("\"curves\"", bad.find("\"curves\"") + 1);
  bad.insert(bad.find("\"degree\": 1,", second_loop) + 12, " \"degree\": 1,");
  EXPECT_EQ(input_error(bad),
            "in.json: surfaces[1].trim.loops[1].curves[0].degree: duplicate key (each key may "
            "appear once)");
  // A key is shown cut to 40 characters, so a megabyte of key makes no megabyte of message.
  const std::string long_key(1 << 20, 'k');
  EXPECT_EQ(input_error("{\"" + long_key + "\": 1, \"" + long_key + "\": 2}"),
            "in.json: " + std::string(37, 'k') + "...: duplicate key (each key may appear once)");
  bad = trimmed;
  bad.insert(bad.find("\"tolerance\""), "\"rule\": \"even-odd\", ");
  EXPECT_EQ(input_error(bad),
            "in.json: surfaces[1].trim.rule: duplicate key (each key may appear once)");
}

std::string nested(int levels) {
  return R"({"format": "nurbs-scene/1", "surfaces": )" + std::string(levels, '[') +
         std::string(levels, ']') + "}";
}

TEST(SceneJsonInput, NestingIsBoundedWhileParsing) {
  // The document object is level 1, so 63 brackets reach the limit of 64 and pass the parser
  // (to be refused as a surface that is not an object), 64 do not.
  EXPECT_NE(input_error(nested(kMaxJsonDepth - 1)).find("a surface must be a JSON object"),
            std::string::npos);
  const std::string refused = input_error(nested(kMaxJsonDepth));
  EXPECT_TRUE(refused.starts_with("in.json: surfaces[0]")) << refused;
  EXPECT_TRUE(refused.ends_with("[0]: nesting deeper than 64 levels")) << refused;
  // Far past any stack: refused as soon as the limit is crossed.
  EXPECT_NE(input_error(nested(300000)).find("nesting deeper than 64 levels"), std::string::npos);
  EXPECT_NE(input_error(std::string(300000, '[')).find("nesting deeper than 64 levels"),
            std::string::npos);
}

TEST(SceneJsonInput, SyntaxErrorsNameWhereTheyAre) {
  std::string text = scene_to_json(trimmed_scene());
  // The second loop's corner (0.875, 0.625) first appears as the end of its curve 2.
  const std::string point = "[0.875, 0.625]";
  ASSERT_NE(text.find(point), std::string::npos);
  text.replace(text.find(point), point.size(), "[0.875, 1e999]");
  const std::string error = input_error(text);
  EXPECT_TRUE(
      error.starts_with("in.json: not valid JSON at surfaces[1].trim.loops[1].curves[2]"
                        ".points[1][1]: number overflow parsing '1e999'"))
      << error;
}

// ----------------------------------------------------------------------------- built-in shapes

void expect_shape(const Surface& s, int degree, int count_u, int count_v) {
  EXPECT_EQ(s.degree_u, degree);
  EXPECT_EQ(s.degree_v, degree);
  EXPECT_EQ(s.count_u, count_u);
  EXPECT_EQ(s.count_v, count_v);
}

int non_empty_spans(const std::vector<double>& knots, int degree, int count) {
  int spans = 0;
  for (int k = degree; k < count; ++k) spans += knots[k] < knots[k + 1];
  return spans;
}

bool uniform_interior(const std::vector<double>& knots, int degree, int count) {
  const double step = knots[degree + 1] - knots[degree];
  for (int k = degree; k < count; ++k)
    if (std::abs((knots[k + 1] - knots[k]) - step) > 1e-12) return false;
  return true;
}

TEST(BuiltinShapes, Patch144IsBicubicTwelveByTwelveNonUniformRational) {
  const Scene scene = builtin("patch144");
  ASSERT_EQ(scene.surfaces.size(), 1u);
  const Surface& s = scene.surfaces[0];
  expect_shape(s, 3, 12, 12);
  EXPECT_FALSE(uniform_interior(s.knots_u, 3, 12));
  EXPECT_FALSE(uniform_interior(s.knots_v, 3, 12));
  EXPECT_TRUE(s.is_rational());
  EXPECT_NE(*std::min_element(s.weights.begin(), s.weights.end()),
            *std::max_element(s.weights.begin(), s.weights.end()));
  // 9 non-empty spans per direction (the paper's 000 §5 patch).
  EXPECT_EQ(non_empty_spans(s.knots_u, 3, 12), 9);
  EXPECT_EQ(non_empty_spans(s.knots_v, 3, 12), 9);
}

TEST(BuiltinShapes, TanScenesAreBicubicNets) {
  for (int n : {16, 64, 256}) {
    SCOPED_TRACE(n);
    const Scene scene = builtin("tan" + std::to_string(n));
    ASSERT_EQ(scene.surfaces.size(), 1u);
    expect_shape(scene.surfaces[0], 3, n, n);
    EXPECT_TRUE(uniform_interior(scene.surfaces[0].knots_u, 3, n));
  }
  const Scene lod = builtin("tan21x23");
  ASSERT_EQ(lod.surfaces.size(), 1u);
  expect_shape(lod.surfaces[0], 3, 21, 23);
}

TEST(BuiltinShapes, DegreeScenesShareOneNetWithRisingDegree) {
  const Scene first = builtin("degree-1");
  for (int p = 1; p <= 9; ++p) {
    SCOPED_TRACE(p);
    const Scene scene = builtin("degree-" + std::to_string(p));
    ASSERT_EQ(scene.surfaces.size(), 1u);
    const Surface& s = scene.surfaces[0];
    expect_shape(s, p, 16, 16);
    EXPECT_EQ(coordinates(s.points), coordinates(first.surfaces[0].points));
    EXPECT_EQ(s.knots_u.size(), static_cast<std::size_t>(16 + p + 1));
  }
  EXPECT_FALSE(make_builtin_scene("degree-10").has_value());
  EXPECT_FALSE(make_builtin_scene("degree-0").has_value());
}

// The longest run of equal interior knots.
int max_interior_multiplicity(const std::vector<double>& knots, int degree, int count) {
  int best = 0;
  for (int k = degree + 1; k < count;) {
    int m = 1;
    while (k + m < count && knots[k + m] == knots[k]) ++m;
    best = std::max(best, m);
    k += m;
  }
  return best;
}

TEST(BuiltinShapes, CreasesHaveFullMultiplicityInteriorKnots) {
  const Surface s = builtin("creases").surfaces.at(0);
  EXPECT_EQ(max_interior_multiplicity(s.knots_u, s.degree_u, s.count_u), s.degree_u);
  EXPECT_EQ(max_interior_multiplicity(s.knots_v, s.degree_v, s.count_v), s.degree_v);
  // patch144, for contrast, has only simple interior knots.
  const Surface p = builtin("patch144").surfaces.at(0);
  EXPECT_EQ(max_interior_multiplicity(p.knots_u, 3, 12), 1);
}

TEST(BuiltinShapes, FarOriginIsFarFromTheOrigin) {
  const Scene scene = builtin("far-origin");
  for (const Surface& s : scene.surfaces)
    for (const Point3& p : s.points)
      for (double c : p) EXPECT_GT(c, 9000.0);
}

// Its values come from mt19937_64, whose sequence the standard fixes (the 10000th output of the
// default-seeded engine is 9981545732273789042), mapped by our own code, not a library
// distribution: so the surface is the same with every standard library.
TEST(BuiltinShapes, RandomBicubicIsTheSameSurfaceEverywhere) {
  std::mt19937_64 engine;
  engine.discard(9999);
  ASSERT_EQ(engine(), 9981545732273789042ull);
  const Surface s = builtin("random-bicubic-12x12").surfaces.at(0);
  expect_shape(s, 3, 12, 12);
  EXPECT_TRUE(s.is_rational());
  EXPECT_EQ(s.knots_u[4], 0.006194300581681911);
  EXPECT_EQ(s.knots_v[11], 0.9339793845650242);
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    EXPECT_GE(s.weights[k], 0.5);
    EXPECT_LE(s.weights[k], 2.0);
    for (double c : s.points[k]) EXPECT_LE(std::abs(c), 10.0);
  }
}

TEST(BuiltinShapes, TeapotIsThirtyTwoBicubicBezierPatches) {
  const Scene scene = builtin("teapot");
  ASSERT_EQ(scene.surfaces.size(), 32u);
  for (const Surface& s : scene.surfaces) expect_shape(s, 3, 4, 4);
}

TEST(BuiltinShapes, DuckHasThreeSurfaces) {
  const Scene scene = builtin("duck");
  EXPECT_EQ(scene.surfaces.size(), 3u);
  EXPECT_TRUE(std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                          [](const Surface& s) { return s.is_rational(); }));
}

TEST(BuiltinShapes, ManyNHasNPatches) {
  for (int n : {1, 7, 4096}) {
    SCOPED_TRACE(n);
    const Scene scene = builtin("many-" + std::to_string(n));
    ASSERT_EQ(scene.surfaces.size(), static_cast<std::size_t>(n));
    for (const Surface& s : {scene.surfaces.front(), scene.surfaces.back()})
      expect_shape(s, 3, 4, 4);
  }
  for (const char* bad : {"many-0", "many-4097", "many-x", "many-", "many--1", "many-1x", "many"}) {
    SCOPED_TRACE(bad);
    EXPECT_FALSE(make_builtin_scene(bad).has_value());
    try {
      load_scene(bad);
      ADD_FAILURE() << "load_scene accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("many-N for N = 1..4096"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace nurbs
