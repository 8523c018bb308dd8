// scenes/: the nurbs-scene/1 writer reads back exactly (every double equal), and the built-in
// scenes have the shapes the papers' experiments need (DESIGN.md, "Scene file format";
// builtin_scenes.h).
#include "scenes/scene_json.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "../cli/run_cli.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"

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
