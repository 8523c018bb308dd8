#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "harness/copy_limit.h"
#include "harness/drivers.h"
#include "harness/link_limit.h"
#include "harness/plugins/plugin.h"
#include "harness/store_limit.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gpu_devices.h"
#include "strategies/registry.h"

namespace nurbs::cli {

namespace {
nlohmann::json capabilities_json(const Capabilities& c) {
  nlohmann::json sampling = nlohmann::json::array();
  if (c.sampling.grid) sampling.push_back("grid");
  if (c.sampling.span_grid) sampling.push_back("span_grid");
  if (c.sampling.explicit_list) sampling.push_back("explicit");
  nlohmann::json precisions = nlohmann::json::array();
  if (c.fp32) precisions.push_back("f32");
  if (c.fp64) precisions.push_back("f64");
  return {{"max_degree", c.max_degree}, {"rational", c.rational},
          {"normals", c.normals},       {"precisions", precisions},
          {"sampling", sampling},       {"updates_control_points", c.updates_control_points}};
}
// The loaded library a driver file names: its path as written, or a loaded file of that name.
std::string loaded_path(const DriverFile& file, const std::vector<std::string>& loaded) {
  const auto base = [](const std::string& p) { return p.substr(p.find_last_of('/') + 1); };
  for (const std::string& l : loaded)
    if (l == file.library || base(l) == base(file.library)) return l;
  return {};
}

// Per GPU API: its devices (which one the strategies use), the driver files its loader reads
// here and which of them served, or why there is nothing.
nlohmann::json devices_json(std::string& text) {
  nlohmann::json apis = nlohmann::json::array();
  text += "devices (per GPU API; a software device is a CPU):\n";
  for (const ApiDevices& api : gpu_api_devices()) {
    nlohmann::json devices = nlohmann::json::array();
    text += fmt::format("  {}:\n", api.api);
    if (!api.unavailable.empty()) text += fmt::format("    none: {}\n", api.unavailable);
    for (const DeviceInfo& d : api.devices) {
      devices.push_back({{"name", d.name}, {"kind", d.kind}, {"details", d.details}});
      const auto detail = [&](const char* key) {
        const auto it = d.details.find(key);
        return it == d.details.end() ? std::string() : it->second;
      };
      std::string driver = detail("driver");
      if (driver.empty()) driver = detail("gl_version");
      if (driver.empty()) driver = detail("driver_version");
      const std::string index = detail("index");
      text += fmt::format("    {}{} ({}{}{}){}\n", index.empty() ? "" : fmt::format("#{} ", index),
                          d.name, d.kind, d.kind == "cpu" ? ": a CPU figure" : "",
                          driver.empty() ? "" : ", " + driver,
                          detail("chosen") == "yes" ? "  <- used without --device" : "");
    }
    nlohmann::json files = nlohmann::json::array();
    const std::vector<DriverFile> driver_files_here = driver_files(api.api);
    if (driver_files_here.empty()) text += "    driver files: none where the loader looks\n";
    for (const DriverFile& f : driver_files_here) {
      const std::string loaded = loaded_path(f, api.loaded_libraries);
      files.push_back(
          {{"path", f.path}, {"library", f.library}, {"from", f.from}, {"loaded", loaded}});
      text += fmt::format("    driver file {} -> {}{} (from {})\n", f.path, f.library,
                          loaded.empty() ? "" : ", loaded: " + loaded, f.from);
    }
    apis.push_back({{"api", api.api},
                    {"unavailable", api.unavailable},
                    {"devices", devices},
                    {"driver_files", files}});
  }
  return apis;
}

}  // namespace

int list_command(const ListOptions& options) {
  IsolationOptions probe;
  probe.timeout_s = options.timeout_s;
  load_plugins(options.plugins, isolation_settings(probe));
  nlohmann::json strategies = nlohmann::json::array();
  std::string text = "strategies:\n";
  for (const StrategyEntry* entry : all_strategies()) {
    const StrategyEntry& e = *entry;
    // A plugin that cannot be used is unavailable here, with its reason and no capabilities (its
    // table, if it has one, was not read); its measurements are failed records with that reason.
    const std::optional<std::string> problem = plugin_problem(e);
    const Availability a = problem ? Availability{false, *problem} : e.probe();
    strategies.push_back({{"name", e.name},
                          {"available", a.available},
                          {"reason", a.reason},
                          {"role", e.role},
                          {"source", e.source},
                          {"capabilities", problem ? nlohmann::json(nullptr)
                                                   : capabilities_json(e.capabilities())}});
    const StrategyLibrary* library = strategy_library(e);
    if (library)
      strategies.back()["library"] = {{"path", library->path}, {"sha256", library->sha256}};
    text += fmt::format("  {:<20} {:<9} {:<40} {}\n", e.name, e.role,
                        a.available ? "available" : "unavailable: " + a.reason, e.source);
    if (library)
      text +=
          fmt::format("  {:<20} {:<9} {} (sha256 {})\n", "", "", library->path, library->sha256);
  }
  // Not strategies: machine ceilings `run` measures beside them (harness/store_limit.h,
  // harness/copy_limit.h, harness/link_limit.h).
  std::vector<std::pair<std::string, std::string>> limit_rows = {
      {std::string(kStoreLimitName),
       "memory store bandwidth for the request's output (points x bytes per point), same threads"},
      {std::string(kDeviceCopyLimitName),
       "device-to-device copy of the request's output on the Vulkan device (a CPU figure on "
       "lavapipe)"}};
  const std::pair<LinkApi, const char*> link_rows[] = {
      {LinkApi::vulkan, "Vulkan (a CPU figure on lavapipe)"},
      {LinkApi::opencl, "OpenCL (a CPU figure on PoCL)"},
      {LinkApi::gl, "OpenGL, through pixel buffers (a CPU figure on llvmpipe)"}};
  for (const auto& [api, where] : link_rows)
    limit_rows.emplace_back(link_limit_name(api),
                            fmt::format("host->device and device->host copies of the request's "
                                        "output through pinned, reused memory on {}",
                                        where));
  limit_rows.emplace_back(kFragmentPassLimitName,
                          "a trivial GL fragment pass writing one RGBA32F pixel per point of the "
                          "request: the GL strategies' own ceiling (a CPU figure on llvmpipe)");
  text += "limits:\n";
  nlohmann::json limits = nlohmann::json::array();
  for (const auto& [name, description] : limit_rows) {
    text += fmt::format("  {:<20} {:<9} {}\n", name, "limit", description);
    limits.push_back({{"name", name}, {"role", "limit"}, {"description", description}});
  }
  nlohmann::json scenes = nlohmann::json::array();
  text += "scenes:\n";
  for (const BuiltinSceneInfo& s : builtin_scenes()) {
    scenes.push_back({{"name", s.name}, {"description", s.description}});
    text += fmt::format("  {:<20} {}\n", s.name, s.description);
  }
  const nlohmann::json apis = devices_json(text);
  if (options.json)
    std::cout << nlohmann::json{{"strategies", strategies},
                                {"limits", limits},
                                {"scenes", scenes},
                                {"devices", apis}}
                     .dump(2)
              << "\n";
  else
    std::cout << text;
  return 0;
}

}  // namespace nurbs::cli
