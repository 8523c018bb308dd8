#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <set>
#include <stdexcept>

#include "harness/error_image.h"
#include "harness/metrics.h"
#include "harness/report/kit.h"
#include "harness/report/redraw.h"

namespace nurbs::report {

// Error heat maps of the `count` worst (strategy, scene) pairs, re-evaluated here (so only for
// strategies and scenes this machine has); a pair that cannot be redone says why.
ReportSection error_maps(const SectionInput& in) {
  const int count = in.options.error_images;
  const fs::path& out = in.options.out;
  ReportSection s;
  s.id = in.row.id;
  s.title = fmt::format(fmt::runtime(in.row.title), count);
  s.command = in.row.run;
  const auto worst = worst_records(
      in.sets, [](const Record&) { return true; },
      [](const Record& a, const Record& b) { return a.accuracy->max_ulp > b.accuracy->max_ulp; });
  draw_worst(
      worst, count,
      [&](const Record& r, const Redone& d) {
        std::vector<ErrorGrid> grids = error_grids(d.scene, d.result, d.reference);
        const std::size_t surface = std::min<std::size_t>(
            static_cast<std::size_t>(r.accuracy->worst_surface), grids.size() - 1);
        const std::string name =
            safe_file_name(fmt::format("error-{}-{}.png", r.strategy, r.scene));
        write_error_images(out / name, {grids[surface]},
                           fmt::format("{} on {} ({}, {}), surface {}", r.strategy, r.scene,
                                       r.precision, d.sampling.label(), surface));
        return std::pair{name, fmt::format("surface {}, {}", surface, d.sampling.label())};
      },
      [](const Record& r) { return report_number(r.accuracy->max_ulp); }, s,
      ReportTable{"Pairs drawn (re-evaluated on this machine; colour = f32 ulps, log scale)",
                  {"strategy", "scene", "samples", "precision", "max_ulp in results", "image"},
                  {}});
  if (s.tables.empty()) s.no_data = "no data in these results: no measured accuracy to map";
  return s;
}

}  // namespace nurbs::report
