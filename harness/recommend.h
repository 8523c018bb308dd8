// `nurbsbench recommend`: for a workload and a tolerance, the strategies ranked by measured
// throughput among those whose measured error is within the tolerance, and for every other one
// the reason it was left out. Works on records only (from a results file or a quick run), so it
// answers for whatever strategies the records hold; records of role "limit" are not candidates.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/record.h"

namespace nurbs {

struct Tolerance {
  enum class Unit { ulp, model } unit = Unit::ulp;
  double value = 0;
  std::string text() const;
};
// "8ulp", "8ulps", "8 ulp" (f32 ulps of the scene's largest coordinate, as max_ulp) or a plain
// number in model units ("1e-5", compared with max_abs). Throws InputError naming --tolerance.
Tolerance parse_tolerance(std::string_view text);

struct Workload {
  std::optional<std::string> scene;      // records of this scene only (else every scene)
  std::optional<std::string> samples;    // "256x256" / "span4" (else every sampling)
  std::optional<std::string> precision;  // f32 / f64 (else both, as separate candidates)
  bool deforming = false;                // rank by the "frame" phase (deforming control points)
  Tolerance tolerance;
};

struct Candidate {
  std::string strategy, precision, role, device;
  std::size_t records = 0;  // measurements of the workload it was judged on
  double points_per_s = 0;  // total points / total median time (evaluate, or frame when deforming)
  double max_ulp = 0, max_abs = 0;
  std::string excluded;  // empty: within tolerance and ranked; else why it was left out
};

struct Recommendation {
  std::string scope;                // which records were used, in words
  std::vector<Candidate> ranked;    // fastest first
  std::vector<Candidate> excluded;  // by name
};

// Throws InputError when no record matches the workload (naming the scenes/samples there are).
Recommendation recommend(const std::vector<Record>& records, const Workload& workload);

std::string recommendation_text(const Recommendation& r, const Workload& workload);
nlohmann::json recommendation_json(const Recommendation& r, const Workload& workload);

}  // namespace nurbs
