// CI accuracy gates: a JSON list of {strategy, scene, metric, max} (globs allowed in strategy and
// scene). Every gate must match at least one measured record and hold on all of them; a gate
// whose strategy failed or was unavailable is violated, so a strategy cannot pass by vanishing.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "harness/record.h"

namespace nurbs {

struct Gate {
  std::string strategy, scene, metric;
  double max = 0;
};

// Throws InputError naming the file, entry index, field and value.
std::vector<Gate> load_gates(const std::filesystem::path& path);
// The same from the file's text; `source` names it in errors.
std::vector<Gate> parse_gates(std::string_view text, const std::string& source);
// Metric names: max_abs, rms_abs, max_rel, max_ulp, max_normal_angle_deg, trim_misclassified,
// trim_misclassified_rate (the last two match only records whose strategy classified samples
// against trims; other records are not applicable and not counted).
bool is_known_metric(std::string_view metric);
// One line per violation; empty when every gate holds.
std::vector<std::string> check_gates(const std::vector<Gate>& gates,
                                     const std::vector<Record>& records);
// Whether `r` was measured and holds every gate that applies to it; false when none applies (a
// record no gate covers has passed none), and for a refused record (it measured nothing).
bool passes_gates(const std::vector<Gate>& gates, const Record& r);

}  // namespace nurbs
