// Measured pairs evaluated again on this machine, for a picture of them (the error heat maps and
// trim masks sections).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "harness/report/kit.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs::report {

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
Redone redo(const Record& r);

using Draw = std::function<std::pair<std::string, std::string>(const Record&, const Redone&)>;
// The records `eligible` keeps, worst first by `worse`.
std::vector<const Record*> worst_records(
    const std::vector<ResultSet>& sets, const std::function<bool(const Record&)>& eligible,
    const std::function<bool(const Record&, const Record&)>& worse);

// Draws the first `count` (strategy, scene) pairs of `worst`, each redone here and drawn by `draw`
// (which returns the image's file name and a note), into s's images and `table` (its `figure`
// column from the record); a pair that cannot be drawn is listed with the reason and the next one
// is tried, up to three times `count` pairs.
void draw_worst(const std::vector<const Record*>& worst, int count, const Draw& draw,
                const std::function<std::string(const Record&)>& figure, ReportSection& s,
                ReportTable table);

}  // namespace nurbs::report
