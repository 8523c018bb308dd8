#include "harness/machine.h"

#include <fmt/format.h>
#include <sys/utsname.h>

#include <chrono>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

namespace nurbs {

namespace generated {
extern const char* const git_commit;
}

const BuildInfo& build_info() {
  static const BuildInfo info{generated::git_commit, NURBSBENCH_BUILD_TYPE,
                              fmt::format("GCC-compatible {}", __VERSION__)};
  return info;
}

namespace {

std::string first_value(const char* path, std::string_view key, char separator) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.starts_with(key)) {
      auto pos = line.find(separator);
      if (pos == std::string::npos) continue;
      std::string value = line.substr(pos + 1);
      value.erase(0, value.find_first_not_of(" \t\""));
      while (!value.empty() && (value.back() == '"' || value.back() == ' ')) value.pop_back();
      return value;
    }
  return "unknown";
}

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace

std::string cpu_model() {
  return first_value("/proc/cpuinfo", "model name", ':');
}

nlohmann::json machine_record(int threads) {
  utsname uts{};
  uname(&uts);
  return {
      {"cpu_model", cpu_model()},
      {"logical_cores", std::thread::hardware_concurrency()},
      {"threads", threads},
      {"os", first_value("/etc/os-release", "PRETTY_NAME", '=')},
      {"kernel", fmt::format("{} {} {}", uts.sysname, uts.release, uts.machine)},
      {"compiler", build_info().compiler},
      {"build_type", build_info().build_type},
      {"git_commit", build_info().git_commit},
      {"libraries",
       {{"fmt",
         fmt::format("{}.{}.{}", FMT_VERSION / 10000, FMT_VERSION / 100 % 100, FMT_VERSION % 100)},
        {"nlohmann_json", fmt::format("{}.{}.{}", NLOHMANN_JSON_VERSION_MAJOR,
                                      NLOHMANN_JSON_VERSION_MINOR, NLOHMANN_JSON_VERSION_PATCH)},
        {"openmp", fmt::format("{}", _OPENMP)}}},
      {"date_utc", utc_now()},
  };
}

}  // namespace nurbs
