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

// Trim masks of the `count` (strategy, scene) pairs with the most misclassified samples, among
// strategies that classified against trims; re-evaluated here like the error maps.
ReportSection trim_masks(const SectionInput& in) {
  const int count = in.options.trim_masks;
  const fs::path& out = in.options.out;
  ReportSection s;
  s.id = in.row.id;
  s.title = fmt::format(fmt::runtime(in.row.title), count);
  s.command = in.row.run;
  const auto misclassified = [](const Record& r) {
    return static_cast<double>(*r.accuracy->trim->misclassified);
  };
  const auto worst = worst_records(
      in.sets,
      [](const Record& r) {
        return r.trimming == "classified" && r.accuracy->trim && r.accuracy->trim->misclassified;
      },
      [&](const Record& a, const Record& b) { return misclassified(a) > misclassified(b); });
  draw_worst(
      worst, count,
      [&](const Record& r, const Redone& d) {
        const std::vector<TrimMask> masks =
            trim_masks(d.scene, d.result, d.reference, r.accuracy->trim->band);
        if (masks.empty()) throw std::runtime_error("no trimmed surface with a classification");
        const TrimMask& mask = *std::max_element(
            masks.begin(), masks.end(),
            [](const TrimMask& a, const TrimMask& b) { return a.misclassified < b.misclassified; });
        const std::string name = safe_file_name(
            fmt::format("trim-mask-{}-{}-{}.png", r.strategy, r.scene, mask.surface));
        write_trim_mask(out / name, mask,
                        fmt::format("trim mask of {} on {} ({}, {}), surface {}", r.strategy,
                                    r.scene, r.precision, d.sampling.label(), mask.surface));
        return std::pair{name, fmt::format("surface {}, {}: {} misclassified here", mask.surface,
                                           d.sampling.label(), mask.misclassified)};
      },
      [&](const Record& r) { return fmt::format("{:g}", misclassified(r)); }, s,
      ReportTable{
          "Pairs drawn (re-evaluated on this machine; light = inside, dark = outside, "
          "orange = trim band, magenta = misclassified)",
          {"strategy", "scene", "samples", "precision", "misclassified in results", "image"},
          {}});
  if (s.tables.empty())
    s.no_data =
        "no data in these results: no strategy classified samples against trims (run a trimmed "
        "scene, e.g. --scenes trimmed-plate, with a strategy that trims)";
  return s;
}

}  // namespace nurbs::report
