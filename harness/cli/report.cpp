#include "harness/report.h"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <set>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "harness/error_image.h"
#include "harness/metrics.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs::embedded {
extern const std::string_view plot_report_py;  // scripts/plot_report.py, embedded at build time
}

namespace nurbs::cli {

namespace {

namespace fs = std::filesystem;

std::string shell_quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs the embedded plotter on charts.json; returns, per chart id, why it was not drawn (charts
// drawn are absent). Never throws for a missing Python or matplotlib: those are notes.
std::map<std::string, std::string> draw_charts(const Report& report, const fs::path& out,
                                               const std::string& python) {
  std::map<std::string, std::string> not_drawn;
  for (const auto& chart : report.charts["charts"])
    not_drawn[chart["id"].get<std::string>()] = "the plotter did not report it";
  if (not_drawn.empty()) return not_drawn;

  const fs::path script = out / ".plot_report.py";
  write_file_atomically(script, embedded::plot_report_py);
  const std::string command =
      fmt::format("{} {} {} {} 2>&1", shell_quote(python), shell_quote(script.string()),
                  shell_quote((out / "charts.json").string()), shell_quote(out.string()));
  std::string output;
  int status = -1;
  if (FILE* pipe = ::popen(command.c_str(), "r")) {
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    status = ::pclose(pipe);
  }
  std::error_code ignored;
  fs::remove(script, ignored);

  std::string last_line, matplotlib_missing;
  std::size_t start = 0;
  while (start < output.size()) {
    std::size_t end = output.find('\n', start);
    if (end == std::string::npos) end = output.size();
    const std::string line = output.substr(start, end - start);
    start = end + 1;
    if (line.empty()) continue;
    last_line = line;
    if (line.starts_with("drawn ")) {
      not_drawn.erase(line.substr(6, line.find(' ', 6) - 6));
    } else if (line.starts_with("failed ")) {
      const std::size_t colon = line.find(": ");
      if (colon != std::string::npos) not_drawn[line.substr(7, colon - 7)] = line.substr(colon + 2);
    } else if (line.starts_with("matplotlib missing: ")) {
      matplotlib_missing = line;
    }
  }
  const int code = status >= 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::string common;
  if (!matplotlib_missing.empty())
    common = fmt::format("{} (with {}; install python3-matplotlib, see scripts/setup.sh)",
                         matplotlib_missing, python);
  else if (code == 127 || code == 126)
    common = fmt::format("cannot run {} (exit {}): {}", python, code, last_line);
  else if (code != 0)
    common = fmt::format("the plotter ({}) exited with {}: {}", python, code, last_line);
  if (!common.empty())
    for (auto& [id, why] : not_drawn) why = common;
  return not_drawn;
}

// The sampling a record was measured at, from its `samples` label ("256x256", "span4").
std::optional<Sampling> sampling_of(const Record& r) {
  try {
    const std::vector<Sampling> list = r.samples.starts_with("span")
                                           ? parse_span_list("samples", r.samples.substr(4))
                                           : parse_grid_list("samples", r.samples);
    if (list.size() == 1) return list.front();
  } catch (const InputError&) {
  }
  return std::nullopt;
}

// A measured pair evaluated again on this machine, for a picture of it: the record's sampling
// (large grids at 256x256: a picture needs no more, and it bounds the time), its precision, the
// classification when the strategy trims, and the reference at the same (u, v).
struct Redone {
  Scene scene;
  Sampling sampling;
  EvalResult result;
  std::vector<ReferenceSurface> reference;
};

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
  EvalRequest request{*sampling, parse_precision(r.precision), false};
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

using Draw = std::function<std::pair<std::string, std::string>(const Record&, const Redone&)>;
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

// Draws the first `count` (strategy, scene) pairs of `worst`, each redone here and drawn by `draw`
// (which returns the image's file name and a note), into s's images and `table` (its `figure`
// column from the record); a pair that cannot be drawn is listed with the reason and the next one
// is tried, up to three times `count` pairs.
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

// Error heat maps of the `count` worst (strategy, scene) pairs, re-evaluated here (so only for
// strategies and scenes this machine has); a pair that cannot be redone says why.
ReportSection error_maps(const std::vector<ResultSet>& sets, int count, const fs::path& out) {
  ReportSection s;
  s.id = "error_maps";
  s.title = fmt::format(
      "Error heat maps of the {} worst (strategy, scene) pairs that can be redrawn here", count);
  s.command = "nurbsbench eval --scene S --strategy X --samples NxM --error-image F.png";
  const auto worst = worst_records(
      sets, [](const Record&) { return true; },
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

// Trim masks of the `count` (strategy, scene) pairs with the most misclassified samples, among
// strategies that classified against trims; re-evaluated here like the error maps.
ReportSection trim_mask_maps(const std::vector<ResultSet>& sets, int count, const fs::path& out) {
  ReportSection s;
  s.id = "trim_masks";
  s.title = fmt::format(
      "Trim masks of the {} (strategy, trimmed scene) pairs with the most misclassified samples",
      count);
  s.command =
      "nurbsbench run --scenes S --strategies X --samples NxM --images DIR (writes "
      "DIR/X__S__maskI.png)";
  const auto misclassified = [](const Record& r) {
    return static_cast<double>(*r.accuracy->trim->misclassified);
  };
  const auto worst = worst_records(
      sets,
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

}  // namespace

int report_command(const ReportOptions& options) {
  // Every input is read and checked before anything is written.
  if (options.results.empty()) throw InputError("--results: at least one results directory");
  std::vector<ResultSet> sets;
  for (const std::string& dir : options.results) sets.push_back(load_result_set(dir));
  const fs::path out =
      options.out.empty() ? fs::path(options.results.front()) / "report" : fs::path(options.out);
  if (options.error_images < 0 || options.error_images > 50)
    throw InputError(fmt::format("--error-images = {}: must be in 0..50", options.error_images));
  if (options.trim_masks < 0 || options.trim_masks > 50)
    throw InputError(fmt::format("--trim-masks = {}: must be in 0..50", options.trim_masks));
  Report report = build_report(sets);

  fs::create_directories(out);
  if (options.error_images > 0)
    report.sections.insert(report.sections.end() - 1, error_maps(sets, options.error_images, out));
  if (options.trim_masks > 0)
    report.sections.insert(report.sections.end() - 1,
                           trim_mask_maps(sets, options.trim_masks, out));
  write_file_atomically(out / "charts.json", report.charts.dump(1) + "\n");
  const auto not_drawn = draw_charts(report, out, options.python);
  for (ReportSection& s : report.sections)
    if (auto it = not_drawn.find(s.id); s.has_chart && it != not_drawn.end())
      s.chart_note = it->second;
  write_file_atomically(out / "REPORT.md", report_markdown(report));
  write_file_atomically(out / "index.html", report_html(report));

  const std::size_t charts = report.charts["charts"].size();
  std::cout << fmt::format("report: {}/REPORT.md, index.html, {} of {} charts drawn\n",
                           out.string(), charts - not_drawn.size(), charts);
  for (const ReportSection& s : report.sections) {
    if (!s.no_data.empty()) std::cout << fmt::format("  {}: {}\n", s.id, s.no_data);
    if (!s.chart_note.empty())
      std::cout << fmt::format("  {}: chart not drawn: {}\n", s.id, s.chart_note);
  }
  return 0;
}

}  // namespace nurbs::cli
