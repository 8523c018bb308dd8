// The C++ compile of the single-source direct-trimming classifier (strategies/trim_direct/
// trim_direct.h, the same text the OpenCL kernel and the GLSL shaders compile) against the
// reference classifier, which isolates the roots of the whole pieces on its own: the gate is the
// issue's, 0 misclassified samples outside the band. Suites are named after the strategies
// (trim_direct, cl_stair_trim, vk_ksquad_trim) so that `ctest -R "vk_ksquad|cl_stair|trim"`
// selects them.
#include <gtest/gtest.h>

#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/trim_direct/trim_tables.h"
#include "tests/scenes/high_degree_trim.h"
#include "tests/strategies/trim_direct/strategy_trim_check.h"

namespace nurbs {
namespace {

template <typename T>
void expect_exact_on(const std::string& scene_name, const Sampling& sampling,
                     std::optional<Scene> scene = std::nullopt) {
  if (!scene) scene = make_builtin_scene(scene_name);
  ASSERT_TRUE(scene);
  const trim_direct::Settings settings;
  const auto tables = trim_direct::build_tables<T>(*scene, settings);
  const auto samples = sample_parameters(*scene, sampling);
  test::TrimMismatch total;
  trim_direct::Cost cost;
  for (std::size_t i = 0; i < scene->surfaces.size(); ++i) {
    if (!scene->surfaces[i].trim) continue;
    const auto inside =
        trim_direct::classify_samples(tables, i, samples[i], settings.iterations, &cost);
    total += test::compare_with_reference(scene->surfaces[i], samples[i], inside);
  }
  std::printf(
      "%s (%s, %zu pieces, %zu rows, %zu row entries): %zu of %zu samples outside the "
      "band misclassified (%zu in it), reads per sample mean %.2f max %d\n",
      scene_name.c_str(), sizeof(T) == 4 ? "float" : "double", tables.pieces, tables.rows,
      tables.entries, total.misclassified, total.compared, total.in_band,
      static_cast<double>(cost.reads) / cost.samples, cost.max_reads);
  EXPECT_EQ(total.misclassified, 0u) << scene_name;
  EXPECT_GT(total.inside, 0u) << "not all one answer";
  EXPECT_LT(total.inside, total.compared) << "not all one answer";
  // Bound on the cost: a sample reads at most the header and breaks (4), the binary search
  // (log2 rows + 1), the row bounds (2), and for each entry of its row 4 + 3 (degree + 1) --
  // the row's entries are the pieces it may cross.
  EXPECT_LE(cost.max_reads, test::max_reads_bound(tables)) << scene_name;
}

using test::trim_grid;

TEST(trim_direct, TrimmedPlateFloatAndDouble) {
  expect_exact_on<float>("trimmed-plate", trim_grid(97));
  expect_exact_on<double>("trimmed-plate", trim_grid(97));
}

TEST(trim_direct, HammerFloatAndDouble) {
  expect_exact_on<float>("hammer", trim_grid(33));
  expect_exact_on<double>("hammer", trim_grid(33));
}

// Trim curves of degree 9 to 15 (kMaxDegree), rational, several pieces each: the same gate.
TEST(trim_direct, TrimCurvesUpToDegree15) {
  for (int degree = 9; degree <= kMaxDegree; ++degree) {
    const Scene scene = test::high_degree_trim_scene(degree);
    validate_scene(scene, "high_degree_trim_scene");
    expect_exact_on<float>(scene.surfaces[0].name, trim_grid(65), scene);
    expect_exact_on<double>(scene.surfaces[0].name, trim_grid(65), scene);
    for (const auto& piece : trim_direct::monotone_pieces(*scene.surfaces[0].trim, 0, 0))
      EXPECT_TRUE(piece.degree == degree || piece.degree == 1) << piece.degree;
  }
}

void expect_monotone_pieces(const Scene& scene) {
  for (const Surface& s : scene.surfaces) {
    const auto pieces = trim_direct::monotone_pieces(*s.trim, 0, 0);
    ASSERT_FALSE(pieces.empty());
    for (const auto& p : pieces) {
      // Monotone: the control polygon need not be, but the curve's samples are.
      for (int c = 0; c < 2; ++c) {
        int sign = 0;
        double previous = p.points.front()[c];
        for (int k = 1; k <= 64; ++k) {
          const double t = k / 64.0;
          double num = 0, den = 0;
          for (int i = 0; i <= p.degree; ++i) {
            double b = 1;  // Bernstein basis by the binomial formula
            for (int j = 1; j <= i; ++j) b = b * (p.degree - i + j) / j;
            b *= std::pow(t, i) * std::pow(1 - t, p.degree - i);
            num += b * p.points[i][2] * p.points[i][c];
            den += b * p.points[i][2];
          }
          const double x = num / den, d = x - previous;
          const double tolerance = 1e-12 * (1 + std::abs(x));
          if (std::abs(d) > tolerance) {
            const int s_now = d > 0 ? 1 : -1;
            EXPECT_TRUE(sign == 0 || sign == s_now) << "not monotone in " << c;
            sign = s_now;
          }
          previous = x;
        }
      }
    }
  }
}

TEST(trim_direct, PiecesAreMonotone) {
  expect_monotone_pieces(*make_builtin_scene("hammer"));
  for (int degree = 9; degree <= kMaxDegree; degree += 3)
    expect_monotone_pieces(test::high_degree_trim_scene(degree));
}

// The gate can fail: stopping the bisection at 5% of the diagonal misclassifies samples well
// outside the band.
TEST(trim_direct, CoarseEpsilonMisclassifies) {
  const Scene scene = *make_builtin_scene("trimmed-plate");
  trim_direct::Settings coarse;
  coarse.epsilon = 0.05;
  const auto tables = trim_direct::build_tables<float>(scene, coarse);
  const auto samples = sample_parameters(scene, trim_grid(97));
  const auto inside = trim_direct::classify_samples(tables, 0, samples[0], coarse.iterations);
  EXPECT_GT(test::compare_with_reference(scene.surfaces[0], samples[0], inside).misclassified, 0u);
}

TEST(trim_direct, OptionsAreValidated) {
  StrategyOptions o;
  EXPECT_EQ(trim_direct::settings_from(o, "x").iterations, trim_direct::Settings{}.iterations);
  o.extra = {{"trim-epsilon", "1e-6"}, {"trim-iterations", "12"}};
  const auto s = trim_direct::settings_from(o, "x");
  EXPECT_EQ(s.epsilon, 1e-6);
  EXPECT_EQ(s.iterations, 12);
  test::expect_trim_options_refused(
      [](const StrategyOptions& bad) { trim_direct::settings_from(bad, "vk-ksquad"); },
      "vk-ksquad");
}

}  // namespace
}  // namespace nurbs
