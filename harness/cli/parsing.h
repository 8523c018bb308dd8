// The CLI's value parsers (lists, samplings, precisions, strategy options): pure functions of the
// option text, each throwing InputError with one line naming the option, the item and the rule.
// A library of their own (nurbsbench_input) so the fuzz targets (tests/fuzz/) link them alone.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "reference/reference_evaluator.h"
#include "reference/sampling.h"
#include "reference/scalar.h"

namespace nurbs::cli {

// More items than any run needs; a longer list is a mistake (or a script gone wrong).
inline constexpr std::size_t kMaxListItems = 1024;

// `text` without the spaces and tabs around it (list items, CSV fields).
std::string_view trim_blanks(std::string_view text);
// A comma list as the user typed it: items trimmed of spaces and tabs; an empty item ("64x64,,")
// or more than kMaxListItems is an error naming `option`. Blank text is the empty list.
std::vector<std::string> parse_list(std::string_view option, std::string_view text);
// NxM grids ("N" alone is NxN), each side in 2..kMaxGridPerDirection, none given twice.
std::vector<Sampling> parse_grid_list(std::string_view option, std::string_view text);
// Span-grid step counts T in 1..kMaxSpanSteps, none given twice.
std::vector<Sampling> parse_span_list(std::string_view option, std::string_view text);
Precision parse_precision(std::string_view text);
// --trim-band: a fraction of each trimmed surface's (u, v) domain diagonal, finite, in [0, 1);
// absent = kDefaultTrimBand (harness/metrics.h).
double parse_trim_band(const std::optional<std::string>& text);
ReferencePrecision parse_reference(std::string_view text);
// The lenient split --strategies uses: empty items dropped.
std::vector<std::string> split_list(std::string_view text);
// --scenes: "default" = every listed built-in scene except those whose default grids exceed the
// per-request sample limit (many-4096); "all" = every listed built-in scene; else a comma list
// (parse_list) with no name given twice.
std::vector<std::string> scene_list(std::string_view text, std::string_view option = "--scenes");
// StrategyOptions.extra for --gl, --device and each --strategy-option KEY=VALUE (empty: the
// strategies' defaults); a KEY given twice is an error.
std::map<std::string, std::string> backend_extra(
    const std::string& gl, const std::string& device,
    const std::vector<std::string>& strategy_options = {});
// An output file the user named (`--out`): absolute (a strategy's chdir() cannot move it), not a
// directory, in a directory where a file can be created -- tried by creating and removing one, so
// that the answer is the filesystem's (/proc refuses even root). Throws InputError naming the
// option, the path and why, before any work is done.
std::string writable_output_file(std::string_view option, const std::string& path);
// The thread setting shared by OpenMP, llvmpipe/lavapipe and PoCL; returns the count in force.
int apply_thread_setting(int threads);

}  // namespace nurbs::cli
