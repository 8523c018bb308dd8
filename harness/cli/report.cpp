#include "harness/report/report.h"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <map>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "reference/validation.h"

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

}  // namespace

int report_command(const ReportOptions& options) {
  // Every input is read and checked before anything is written.
  if (options.results.empty()) throw InputError("--results: at least one results directory");
  std::vector<ResultSet> sets;
  for (const std::string& dir : options.results)
    for (ResultSet& set : load_result_sets(dir)) sets.push_back(std::move(set));
  const fs::path out =
      options.out.empty() ? fs::path(options.results.front()) / "report" : fs::path(options.out);
  if (options.error_images < 0 || options.error_images > 50)
    throw InputError(fmt::format("--error-images = {}: must be in 0..50", options.error_images));
  if (options.trim_masks < 0 || options.trim_masks > 50)
    throw InputError(fmt::format("--trim-masks = {}: must be in 0..50", options.trim_masks));
  // The sections that redraw pairs write their images into `out` as they are built.
  fs::create_directories(out);
  Report report = build_report(sets, {out, options.error_images, options.trim_masks});
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
