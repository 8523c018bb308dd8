#include "harness/gates.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fnmatch.h>

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>
#include <optional>

#include "reference/validation.h"
#include "scenes/json_strict.h"
#include "scenes/scene_json.h"

namespace nurbs {

namespace {

// Every metric a gate can name; the trim_ ones apply only to records that classified.
constexpr std::array<std::string_view, 7> kMetrics = {"max_abs",
                                                      "rms_abs",
                                                      "max_rel",
                                                      "max_ulp",
                                                      "max_normal_angle_deg",
                                                      "trim_misclassified",
                                                      "trim_misclassified_rate"};

bool is_trim_metric(std::string_view metric) {
  return metric.starts_with("trim_");
}

std::optional<double> metric_value(const Accuracy& a, std::string_view metric) {
  if (is_trim_metric(metric)) {
    if (!a.trim || !a.trim->misclassified) return std::nullopt;
    if (metric == "trim_misclassified") return static_cast<double>(*a.trim->misclassified);
    return a.trim->misclassified_rate;
  }
  if (metric == "max_abs") return a.max_abs;
  if (metric == "rms_abs") return a.rms_abs;
  if (metric == "max_rel") return a.max_rel;
  if (metric == "max_ulp") return a.max_ulp;
  if (metric == "max_normal_angle_deg") return a.max_normal_angle_deg;
  return std::nullopt;
}

bool glob_match(const std::string& pattern, const std::string& text) {
  return ::fnmatch(pattern.c_str(), text.c_str(), 0) == 0;
}

bool gate_applies(const Gate& g, const Record& r) {
  if (!glob_match(g.strategy, r.strategy) || !glob_match(g.scene, r.scene)) return false;
  // A limit row (a machine ceiling) evaluates nothing and has no accuracy to gate.
  if (r.role == "limit") return false;
  // A classification gate does not apply to a strategy that does not trim, nor to a scene
  // without trims: such records are not counted (docs/formats.md §Gates files).
  return !is_trim_metric(g.metric) || r.trimming == "classified";
}

}  // namespace

bool is_known_metric(std::string_view metric) {
  return std::find(kMetrics.begin(), kMetrics.end(), metric) != kMetrics.end();
}

std::vector<Gate> load_gates(const std::filesystem::path& path) {
  return parse_gates(read_input_file(path, "gates"), path.string());
}

std::vector<Gate> parse_gates(std::string_view text, const std::string& source) {
  const nlohmann::json document = parse_json_strictly(text, source);
  if (!document.is_array())
    throw InputError(fmt::format("{}: (document): must be a JSON list of gates", source));
  std::vector<Gate> gates;
  for (std::size_t i = 0; i < document.size(); ++i) {
    const auto& entry = document[i];
    auto fail = [&](const std::string& field, const std::string& value, const std::string& rule) {
      throw InputError(fmt::format("{}: gate [{}]: {} = {}: {}", source, i, field, value, rule));
    };
    if (!entry.is_object()) fail("(entry)", entry.dump(), "must be an object");
    for (const auto& [key, value] : entry.items())
      if (key != "strategy" && key != "scene" && key != "metric" && key != "max" && key != "note")
        fail(key, value.dump(), "unknown key (expected strategy, scene, metric, max, note)");
    Gate g;
    for (const char* field : {"strategy", "scene", "metric"}) {
      if (!entry.contains(field) || !entry[field].is_string())
        fail(field, entry.contains(field) ? entry[field].dump() : "(missing)", "must be a string");
    }
    g.strategy = entry["strategy"];
    g.scene = entry["scene"];
    g.metric = entry["metric"];
    if (!is_known_metric(g.metric))
      fail("metric", g.metric, fmt::format("unknown metric ({})", fmt::join(kMetrics, ", ")));
    if (!entry.contains("max") || !entry["max"].is_number())
      fail("max", entry.contains("max") ? entry["max"].dump() : "(missing)", "must be a number");
    g.max = entry["max"].get<double>();
    gates.push_back(g);
  }
  return gates;
}

std::vector<std::string> check_gates(const std::vector<Gate>& gates,
                                     const std::vector<Record>& records) {
  std::vector<std::string> violations;
  for (const Gate& g : gates) {
    int matched = 0;
    for (const Record& r : records) {
      if (!gate_applies(g, r)) continue;
      ++matched;
      const std::string where =
          fmt::format("{} on {} ({}, {})", r.strategy, r.scene, r.precision, r.samples);
      if (r.status != Status::ok) {
        // A refusal is the strategy saying "not my case"; anything else means no measurement, and
        // a crashed or timed_out record (isolation) violates the gate like a failed one: a
        // strategy cannot pass its gates by crashing or hanging.
        if (r.status != Status::refused)
          violations.push_back(fmt::format("{}: {} <= {} not measured: {}: {}", where, g.metric,
                                           g.max, to_string(r.status), r.reason));
        else
          --matched;
        continue;
      }
      if (!r.accuracy) {
        violations.push_back(fmt::format("{}: no accuracy was measured", where));
        continue;
      }
      const Accuracy& accuracy = *r.accuracy;
      if (!is_trim_metric(g.metric) && no_inside_samples(accuracy)) {
        violations.push_back(
            fmt::format("{}: {} was measured over no sample: none lies inside the trimmed faces",
                        where, g.metric));
        continue;
      }
      const auto value = metric_value(accuracy, g.metric);
      if (!value) {
        violations.push_back(
            fmt::format("{}: {} was not measured (run with --normals?)", where, g.metric));
        continue;
      }
      if (*value <= g.max) continue;
      if (is_trim_metric(g.metric))
        violations.push_back(fmt::format(
            "{}: {} = {:.6g} exceeds {} ({} samples misclassified outside the boundary band of "
            "{:g} x the domain diagonal)",
            where, g.metric, *value, g.max, *accuracy.trim->misclassified, accuracy.trim->band));
      else
        violations.push_back(fmt::format(
            "{}: {} = {:.6g} exceeds {} (worst sample: surface {}, u = {:.17g}, v = {:.17g})",
            where, g.metric, *value, g.max, accuracy.worst_surface, accuracy.worst_u,
            accuracy.worst_v));
    }
    if (matched == 0)
      violations.push_back(
          fmt::format("gate {{strategy: {}, scene: {}, metric: {}}} matched no measured result",
                      g.strategy, g.scene, g.metric));
  }
  return violations;
}

bool passes_gates(const std::vector<Gate>& gates, const Record& r) {
  std::vector<Gate> applicable;
  for (const Gate& g : gates)
    if (gate_applies(g, r)) applicable.push_back(g);
  // A record no gate covers has not passed one.
  return !applicable.empty() && check_gates(applicable, {r}).empty();
}

}  // namespace nurbs
