// `nurbsbench lod`: 002 Fig 15 on this machine (strategies/glsl_deboor/lod_experiment.h), one row
// per grid size: the level change by one Haar step versus re-evaluation, both directions, and
// each coarser level's distance to the surface. Writes DIR/lod.json (nurbsbench-lod/1).
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "harness/machine.h"
#include "harness/metrics.h"
#include "harness/timing.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/glsl_deboor/lod_experiment.h"

namespace nurbs::cli {

inline constexpr std::string_view kLodFormat = "nurbsbench-lod/1";

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

  const double largest = scene.largest_coordinate();
  nlohmann::json rows = nlohmann::json::array();
  std::string table = fmt::format(
      "{:<11} {:>14} {:>14} {:>7}   {:>14} {:>14} {:>7}   level distances to the surface\n",
      "samples", "coarser: Haar", "re-evaluate", "ratio", "finer: Haar", "re-evaluate", "ratio");
  std::string device;
  for (const Sampling& g : grids) {
    const glsl_deboor::LodMeasurement m =
        glsl_deboor::measure_lod(scene, g.grid_u, g.grid_v, options.levels, options.repetitions,
                                 {threads, backend_extra(options.gl, "")});
    const double coarser_haar = PhaseStats::of(m.coarser_by_haar).median_s;
    const double coarser_eval = PhaseStats::of(m.coarser_by_reevaluation).median_s;
    const double finer_haar = PhaseStats::of(m.finer_by_haar).median_s;
    const double finer_eval = PhaseStats::of(m.finer_by_reevaluation).median_s;
    nlohmann::json levels = nlohmann::json::array();
    std::string distances;
    for (const glsl_deboor::LodLevel& l : m.levels) {
      const double ulp = ulps_of_largest_coordinate(l.max_distance, largest);
      levels.push_back({{"level", l.level},
                        {"samples", fmt::format("{}x{}", l.width, l.height)},
                        {"max_distance", l.max_distance},
                        {"max_ulp", ulp}});
      distances += fmt::format("  L{} {:.2e}", l.level, l.max_distance);
    }
    rows.push_back({{"scene", scene.name},
                    {"samples", g.label()},
                    {"device", {{"name", m.device.name}, {"kind", m.device.kind}}},
                    {"repetitions", options.repetitions},
                    {"coarser_by_haar_s", coarser_haar},
                    {"coarser_by_reevaluation_s", coarser_eval},
                    {"finer_by_haar_s", finer_haar},
                    {"finer_by_reevaluation_s", finer_eval},
                    {"levels", levels}});
    table += fmt::format(
        "{:<11} {:>11.3f} ms {:>11.3f} ms {:>6.2f}x   {:>11.3f} ms {:>11.3f} ms "
        "{:>6.2f}x {}\n",
        g.label(), coarser_haar * 1e3, coarser_eval * 1e3, coarser_eval / coarser_haar,
        finer_haar * 1e3, finer_eval * 1e3, finer_eval / finer_haar, distances);
    device = fmt::format("{} ({})", m.device.name, m.device.kind);
  }
  const nlohmann::json document = {{"format", kLodFormat},
                                   {"machine", machine_record(threads)},
                                   {"settings",
                                    {{"scene", scene.name},
                                     {"samples", options.samples},
                                     {"levels", options.levels},
                                     {"repetitions", options.repetitions},
                                     {"gl", options.gl.empty() ? "egl" : options.gl}}},
                                   {"rows", rows}};
  std::filesystem::create_directories(options.out);
  write_file_atomically(std::filesystem::path(options.out) / "lod.json", document.dump(1) + "\n");
  std::cout << fmt::format("002 Fig 15: LOD change on {} by Haar step vs re-evaluation, on {}\n",
                           scene.name, device)
            << table
            << fmt::format(
                   "(ratio = re-evaluation / Haar; medians of {} runs; distances in model "
                   "units, largest coordinate {:.3g})\n{}/lod.json\n",
                   options.repetitions, largest, options.out);
  return 0;
}

}  // namespace nurbs::cli
