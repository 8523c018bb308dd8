#include "harness/report/redraw.h"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <set>
#include <stdexcept>

#include "harness/cli/parsing.h"
#include "harness/error_image.h"
#include "harness/metrics.h"
#include "harness/report/kit.h"

namespace nurbs::report {

namespace {

// The sampling a record was measured at, from its `samples` label ("256x256", "span4").
std::optional<Sampling> sampling_of(const Record& r) {
  try {
    const std::vector<Sampling> list = r.samples.starts_with("span")
                                           ? cli::parse_span_list("samples", r.samples.substr(4))
                                           : cli::parse_grid_list("samples", r.samples);
    if (list.size() == 1) return list.front();
  } catch (const InputError&) {
  }
  return std::nullopt;
}

}  // namespace

// Throws std::runtime_error saying why the pair cannot be redone here.
Redone redo(const Record& r) {
  const StrategyEntry* entry = find_strategy(r.strategy);
  if (!entry) throw std::runtime_error("strategy not in this build");
  const Availability availability = entry->probe();
  if (!availability.available) throw std::runtime_error("unavailable here: " + availability.reason);
  std::optional<Sampling> sampling = sampling_of(r);
  if (!sampling) throw std::runtime_error("samples '" + r.samples + "' have no image layout");
  if (sampling->mode == SamplingMode::grid && sampling->grid_u * sampling->grid_v > 65536)
    sampling->grid_u = sampling->grid_v = 256;
  Redone d{load_scene(r.scene), *sampling, {}, {}};
  EvalRequest request{*sampling, cli::parse_precision(r.precision), false};
  if (auto refused = refusal_reason(entry->capabilities(), d.scene, request))
    throw std::runtime_error("refused: " + *refused);
  std::unique_ptr<Strategy> strategy = entry->create(StrategyOptions{0, {}});
  strategy->prepare(d.scene, request);
  strategy->evaluate();
  if (entry->capabilities().trims && d.scene.has_trims()) strategy->classify();
  d.result = strategy->read_back();
  const std::vector<SurfaceSamples> produced = result_samples(d.result);
  if (!same_samples(produced, sample_parameters(d.scene, *sampling)))
    throw std::runtime_error("it chose its own samples, which have no (u, v) image layout");
  d.reference = evaluate_reference(d.scene, produced, false, ReferencePrecision::long_double);
  return d;
}

// The records `eligible` keeps, worst first by `worse`.
std::vector<const Record*> worst_records(
    const std::vector<ResultSet>& sets, const std::function<bool(const Record&)>& eligible,
    const std::function<bool(const Record&, const Record&)>& worse) {
  std::vector<const Record*> worst;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records)
      if (r.status == Status::ok && r.role != "limit" && r.accuracy && eligible(r))
        worst.push_back(&r);
  std::stable_sort(worst.begin(), worst.end(),
                   [&](const Record* a, const Record* b) { return worse(*a, *b); });
  return worst;
}

void draw_worst(const std::vector<const Record*>& worst, int count, const Draw& draw,
                const std::function<std::string(const Record&)>& figure, ReportSection& s,
                ReportTable table) {
  std::set<std::pair<std::string, std::string>> done;
  int drawn = 0;
  for (const Record* r : worst) {
    if (drawn >= count || static_cast<int>(done.size()) >= 3 * count) break;
    if (!done.insert({r->strategy, r->scene}).second) continue;
    std::string image = "-";
    try {
      const auto [name, note] = draw(*r, redo(*r));
      s.images.push_back(name);
      ++drawn;
      image = fmt::format("{} ({})", name, note);
    } catch (const std::exception& e) {
      image = fmt::format("not drawn: {}", e.what());
    }
    table.rows.push_back({r->strategy, r->scene, r->samples, r->precision, figure(*r), image});
  }
  if (table.rows.empty()) return;
  s.tables.push_back(std::move(table));
}

}  // namespace nurbs::report
