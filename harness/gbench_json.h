// Results as Google Benchmark JSON (`context` + `benchmarks`), so `compare.py` from Google
// Benchmark's tools compares two nurbsbench runs (e.g. two machines or two commits) as it compares
// two benchmark binaries' outputs. A writer reading records, like the CSV and JSON writers.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "harness/results_writer.h"

namespace nurbs {

// One benchmark per measured record, named "<strategy>/<scene>/<samples>/<precision>", with the
// median evaluate time as real_time and cpu_time (host wall clock; nurbsbench measures no separate
// CPU time), `iterations` = repetitions, time_unit "us", items_per_second = throughput, and
// max_ulp as a counter; plus "<name>/end_to_end" with the median upload + evaluate + read_back.
// Records that were not measured (unavailable, refused, failed) are left out.
nlohmann::json gbench_json(const ResultsFile& results);

}  // namespace nurbs
