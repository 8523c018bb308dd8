// The report: every table and chart of issue 7 computed from whatever records one or more results
// sets hold (no list of strategies is named anywhere), plus the optional side files a set may
// carry (lod.json from `nurbsbench lod`, memory.json from the memory study). The charts are
// described as data (chart JSON) and drawn outside the core by scripts/plot_report.py, as Google
// Benchmark leaves plotting to its tools; REPORT.md and index.html are rendered here from the same
// sections so they show the same thing.
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/results_writer.h"
#include "harness/side_files.h"

namespace nurbs {

struct ResultSet {
  std::filesystem::path directory;
  std::string tag;  // short name (the directory's), used in labels when there are several sets
  ResultsFile results;
  std::optional<LodFile> lod;        // lod.json (nurbsbench-lod/1), when present
  std::optional<MemoryFile> memory;  // memory.json (nurbsbench-memory/1), when present
  // camera_path.json (nurbsbench-camera-path/1, `nurbsbench camera-path`), when present
  std::optional<CameraPathFile> camera_path;
};

// Reads DIR/results.json and, when present, DIR/lod.json, DIR/memory.json and DIR/camera_path.json.
// Throws InputError naming the file and field for anything malformed.
ResultSet load_result_set(const std::filesystem::path& directory);
// `path` as one set (a results.json, or a directory holding results.json or a side file), or else
// a tree of sets (results/canonical): every directory below it that is a set, in path order, the
// report folders a set may hold left out. A directory with no set in or below it is read as one
// set, so its error names the missing results.json.
std::vector<ResultSet> load_result_sets(const std::filesystem::path& path);

struct ReportTable {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

struct ReportSection {
  std::string id;          // also the chart's file stem
  std::string title;       // the paper figure it reproduces
  std::string context;     // machine (CPU model), devices and drivers, commit
  std::string command;     // the command that regenerates its data and the report
  std::string no_data;     // non-empty: nothing to show, and what to run to get it
  bool has_chart = false;  // a chart is described in the chart JSON under `id`
  std::string chart_note;  // filled after plotting: why the chart could not be drawn
  std::vector<ReportTable> tables;
  std::vector<std::string> notes;   // plain paragraphs
  std::vector<std::string> images;  // extra images (relative paths), e.g. error heat maps
};

struct Report {
  std::vector<ReportSection> sections;
  nlohmann::json charts;  // {"format": "nurbsbench-charts/1", "charts": [ ... ]}
};

// The sections that redraw measured pairs on this machine (error heat maps, trim masks) re-evaluate
// them and write images into `out`: only with a count above 0 (the default leaves them out).
struct ReportBuildOptions {
  std::filesystem::path out;
  int error_images = 0;
  int trim_masks = 0;
};

// Every section of the sections table (harness/report/sections.cpp), in its order.
Report build_report(const std::vector<ResultSet>& sets, const ReportBuildOptions& options = {});

// The command that makes a chart's data: the `nurbsbench` verb and options, DIR where it writes
// (or a script of scripts/ that runs them and writes its own report, DIR/report).
// One row per chart, from the sections table (harness/report/sections.cpp), so the report's
// "regenerate" lines, scripts/canonical.sh and the test that runs every row
// (tests/cli/regenerate_test.cpp) cannot drift apart.
struct ChartCommand {
  std::string id;  // the chart's id (its section's id and file stem)
  std::string
      run;  // "nurbsbench run --scenes patch144 ... --out DIR", "scripts/x.sh ... --out DIR"
};
const std::vector<ChartCommand>& chart_commands();

std::string report_markdown(const Report& report);
std::string report_html(const Report& report);

// Numbers as the tables print them: 3 significant digits, "inf" for infinities, "n/a" for
// anything else non-finite (never "nan").
std::string report_number(double x);

}  // namespace nurbs
