// The machine a run was measured on, recorded with every results file so numbers from different
// machines are never mixed up: CPU, cores, OS, compiler, build type, library versions, commit,
// the thread setting. Each record adds its own strategy's device (GL renderer, Vulkan device...).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

namespace nurbs {

struct BuildInfo {
  std::string git_commit;  // "<sha>[-dirty]" or "unknown"
  std::string build_type;
  std::string compiler;
};
const BuildInfo& build_info();

nlohmann::json machine_record(int threads);
std::string cpu_model();

}  // namespace nurbs
