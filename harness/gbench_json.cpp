#include "harness/gbench_json.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

namespace nurbs {

using nlohmann::json;

json gbench_json(const ResultsFile& results) {
  const json& m = results.machine;
  json context = {
      {"date", m.value("date_utc", "")},
      {"host_name", m.value("cpu_model", "unknown")},
      {"executable", "nurbsbench run"},
      {"num_cpus", m.contains("logical_cores") && m["logical_cores"].is_number()
                       ? m["logical_cores"].get<int>()
                       : 0},
      {"mhz_per_cpu", 0},
      {"cpu_scaling_enabled", false},
      {"caches", json::array()},
      {"library_build_type", m.value("build_type", "") == "Debug" ? "debug" : "release"},
      {"nurbsbench_git_commit", m.value("git_commit", "unknown")},
      {"nurbsbench_cpu_model", m.value("cpu_model", "unknown")}};
  json benchmarks = json::array();
  int family = 0;
  for (const Record& r : results.records) {
    if (r.status != Status::ok) continue;
    const std::string name =
        fmt::format("{}/{}/{}/{}", r.strategy, r.scene, r.samples, r.precision);
    auto entry = [&](const std::string& run_name, double seconds) {
      json b = {{"name", run_name},
                {"family_index", family},
                {"per_family_instance_index", 0},
                {"run_name", run_name},
                {"run_type", "iteration"},
                {"repetitions", 1},
                {"repetition_index", 0},
                {"threads", 1},
                {"iterations", std::max(r.repetitions, 1)},
                {"real_time", seconds * 1e6},
                {"cpu_time", seconds * 1e6},
                {"time_unit", "us"},
                {"items_per_second", seconds > 0 ? static_cast<double>(r.points) / seconds : 0.0},
                {"device", r.device.name},
                {"device_kind", r.device.kind}};
      if (r.accuracy && std::isfinite(r.accuracy->max_ulp)) b["max_ulp"] = r.accuracy->max_ulp;
      benchmarks.push_back(std::move(b));
      ++family;
    };
    entry(name, r.evaluate.median_s);
    if (r.role != "limit") entry(name + "/end_to_end", r.end_to_end.median_s);
  }
  return {{"context", context}, {"benchmarks", benchmarks}};
}

}  // namespace nurbs
