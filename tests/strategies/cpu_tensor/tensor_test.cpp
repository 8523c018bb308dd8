// cpu-tensor: thread count changes nothing (every row is computed by one thread with the same
// operations), f64 agrees with cpu-coxdeboor to double precision, explicit lists are refused.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <map>
#include <string>

#include "harness/runner.h"
#include "reference/nurbs_math.h"
#include "reference/sampling.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

EvalResult run(const std::string& name, const Scene& scene, const EvalRequest& request, int threads,
               std::map<std::string, std::string> extra = {}) {
  StrategyOptions options;
  options.threads = threads;
  options.extra = std::move(extra);
  auto s = find_strategy(name)->create(options);
  s->prepare(scene, request);
  s->evaluate();
  return s->read_back();
}

TEST(CpuTensor, ThreadCountGivesIdenticalResults) {
  for (const char* scene_name : {"patch144", "many-16", "sphere"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    for (Precision precision : {Precision::f32, Precision::f64}) {
      Sampling grid;
      grid.grid_u = 37;
      grid.grid_v = 41;
      const EvalRequest request{grid, precision, true};
      const EvalResult one = run("cpu-tensor", scene, request, 1);
      for (int threads : {2, 3}) {
        const EvalResult many = run("cpu-tensor", scene, request, threads);
        for (std::size_t i = 0; i < one.surfaces.size(); ++i)
          for (std::size_t k = 0; k < one.surfaces[i].positions.size(); ++k) {
            ASSERT_EQ(one.surfaces[i].positions[k], many.surfaces[i].positions[k]) << scene_name;
            ASSERT_EQ(one.surfaces[i].normals[k], many.surfaces[i].normals[k]) << scene_name;
          }
      }
    }
  }
}

// f64 positions within 64 double ulps of the scene's largest coordinate of cpu-coxdeboor's, which
// evaluates each sample on its own (A2.2 + A4.3, no tables, always the homogeneous divide).
void expect_agrees_with_coxdeboor(const Scene& scene, const Sampling& sampling) {
  const EvalRequest request{sampling, Precision::f64, false};
  const EvalResult tensor = run("cpu-tensor", scene, request, 0);
  const EvalResult cox = run("cpu-coxdeboor", scene, request, 0);
  const double tolerance = 64 * DBL_EPSILON * scene.largest_coordinate();
  for (std::size_t i = 0; i < tensor.surfaces.size(); ++i)
    for (std::size_t k = 0; k < tensor.surfaces[i].positions.size(); ++k)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(tensor.surfaces[i].positions[k][c], cox.surfaces[i].positions[k][c], tolerance)
            << scene.name << " surface " << i << " sample " << k;
}

// many-16's weights are all 1: its positions take the kernel's polynomial path.
TEST(CpuTensor, AgreesWithCoxDeBoorInDoublePrecision) {
  for (const char* scene_name : {"patch144", "torus", "degree-7", "creases", "many-16"}) {
    expect_agrees_with_coxdeboor(*make_builtin_scene(scene_name), test::span_grid(5));
  }
}

// simd=off runs the same kernels compiled without vectorisation: the same sums in the same order,
// so the results agree to the last bits FMA contraction may change (the AVX2/AVX-512 clones fuse
// multiply-adds, the baseline build cannot).
TEST(CpuTensor, SimdOffAgreesAndSaysSo) {
  const Scene scene = *make_builtin_scene("patch144");
  Sampling grid;
  grid.grid_u = 33;
  grid.grid_v = 29;
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalRequest request{grid, precision, true};
    const EvalResult simd = run("cpu-tensor", scene, request, 2);
    const EvalResult scalar = run("cpu-tensor", scene, request, 2, {{"simd", "off"}});
    const double eps = precision == Precision::f32 ? FLT_EPSILON : DBL_EPSILON;
    const double tolerance = 8 * eps * scene.largest_coordinate();
    for (std::size_t k = 0; k < simd.surfaces[0].positions.size(); ++k)
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(simd.surfaces[0].positions[k][c], scalar.surfaces[0].positions[k][c],
                    tolerance);
        ASSERT_NEAR(simd.surfaces[0].normals[k][c], scalar.surfaces[0].normals[k][c], 64 * eps);
      }
  }
  StrategyOptions off;
  off.extra["simd"] = "off";
  EXPECT_EQ(find_strategy("cpu-tensor")->create(off)->device().details.at("simd").rfind("off", 0),
            0u);
  off.extra["simd"] = "fast";
  EXPECT_THROW(find_strategy("cpu-tensor")->create(off), std::invalid_argument);
}

// Faces of one knot vector and sampling share their basis tables (many-N's Bezier patches), faces
// of others have their own: a scene mixing both evaluates every face exactly as that face alone
// does, and in double agrees with cpu-coxdeboor, which shares nothing.
TEST(CpuTensor, SharedTablesGiveEachFaceItsOwnValues) {
  Scene mixed{"mixed", "shared and distinct knot vectors", {}};
  for (const char* name : {"many-9", "patch144", "sphere", "degree-5", "many-4"}) {
    const Scene part = *make_builtin_scene(name);
    mixed.surfaces.insert(mixed.surfaces.end(), part.surfaces.begin(), part.surfaces.end());
  }
  const Sampling grid = test::grid(23, 19);
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalRequest request{grid, precision, true};
    const EvalResult all = run("cpu-tensor", mixed, request, 2);
    for (std::size_t i = 0; i < mixed.surfaces.size(); ++i) {
      const Scene alone{"alone", "", {mixed.surfaces[i]}};
      const EvalResult one = run("cpu-tensor", alone, request, 2);
      for (std::size_t k = 0; k < one.surfaces[0].positions.size(); ++k) {
        ASSERT_EQ(all.surfaces[i].positions[k], one.surfaces[0].positions[k]) << "surface " << i;
        ASSERT_EQ(all.surfaces[i].normals[k], one.surfaces[0].normals[k]) << "surface " << i;
      }
    }
  }
  expect_agrees_with_coxdeboor(mixed, grid);
}

// stores=streaming copies each finished row out with non-temporal stores, stores=cached (the
// default) writes in place: the same arithmetic, so the same bits, on row lengths whose rows start
// at every 16-byte misalignment (13 columns: 39 floats a row).
TEST(CpuTensor, StreamingStoresWriteTheSameValues) {
  const Scene scene = *make_builtin_scene("many-16");
  for (int columns : {13, 64}) {
    const Sampling grid = test::grid(11, columns);
    for (Precision precision : {Precision::f32, Precision::f64})
      for (bool normals : {false, true}) {
        const EvalRequest request{grid, precision, normals};
        const EvalResult cached = run("cpu-tensor", scene, request, 2, {{"stores", "cached"}});
        const EvalResult streamed = run("cpu-tensor", scene, request, 2, {{"stores", "streaming"}});
        for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
          for (std::size_t k = 0; k < cached.surfaces[i].positions.size(); ++k) {
            ASSERT_EQ(cached.surfaces[i].positions[k], streamed.surfaces[i].positions[k]);
            if (normals) {
              ASSERT_EQ(cached.surfaces[i].normals[k], streamed.surfaces[i].normals[k]);
            }
          }
      }
  }
  StrategyOptions bad;
  bad.extra["stores"] = "fast";
  try {
    find_strategy("cpu-tensor")->create(bad);
    FAIL() << "stores=fast accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("stores = 'fast'"), std::string::npos) << e.what();
  }
}

// Where Su x Sv vanishes (an edge of the net collapsed to a point) the kernel flags the samples
// and the reference's own surface_normal finishes them: every normal, the edge's limit normals
// included, is the reference's, unit length and finite. A row whose flags went unseen would keep
// the kernel's 0/0 there.
TEST(CpuTensor, CollapsedEdgeNormalsAreTheReferencesLimitNormals) {
  test::Rng rng(61);
  Surface s = test::random_surface(rng, 3, 3, 7, 6, test::Ends::clamped, true);
  for (int j = 1; j < s.count_v; ++j) s.points[j] = s.points[0];  // the edge u = u_min
  const Scene scene{"collapsed", "first row of the net one point", {s}};
  Sampling grid;
  grid.grid_u = 9;
  grid.grid_v = 11;
  const SurfaceNet<double> net(s);
  const SurfaceSamples samples = sample_parameters(scene, grid)[0];
  // Sv = 0 along it, up to the rounding of equal points' weighted sums
  ASSERT_LT(norm(surface_derivatives(net, samples.u[0], samples.v[5], 1).skl[0][1]), 1e-12)
      << "the edge u = u_min must be collapsed";
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalResult result = run("cpu-tensor", scene, EvalRequest{grid, precision, true}, 2);
    const double tolerance = precision == Precision::f64 ? 1e-9 : 1e-3;
    for (std::size_t k = 0; k < samples.count(); ++k) {
      const Vec3<double> expected = surface_normal(net, samples.u_of(k), samples.v_of(k));
      const std::array<double, 3>& got = result.surfaces[0].normals[k];
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(got[c], expected[c], tolerance) << to_string(precision) << " sample " << k;
    }
  }
}

TEST(CpuTensor, RefusesExplicitLists) {
  const StrategyEntry& entry = *find_strategy("cpu-tensor");
  Sampling list;
  list.mode = SamplingMode::explicit_list;
  list.explicit_uv = {{{0.5, 0.5}}};
  const Scene scene = *make_builtin_scene("patch144");
  EXPECT_TRUE(
      refusal_reason(entry.capabilities(), scene, EvalRequest{list, Precision::f32, false}));
}

}  // namespace
}  // namespace nurbs
