// The console summary of a run: one row per record, aligned columns, CPU/GPU device kind shown so
// a software-rasterizer figure is never read as a GPU figure.
#pragma once

#include <string>
#include <vector>

#include "harness/gates.h"
#include "harness/record.h"

namespace nurbs {

// With a "trim" column when some record is on a trimmed scene (trim_text).
std::string summary_table(const std::vector<Record>& records);
// One line counting each status present, in the Status order: "statuses: 5 ok, 1 crashed".
std::string status_counts(const std::vector<Record>& records);
// A record's trimming as tables show it: "untrimmed", "N misclassified (rate), M boundary" for a
// strategy that classified, "" on a scene without trims.
std::string trim_text(const Record& r);
// The digest under the table, one line per scene and sampling: the fastest record that passes its
// accuracy gates (passes_gates; over both precisions when the run has both, naming the one), and
// its evaluate throughput over cpu-coxdeboor's on the same scene, samples and precision. A figure
// measured on a "cpu" device -- the host, or llvmpipe/lavapipe/PoCL behind a GPU API -- is
// labelled "CPU figure". Pure: records and gates in, lines out, the heading first.
std::vector<std::string> summary_digest(const std::vector<Record>& records,
                                        const std::vector<Gate>& gates);
// The deforming benchmark's view (records with extra phase "frame"): median frame time and its
// parts, and whether the strategy updated its control points or was prepared again.
std::string deforming_table(const std::vector<Record>& records);

}  // namespace nurbs
