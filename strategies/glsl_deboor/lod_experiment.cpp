#include "strategies/glsl_deboor/lod_experiment.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>

#include "reference/nurbs_math.h"
#include "reference/sampling.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_context/grid_renderer.h"
#include "strategies/glsl_deboor/haar_lod.h"

namespace nurbs::glsl_deboor {

namespace {

// One warm-up (llvmpipe compiles shader variants at the first draw), then `repetitions` timed
// runs, each ended by glFinish so the device work is inside the time.
std::vector<double> time_runs(gl::Context& context, int repetitions, const auto& work) {
  work();
  context.finish("glsl-deboor lod");
  std::vector<double> seconds;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    context.finish("glsl-deboor lod");
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return seconds;
}

// Means of consecutive blocks of `block` parameters: the parameter a level-k average stands for.
std::vector<long double> block_means(const std::vector<double>& parameters, int block) {
  std::vector<long double> means(parameters.size() / static_cast<std::size_t>(block), 0.0L);
  for (std::size_t i = 0; i < parameters.size(); ++i) means[i / block] += parameters[i];
  for (long double& m : means) m /= block;
  return means;
}

// Draws `grid` in `repetitions` timed frames; the image and its coverage from the last.
LodDraw timed_draw(gl::Context& context, gl::GridRenderer& renderer, const gl::GridPoints& grid,
                   const float mvp[16], int repetitions, bool picture) {
  LodDraw d;
  // Built once per level before any draw, as 002 compiles each level's index data to a display
  // list: the draws then reuse it.
  d.index_elements = renderer.rebuild_index_buffer(grid.nu, grid.nv);
  d.seconds = time_runs(context, repetitions, [&] {
    renderer.begin_frame();
    renderer.draw(grid, mvp, nullptr);
    renderer.end_frame("glsl-deboor lod draw");
  });
  const std::vector<unsigned char> image = renderer.image();
  for (std::size_t i = 3; i < image.size(); i += 4) d.drawn_pixels += image[i] != 0;
  if (picture) d.picture = renderer.picture();
  return d;
}

}  // namespace

LodMeasurement measure_lod(const Scene& scene, int nu, int nv, int levels, int repetitions,
                           const StrategyOptions& options, bool pictures) {
  const int divisor = 1 << levels;
  if (scene.surfaces.empty() || levels < 1 || nu % divisor != 0 || nv % divisor != 0)
    throw RefusedError(fmt::format("lod: a {}x{} grid does not halve {} times", nu, nv, levels));
  // The experiment is about one surface; a scene of several uses its first.
  Scene single{scene.name, scene.description, {scene.surfaces.front()}};
  std::unique_ptr<gl::Context> context;
  try {
    context = gl::Context::create(gl::platform_option(options));
  } catch (const gl::UnavailableError& e) {
    throw std::runtime_error(fmt::format("unavailable: {}", e.what()));
  }
  const int tile = std::min(context->max_texture_size(), context->max_viewport());
  auto evaluated_at = [&](int width, int height) {
    Sampling grid;
    grid.grid_u = width;
    grid.grid_v = height;
    auto evaluator = std::make_unique<Evaluator>(*context, tile);
    evaluator->prepare(single, sample_parameters(single, grid));
    evaluator->evaluate();
    return evaluator;
  };
  const auto fine = evaluated_at(nu, nv);
  const auto coarse = evaluated_at(nu / 2, nv / 2);
  if (fine->pages().size() != 1)
    throw RefusedError(fmt::format("lod: a {}x{} grid does not fit one texture", nu, nv));
  HaarLod lod(*context, fine->pages()[0], fine->pages()[0].slots[0], levels);

  LodMeasurement m;
  m.device = context->device_info();
  m.coarser_by_haar = time_runs(*context, repetitions, [&] { lod.forward(0); });
  m.coarser_by_reevaluation = time_runs(*context, repetitions, [&] { coarse->evaluate(); });
  m.finer_by_haar = time_runs(*context, repetitions, [&] { lod.inverse(0); });
  m.finer_by_reevaluation = time_runs(*context, repetitions, [&] { fine->evaluate(); });
  gl::GridRenderer renderer(*context, kLodRenderSize, kLodRenderSize);
  auto full_reevaluation = [&](Evaluator& evaluator, int width, int height, int& elements) {
    evaluator.evaluate();
    const std::vector<std::vector<float>> xyz = evaluator.read_back();
    renderer.upload_vertices(xyz[0].data(), width, height);
    elements = renderer.rebuild_index_buffer(width, height);
  };
  m.coarser_by_full_reevaluation = time_runs(*context, repetitions, [&] {
    full_reevaluation(*coarse, nu / 2, nv / 2, m.coarser_index_elements);
  });
  m.finer_by_full_reevaluation = time_runs(
      *context, repetitions, [&] { full_reevaluation(*fine, nu, nv, m.finer_index_elements); });

  // Levels 1..levels from the (re-)evaluated grid, each against the surface in long double.
  fine->evaluate();
  for (int k = 0; k < levels; ++k) lod.forward(k);
  const std::array<float, 16> view = gl::orthographic_view(single);
  m.full_draw = timed_draw(*context, renderer, lod.grid(0), view.data(), repetitions, pictures);
  const SurfaceNet<long double> net(single.surfaces[0]);
  Sampling grid;
  grid.grid_u = nu;
  grid.grid_v = nv;
  const SurfaceSamples samples = sample_parameters(single, grid)[0];
  for (int k = 1; k <= levels; ++k) {
    const std::vector<float> level = lod.read(k);
    const int width = lod.width(k), height = lod.height(k);
    const std::vector<long double> u = block_means(samples.u, nu / width);
    const std::vector<long double> v = block_means(samples.v, nv / height);
    double worst = 0;
    for (int a = 0; a < width; ++a)
      for (int b = 0; b < height; ++b) {
        const Vec3<long double> s = surface_point(net, u[a], v[b]);
        const float* p = &level[(static_cast<std::size_t>(a) * height + b) * 3];
        worst =
            std::max(worst, static_cast<double>(std::hypot(p[0] - s[0], p[1] - s[1], p[2] - s[2])));
      }
    m.levels.push_back(
        {k, width, height, worst,
         timed_draw(*context, renderer, lod.grid(k), view.data(), repetitions, pictures)});
  }
  context->check("lod experiment");
  return m;
}

}  // namespace nurbs::glsl_deboor
