#include "harness/recommend.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "reference/validation.h"

namespace nurbs {

std::string Tolerance::text() const {
  return unit == Unit::ulp ? fmt::format("{:g} ulp (max_ulp)", value)
                           : fmt::format("{:g} model units (max_abs)", value);
}

Tolerance parse_tolerance(std::string_view text) {
  std::string number(text);
  Tolerance t;
  t.unit = Tolerance::Unit::model;
  for (std::string_view suffix : {"ulps", "ulp"})
    if (number.ends_with(suffix)) {
      number.resize(number.size() - suffix.size());
      t.unit = Tolerance::Unit::ulp;
      break;
    }
  while (!number.empty() && number.back() == ' ') number.pop_back();
  char* end = nullptr;
  t.value = std::strtod(number.c_str(), &end);
  if (number.empty() || end != number.c_str() + number.size() || !std::isfinite(t.value) ||
      !(t.value > 0))
    throw InputError(fmt::format(
        "--tolerance = '{}': expected a positive number of ulps ('8ulp') or of model units "
        "('1e-5')",
        text));
  return t;
}

namespace {

std::string unique_list(const std::vector<Record>& records, std::string Record::*field) {
  std::set<std::string> values;
  for (const Record& r : records)
    if (r.role != "limit") values.insert(r.*field);
  return fmt::format("{}", fmt::join(values, ", "));
}

}  // namespace

Recommendation recommend(const std::vector<Record>& records, const Workload& w) {
  std::vector<const Record*> matching;
  for (const Record& r : records)
    if (r.role != "limit" && (!w.scene || r.scene == *w.scene) &&
        (!w.samples || r.samples == *w.samples) && (!w.precision || r.precision == *w.precision))
      matching.push_back(&r);
  if (matching.empty())
    throw InputError(fmt::format(
        "no measurement matches the workload (scene {}, samples {}, precision {}); the results "
        "hold scenes: {}; samples: {}; precisions: {}",
        w.scene.value_or("any"), w.samples.value_or("any"), w.precision.value_or("any"),
        unique_list(records, &Record::scene), unique_list(records, &Record::samples),
        unique_list(records, &Record::precision)));

  Recommendation out;
  out.scope = fmt::format("{} measurements: scene {}, samples {}, precision {}", matching.size(),
                          w.scene.value_or("(every scene)"), w.samples.value_or("(every sampling)"),
                          w.precision.value_or("(each)"));
  std::map<std::pair<std::string, std::string>, std::vector<const Record*>> by_candidate;
  for (const Record* r : matching) by_candidate[{r->strategy, r->precision}].push_back(r);

  for (const auto& [key, list] : by_candidate) {
    Candidate c{
        key.first, key.second, list.front()->role, list.front()->device.name, list.size(), 0, 0,
        0,         ""};
    double points = 0, seconds = 0;
    for (const Record* r : list) {
      if (c.device.empty()) c.device = r->device.name;
      if (r->status != Status::ok) {
        // A strategy that cannot serve part of the workload cannot serve the workload.
        if (c.excluded.empty())
          c.excluded =
              fmt::format("{} on {} {}: {}", to_string(r->status), r->scene, r->samples, r->reason);
        continue;
      }
      if (!r->accuracy) {
        if (c.excluded.empty())
          c.excluded = fmt::format("no accuracy measured on {} {}", r->scene, r->samples);
        continue;
      }
      // A trimmed scene sampled where no face is scores 0 error over nothing: not a perfect
      // score, no score.
      if (no_inside_samples(*r->accuracy)) {
        if (c.excluded.empty())
          c.excluded =
              fmt::format("no sample inside a trimmed face on {} {}: its errors are over nothing",
                          r->scene, r->samples);
        continue;
      }
      // !(x <= max) keeps NaN as the worst.
      if (!(r->accuracy->max_ulp <= c.max_ulp)) c.max_ulp = r->accuracy->max_ulp;
      if (!(r->accuracy->max_abs <= c.max_abs)) c.max_abs = r->accuracy->max_abs;
      if (w.deforming) {
        const auto frame = r->extra_phases.find("frame");
        if (frame == r->extra_phases.end()) {
          if (c.excluded.empty())
            c.excluded = fmt::format(
                "no deforming measurement (frame phase) on {} {}: run `nurbsbench run "
                "--deforming`",
                r->scene, r->samples);
          continue;
        }
        seconds += frame->second.median_s;
      } else {
        seconds += r->evaluate.median_s;
      }
      points += static_cast<double>(r->points);
    }
    c.points_per_s = seconds > 0 ? points / seconds : 0;
    if (c.excluded.empty()) {
      const bool ulp = w.tolerance.unit == Tolerance::Unit::ulp;
      const double error = ulp ? c.max_ulp : c.max_abs;
      if (!(error <= w.tolerance.value))
        c.excluded = fmt::format("{} {:.3g} exceeds the tolerance {}", ulp ? "max_ulp" : "max_abs",
                                 error, w.tolerance.text());
    }
    (c.excluded.empty() ? out.ranked : out.excluded).push_back(std::move(c));
  }
  std::stable_sort(
      out.ranked.begin(), out.ranked.end(),
      [](const Candidate& a, const Candidate& b) { return a.points_per_s > b.points_per_s; });
  return out;
}

std::string recommendation_text(const Recommendation& r, const Workload& w) {
  std::string out = fmt::format("workload: {}; tolerance {}{}\n", r.scope, w.tolerance.text(),
                                w.deforming ? "; deforming (ranked by time per frame)" : "");
  if (r.ranked.empty()) {
    out += "no strategy meets the tolerance\n";
  } else {
    out += fmt::format("{:<4} {:<22} {:<5} {:>12} {:>10} {:>11}  {}\n", "rank", "strategy", "prec",
                       "points/s", "max_ulp", "max_abs", "device");
    for (std::size_t k = 0; k < r.ranked.size(); ++k) {
      const Candidate& c = r.ranked[k];
      out += fmt::format("{:<4} {:<22} {:<5} {:>12.3g} {:>10.3g} {:>11.3g}  {}\n", k + 1,
                         c.strategy, c.precision, c.points_per_s, c.max_ulp, c.max_abs, c.device);
    }
  }
  if (!r.excluded.empty()) {
    out += "excluded:\n";
    for (const Candidate& c : r.excluded)
      out += fmt::format("  {} {}: {}\n", c.strategy, c.precision, c.excluded);
  }
  return out;
}

nlohmann::json recommendation_json(const Recommendation& r, const Workload& w) {
  using nlohmann::json;
  auto number = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
  auto candidate = [&](const Candidate& c) {
    json j = {{"strategy", c.strategy},
              {"precision", c.precision},
              {"role", c.role},
              {"device", c.device},
              {"records", c.records},
              {"points_per_s", number(c.points_per_s)},
              {"max_ulp", number(c.max_ulp)},
              {"max_abs", number(c.max_abs)}};
    if (!c.excluded.empty()) j["excluded"] = c.excluded;
    return j;
  };
  json out = {{"format", "nurbsbench-recommend/1"},
              {"scope", r.scope},
              {"tolerance",
               {{"value", w.tolerance.value},
                {"unit", w.tolerance.unit == Tolerance::Unit::ulp ? "ulp" : "model"}}},
              {"deforming", w.deforming},
              {"ranked", json::array()},
              {"excluded", json::array()}};
  for (const Candidate& c : r.ranked) out["ranked"].push_back(candidate(c));
  for (const Candidate& c : r.excluded) out["excluded"].push_back(candidate(c));
  return out;
}

}  // namespace nurbs
