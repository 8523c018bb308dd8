// The sections table: the only place a report section is registered. A new section is one file
// (its builder) and one row here: its id, its place, its title, the command that makes its data
// (a chart's command is also a row of chart_commands(), which scripts/canonical.sh and
// tests/cli/regenerate_test.cpp follow) and its builder.
#include <fmt/format.h>

#include <algorithm>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

// The builders, one file each under harness/report/.
ReportSection sets_section(const SectionInput&);
ReportSection claims_section(const SectionInput&);
ReportSection fig7_time_vs_points(const SectionInput&);
ReportSection fig9_tspline_time_vs_points(const SectionInput&);
ReportSection fig14_deboor_vs_basis(const SectionInput&);
ReportSection fig15_lod(const SectionInput&);
ReportSection camera_path_section(const SectionInput&);
ReportSection rpns_frame(const SectionInput&);
ReportSection rpns_mappings(const SectionInput&);
ReportSection rpns_memory(const SectionInput&);
ReportSection fig8_many_surfaces(const SectionInput&);
ReportSection fig8_trimmed_ducks(const SectionInput&);
ReportSection accuracy_heatmap(const SectionInput&);
ReportSection accuracy_vs_degree(const SectionInput&);
ReportSection phases_section(const SectionInput&);
ReportSection trim_texture_resolution(const SectionInput&);
ReportSection error_maps(const SectionInput&);
ReportSection trim_masks(const SectionInput&);
ReportSection measurements_section(const SectionInput&);

namespace {

bool error_images_wanted(const ReportBuildOptions& o) {
  return o.error_images > 0;
}
bool trim_masks_wanted(const ReportBuildOptions& o) {
  return o.trim_masks > 0;
}

}  // namespace

const std::vector<SectionRow>& section_rows() {
  // The scenes, samples, repetitions and frames of scripts/canonical.sh, which made the committed
  // results: a line here that differs from the script regenerates something else.
  static const std::vector<SectionRow> rows = [] {
    std::vector<SectionRow> table = {
        // What a reader came for first (the verdicts, then the charts); the bookkeeping (sets,
        // strategies, every measurement) after.
        {"claims", 10, "Paper vs measured: which headline claims hold on this machine", "", false,
         claims_section},
        {"fig7_time_vs_points", 30,
         "Krishnamurthy 2007 Fig 7 / Krishnamurthy-Yasui Fig 9: evaluation time vs number of "
         "evaluation points (patch144, 144 control points)",
         "nurbsbench run --scenes patch144 --strategies all --samples "
         "4x4,8x8,16x16,32x32,64x64,128x128,256x256,512x512,1024x1024,2048x2048 --repetitions 3 "
         "--out DIR",
         true, fig7_time_vs_points},
        {"fig9_tspline_time_vs_points", 40,
         "Krishnamurthy-Yasui Fig 9 for T-splines (which they could not run on the GPU): "
         "evaluation time vs number of evaluation points (tspline-tjunction, 489 control points, "
         "six T-junctions)",
         "nurbsbench run --scenes tspline-tjunction --strategies all --samples "
         "4x4,8x8,16x16,32x32,64x64,128x128,256x256,512x512,1024x1024 --repetitions 3 --out DIR",
         true, fig9_tspline_time_vs_points},
        {"fig14_deboor_vs_basis", 50,
         "Tan 2012 Fig 14: one-pass de Boor (glsl-deboor) vs multi-pass basis functions "
         "(gl-pingpong), 16², 64², 256² control points",
         "nurbsbench run --scenes tan16,tan64,tan256 --strategies all --samples 256x256 "
         "--repetitions 5 --out DIR",
         true, fig14_deboor_vs_basis},
        {"fig15_lod", 60,
         "Tan 2012 Fig 15: LOD change by Haar wavelet vs re-evaluation (21×23 control points; "
         "128², 512², 1024² samples)",
         "nurbsbench lod --samples 128x128,512x512,1024x1024 --out DIR", true, fig15_lod},
        {"camera_path", 70,
         "Krishnamurthy 2007 §3.2: continuous LOD along a camera fly-in (gl-pingpong, drawn from "
         "a device copy) vs a fixed grid",
         "nurbsbench camera-path --scenes teapot --frames 60 --viewport 640x480 "
         "--pixels-per-sample 4 --fixed-samples 64x64 --out DIR",
         true, camera_path_section},
        {"rpns_frame", 80,
         "RPNS 2014: time per frame with deforming control points (update + evaluate)",
         "nurbsbench run --scenes teapot,patch144,many-256 --strategies all --samples 16x16 "
         "--repetitions 1 --deforming 30 --out DIR",
         true, rpns_frame},
        // A script, not a verb: one deforming run of vk-ksquad per mapping under DIR, then its
        // own report there; canonical.sh also hands those sets to the machine's report.
        {"rpns_mappings", 90,
         "RPNS 2014 §4: vk-ksquad's mappings onto the pipeline (GS-based, uniform, adaptive, "
         "non-uniform), time per frame with deforming control points",
         "scripts/rpns_mappings.sh --modes uniform,adaptive,gs,nonuniform --scenes "
         "teapot,patch144 --samples 16x16 --span-samples 4 --deforming 30 --repetitions 1 --out "
         "DIR",
         true, rpns_mappings},
        {"rpns_memory", 100, "RPNS 2014 Table 1: memory of NURBS vs Bézier control points",
         "nurbsbench memory --scenes all --json > DIR/memory.json", false, rpns_memory},
        {"fig8_many_surfaces", 110,
         "Krishnamurthy 2007 Fig 8 style: throughput vs number of surfaces (16×16 samples each)",
         "nurbsbench run --scenes many-1,many-4,many-16,many-64,many-256,many-1024,many-4096 "
         "--strategies all --samples 16x16 --repetitions 3 --out DIR",
         true, fig8_many_surfaces},
        {"fig8_trimmed_ducks", 120,
         "Krishnamurthy 2007 Fig 8 as it ran: frames per second vs number of ducks, one third "
         "trimmed (many-ducks-N, 16×16 samples per surface)",
         "nurbsbench run --scenes many-ducks-1,many-ducks-2,many-ducks-4,many-ducks-8,"
         "many-ducks-16,many-ducks-32,many-ducks-64 --strategies all --samples 16x16 "
         "--repetitions 5 --threads 1 --out DIR",
         true, fig8_trimmed_ducks},
        {"accuracy_heatmap", 130, "Accuracy: max_ulp per strategy and scene (worst over samplings)",
         "nurbsbench run --scenes default --strategies all --samples 64x64 --repetitions 3 --out "
         "DIR",
         true, accuracy_heatmap},
        {"accuracy_vs_degree", 140, "Accuracy: max_ulp vs degree (scenes degree-1 … degree-9)",
         "nurbsbench run --scenes degree-1,degree-2,degree-3,degree-4,degree-5,degree-6,"
         "degree-7,degree-8,degree-9 --strategies all --samples 64x64 --repetitions 3 --out DIR",
         true, accuracy_vs_degree},
        {"phases", 150, "Phase breakdown: where the time goes (setup, upload, evaluate, read back)",
         "nurbsbench run --scenes patch144 --strategies all --samples 256x256 --repetitions 3 "
         "--out DIR",
         true, phases_section},
        // A script, not a verb: one run per (R, tolerance) under DIR, then its own report there.
        {"trim_texture_resolution", 160,
         "Krishnamurthy 2007 §4: trim-texture misclassification rate outside the band vs "
         "trim-texture resolution R",
         "scripts/trim_texture_study.sh --resolutions 64,128,256,512,1024,2048,4096 --tolerances "
         "1e-2,1e-3,1e-5 --samples 256x256 --repetitions 3 --out DIR",
         true, trim_texture_resolution},
        // Re-evaluated here (only with --error-images / --trim-masks above 0); {} is the count.
        {"error_maps", 170,
         "Error heat maps of the {} worst (strategy, scene) pairs that can be redrawn here",
         "nurbsbench eval --scene S --strategy X --samples NxM --error-image F.png", false,
         error_maps, error_images_wanted},
        {"trim_masks", 180,
         "Trim masks of the {} (strategy, trimmed scene) pairs with the most misclassified "
         "samples",
         "nurbsbench run --scenes S --strategies X --samples NxM --images DIR (writes "
         "DIR/X__S__maskI.png)",
         false, trim_masks, trim_masks_wanted},
        {"results", 185, "Results sets and strategies", "", false, sets_section},
        {"measurements", 190,
         "Every measurement, with throughput as a fraction of the store-bandwidth limit", "", false,
         measurements_section},
    };
    std::stable_sort(table.begin(), table.end(),
                     [](const SectionRow& a, const SectionRow& b) { return a.order < b.order; });
    return table;
  }();
  return rows;
}

const std::string& chart_run(std::string_view id) {
  for (const SectionRow& row : section_rows())
    if (row.id == id && row.chart) return row.run;
  throw std::logic_error(fmt::format("chart {} has no row in section_rows()", id));
}

}  // namespace nurbs::report

namespace nurbs {

const std::vector<ChartCommand>& chart_commands() {
  static const std::vector<ChartCommand> commands = [] {
    std::vector<ChartCommand> out;
    for (const report::SectionRow& row : report::section_rows())
      if (row.chart) out.push_back({row.id, row.run});
    return out;
  }();
  return commands;
}

Report build_report(const std::vector<ResultSet>& sets, const ReportBuildOptions& options) {
  Report report;
  report.charts = {{"format", "nurbsbench-charts/1"}, {"charts", nlohmann::json::array()}};
  const report::Labeller label(sets);
  for (const report::SectionRow& row : report::section_rows())
    if (!row.wanted || row.wanted(options))
      report.sections.push_back(row.build({sets, label, report.charts, row, options}));
  // Each chart carries what its caption needs, so the plotter knows nothing about the report.
  for (nlohmann::json& chart : report.charts["charts"])
    for (const ReportSection& s : report.sections)
      if (s.id == chart["id"]) {
        chart["title"] = s.title;
        chart["context"] = s.context;
        chart["command"] = s.command;
        chart["file"] = s.id + ".png";
      }
  return report;
}

}  // namespace nurbs
