// `nurbsbench lod`: 002 Fig 15 on this machine (strategies/glsl_deboor/lod_experiment.h), one row
// per grid size: the level change by one Haar step versus re-evaluation (the de Boor passes alone,
// and with the read-back, vertex upload and index rebuild 002's baseline pays), both directions;
// each level drawn from its texture, timed; each coarser level's distance to the surface. Writes
// DIR/lod.json (nurbsbench-lod/1: the fields added since are optional to its readers) and, with
// --images, DIR/lod__<scene>__<samples>__L<level>.png.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "harness/error_image.h"
#include "harness/machine.h"
#include "harness/metrics.h"
#include "harness/side_files.h"
#include "harness/timing.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/glsl_deboor/lod_experiment.h"

namespace nurbs::cli {

int lod_command(const LodOptions& options) {
  // Everything is checked before the output directory is touched.
  const int threads = apply_thread_setting(options.threads);
  if (options.levels < 1 || options.levels > 8)
    throw InputError(fmt::format("--levels = {}: must be in 1..8", options.levels));
  if (options.repetitions < 1 || options.repetitions > 1000)
    throw InputError(fmt::format("--repetitions = {}: must be in 1..1000", options.repetitions));
  const Scene scene = load_scene(options.scene);
  if (scene.surfaces.size() != 1)
    throw InputError(fmt::format(
        "--scene '{}': has {} surfaces; the LOD experiment (002 §4.3) takes a one-surface scene",
        options.scene, scene.surfaces.size()));
  if (scene.surfaces[0].is_tspline())
    throw InputError(fmt::format(
        "--scene '{}': is a T-spline; the LOD experiment (002 §4.3, glsl-deboor) takes a NURBS "
        "surface",
        options.scene));
  const std::vector<Sampling> grids = parse_grid_list("--samples", options.samples);
  const int divisor = 1 << options.levels;
  for (const Sampling& g : grids)
    if (g.grid_u % divisor != 0 || g.grid_v % divisor != 0)
      throw InputError(fmt::format(
          "--samples = '{}': {} does not halve {} times (--levels); use multiples of {}",
          options.samples, g.label(), options.levels, divisor));

  if (!options.images.empty()) prepare_image_directory("--images", options.images);

  const double largest = scene.largest_coordinate();
  LodFile file;
  std::string changes =
      fmt::format("{:<11} {:>13} {:>13} {:>13} {:>6} {:>10}   {:>13} {:>13} {:>13} {:>6} {:>10}\n",
                  "samples", "coarser: Haar", "re-evaluate", "full re-eval", "ratio", "full ratio",
                  "finer: Haar", "re-evaluate", "full re-eval", "ratio", "full ratio");
  std::string draws =
      fmt::format("{:<11} {:>5} {:>11} {:>11} {:>14} {:>12} {:>16}\n", "samples", "level",
                  "level grid", "draw", "index elements", "drawn pixels", "max distance");
  std::string device;
  for (const Sampling& g : grids) {
    const glsl_deboor::LodMeasurement m =
        glsl_deboor::measure_lod(scene, g.grid_u, g.grid_v, options.levels, options.repetitions,
                                 {threads, backend_extra(options.gl, "")}, !options.images.empty());
    const double coarser_haar = PhaseStats::of(m.coarser_by_haar).median_s;
    const double coarser_eval = PhaseStats::of(m.coarser_by_reevaluation).median_s;
    const double coarser_full = PhaseStats::of(m.coarser_by_full_reevaluation).median_s;
    const double finer_haar = PhaseStats::of(m.finer_by_haar).median_s;
    const double finer_eval = PhaseStats::of(m.finer_by_reevaluation).median_s;
    const double finer_full = PhaseStats::of(m.finer_by_full_reevaluation).median_s;
    // Level 0 is the evaluated grid itself: drawn like the levels, no distance of its own.
    auto add_draw = [&](int level, int width, int height, const glsl_deboor::LodDraw& d,
                        std::optional<double> distance) {
      const double seconds = PhaseStats::of(d.seconds).median_s;
      draws +=
          fmt::format("{:<11} {:>5} {:>11} {:>8.3f} ms {:>14} {:>12} {:>16}\n", g.label(), level,
                      fmt::format("{}x{}", width, height), seconds * 1e3, d.index_elements,
                      d.drawn_pixels, distance ? fmt::format("{:.2e}", *distance) : "-");
      if (d.picture)
        write_render_image(
            std::filesystem::path(options.images) /
                safe_file_name(fmt::format("lod__{}__{}__L{}.png", scene.name, g.label(), level)),
            *d.picture,
            fmt::format("glsl-deboor Haar level {} ({}x{}) of {} at {}", level, width, height,
                        scene.name, g.label()));
      return LodDrawFields{seconds, d.index_elements, d.drawn_pixels};
    };
    LodRow row;
    row.scene = scene.name;
    row.samples = g.label();
    row.device = {m.device.name, m.device.kind};
    row.repetitions = options.repetitions;
    row.coarser_by_haar_s = coarser_haar;
    row.coarser_by_reevaluation_s = coarser_eval;
    row.coarser_by_full_reevaluation_s = coarser_full;
    row.coarser_index_elements = m.coarser_index_elements;
    row.finer_by_haar_s = finer_haar;
    row.finer_by_reevaluation_s = finer_eval;
    row.finer_by_full_reevaluation_s = finer_full;
    row.finer_index_elements = m.finer_index_elements;
    row.draw = add_draw(0, g.grid_u, g.grid_v, m.full_draw, std::nullopt);
    for (const glsl_deboor::LodLevel& l : m.levels)
      row.levels.push_back({l.level, fmt::format("{}x{}", l.width, l.height), l.max_distance,
                            ulps_of_largest_coordinate(l.max_distance, largest),
                            add_draw(l.level, l.width, l.height, l.draw, l.max_distance)});
    file.rows.push_back(std::move(row));
    changes += fmt::format(
        "{:<11} {:>10.3f} ms {:>10.3f} ms {:>10.3f} ms {:>5.2f}x {:>9.2f}x   {:>10.3f} ms "
        "{:>10.3f} ms {:>10.3f} ms {:>5.2f}x {:>9.2f}x\n",
        g.label(), coarser_haar * 1e3, coarser_eval * 1e3, coarser_full * 1e3,
        coarser_eval / coarser_haar, coarser_full / coarser_haar, finer_haar * 1e3,
        finer_eval * 1e3, finer_full * 1e3, finer_eval / finer_haar, finer_full / finer_haar);
    device = fmt::format("{} ({})", m.device.name, m.device.kind);
  }
  file.machine = machine_record(threads);
  file.settings = {{"scene", scene.name},
                   {"samples", options.samples},
                   {"levels", options.levels},
                   {"repetitions", options.repetitions},
                   {"gl", options.gl.empty() ? "egl" : options.gl},
                   {"render_size", glsl_deboor::kLodRenderSize}};
  const nlohmann::json document = file;
  std::filesystem::create_directories(options.out);
  write_file_atomically(std::filesystem::path(options.out) / "lod.json", document.dump(1) + "\n");
  std::cout << fmt::format("002 Fig 15: LOD change on {} by Haar step vs re-evaluation, on {}\n",
                           scene.name, device)
            << changes
            << "(re-evaluate: the de Boor passes alone; full re-eval: also the read-back, the "
               "vertex-buffer upload and the new size's index buffer, 002's baseline; ratio = "
               "re-evaluate / Haar, full ratio = full re-eval / Haar)\n\n"
            << fmt::format("Each level drawn from its texture ({0}x{0} image, no read-back):\n",
                           glsl_deboor::kLodRenderSize)
            << draws
            << fmt::format(
                   "(medians of {} runs; distances in model units, largest coordinate {:.3g})\n"
                   "{}/lod.json\n",
                   options.repetitions, largest, options.out);
  return 0;
}

}  // namespace nurbs::cli
