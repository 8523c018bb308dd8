#include "harness/drivers.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <system_error>

#include "reference/validation.h"

namespace fs = std::filesystem;

namespace nurbs {
namespace {

std::string env(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

std::vector<std::string> split_colons(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ':');)
    if (!item.empty()) items.push_back(item);
  return items;
}

std::string join_colons(const std::vector<std::string>& items) {
  return fmt::format("{}", fmt::join(items, ":"));
}

// Appends (or prepends) the items not already in the colon list `name`; true when it changed.
bool add_to_list(const char* name, const std::vector<std::string>& added, bool prepend,
                 std::vector<std::string> base) {
  std::vector<std::string> items = std::move(base);
  std::vector<std::string> fresh;
  for (const std::string& a : added)
    if (std::find(items.begin(), items.end(), a) == items.end() &&
        std::find(fresh.begin(), fresh.end(), a) == fresh.end())
      fresh.push_back(a);
  if (fresh.empty()) return false;
  items.insert(prepend ? items.begin() : items.end(), fresh.begin(), fresh.end());
  setenv(name, join_colons(items).c_str(), 1);
  return true;
}

// {"ICD": {"library_path": ...}}: the Vulkan manifests' and glvnd vendor files' common shape.
std::string json_library(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return "(unreadable)";
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("ICD") || !j["ICD"].is_object() ||
      !j["ICD"].contains("library_path") || !j["ICD"]["library_path"].is_string())
    return "(unreadable)";
  return j["ICD"]["library_path"].get<std::string>();
}

std::string icd_library(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  if (!in || !std::getline(in, line)) return "(unreadable)";
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

std::vector<fs::path> files_in(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.path().extension() == extension) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// A list entry that is a folder stands for its files (the loaders read either).
void add_entry(std::vector<DriverFile>& out, const std::string& entry, const std::string& extension,
               const std::string& from, std::string (*library)(const fs::path&)) {
  std::error_code ec;
  if (fs::is_directory(entry, ec)) {
    for (const fs::path& f : files_in(entry, extension)) out.push_back({f, library(f), from});
  } else {
    out.push_back({entry, library(entry), from});
  }
}

std::string home_path(const char* xdg, const char* fallback) {
  const std::string value = env(xdg);
  if (!value.empty()) return value;
  const std::string home = env("HOME");
  return home.empty() ? "" : home + "/" + fallback;
}

std::vector<DriverFile> vulkan_files() {
  std::vector<DriverFile> out;
  for (const std::string& f : split_colons(env("VK_ADD_DRIVER_FILES")))
    add_entry(out, f, ".json", "VK_ADD_DRIVER_FILES", json_library);
  for (const char* name : {"VK_DRIVER_FILES", "VK_ICD_FILENAMES"}) {
    if (env(name).empty()) continue;
    for (const std::string& f : split_colons(env(name))) add_entry(out, f, ".json", name, json_library);
    return out;  // replaces the standard locations
  }
  // The loader's order on Linux: XDG config dirs, /etc, XDG data dirs (LoaderInterfaceArchitecture).
  std::vector<std::string> roots;
  if (const std::string h = home_path("XDG_CONFIG_HOME", ".config"); !h.empty()) roots.push_back(h);
  const std::string config_dirs = env("XDG_CONFIG_DIRS");
  for (const std::string& d : split_colons(config_dirs.empty() ? "/etc/xdg" : config_dirs))
    roots.push_back(d);
  roots.push_back("/etc");
  if (const std::string h = home_path("XDG_DATA_HOME", ".local/share"); !h.empty()) roots.push_back(h);
  const std::string data_dirs = env("XDG_DATA_DIRS");
  for (const std::string& d : split_colons(data_dirs.empty() ? "/usr/local/share:/usr/share" : data_dirs))
    roots.push_back(d);
  for (const std::string& root : roots) {
    const fs::path dir = fs::path(root) / "vulkan" / "icd.d";
    for (const fs::path& f : files_in(dir, ".json")) out.push_back({f, json_library(f), dir});
  }
  return out;
}

constexpr const char* kEglVendorDirs = "/etc/glvnd/egl_vendor.d:/usr/share/glvnd/egl_vendor.d";

std::vector<DriverFile> egl_files() {
  std::vector<DriverFile> out;
  if (const std::string files = env("__EGL_VENDOR_LIBRARY_FILENAMES"); !files.empty()) {
    for (const std::string& f : split_colons(files))
      out.push_back({f, json_library(f), "__EGL_VENDOR_LIBRARY_FILENAMES"});
    return out;
  }
  const std::string dirs = env("__EGL_VENDOR_LIBRARY_DIRS");
  for (const std::string& d : split_colons(dirs.empty() ? kEglVendorDirs : dirs))
    for (const fs::path& f : files_in(d, ".json"))
      out.push_back({f, json_library(f), dirs.empty() ? d : "__EGL_VENDOR_LIBRARY_DIRS"});
  return out;
}

constexpr const char* kOpenClVendors = "/etc/OpenCL/vendors";

std::vector<DriverFile> opencl_files() {
  std::vector<DriverFile> out;
  const std::string vendors = env("OCL_ICD_VENDORS");
  if (vendors.empty()) {
    for (const fs::path& f : files_in(kOpenClVendors, ".icd"))
      out.push_back({f, icd_library(f), kOpenClVendors});
    return out;
  }
  std::error_code ec;
  if (fs::is_directory(vendors, ec)) {
    for (const fs::path& f : files_in(vendors, ".icd"))
      out.push_back({f, icd_library(f), "OCL_ICD_VENDORS"});
  } else if (fs::path(vendors).extension() == ".icd") {
    out.push_back({vendors, icd_library(vendors), "OCL_ICD_VENDORS"});
  } else {
    out.push_back({vendors, vendors, "OCL_ICD_VENDORS (a library)"});
  }
  return out;
}

// OpenCL libraries of vendors that may come without an .icd file beside them.
bool opencl_vendor_library(const std::string& name) {
  for (const char* known : {"libnvidia-opencl.so.1", "libamdocl64.so", "libamdocl-orca64.so",
                            "libigdrcl.so", "libintelocl.so", "libpocl.so.2",
                            "libMesaOpenCL.so.1", "librusticlOpenCL.so.1"})
    if (name == known) return true;
  return false;
}

bool shared_library(const std::string& name) {
  return name.rfind("lib", 0) == 0 &&
         (name.size() > 3 && (name.ends_with(".so") || name.find(".so.") != std::string::npos));
}

// glibc's own libraries: never a driver, and never to be taken from a driver's folder.
bool glibc_library(const std::string& name) {
  for (const char* prefix : {"ld-linux", "libc.so", "libm.so", "libmvec.so", "libpthread.so",
                             "libdl.so", "librt.so", "libresolv.so", "libutil.so", "libanl.so",
                             "libnsl.so", "libcrypt.so", "libBrokenLocale.so", "libc_malloc_debug.so",
                             "libnss_", "libthread_db.so", "libmemusage.so", "libpcprofile.so"})
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

struct FoundDrivers {
  std::vector<std::string> vulkan, egl_dirs, opencl_icds, opencl_libraries, library_dirs;
};

FoundDrivers scan(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(fmt::format("--driver-dir '{}': not a folder", dir));
  FoundDrivers found;
  std::set<std::string> library_dirs, egl_dirs, glibc_dirs;
  std::size_t entries = 0;
  const fs::path root = fs::absolute(dir, ec);
  // A driver tree is a few levels deep; the bounds keep a wrong DIR (say /) cheap.
  fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
  for (; !ec && it != end && entries < 200000; it.increment(ec), ++entries) {
    if (it.depth() > 6) {
      it.disable_recursion_pending();
      continue;
    }
    const fs::path& p = it->path();
    const std::string name = p.filename().string();
    const std::string parent = p.parent_path().filename().string();
    const std::string grandparent = p.parent_path().parent_path().filename().string();
    if (it->is_directory(ec)) continue;
    if (parent == "icd.d" && grandparent == "vulkan" && p.extension() == ".json")
      found.vulkan.push_back(p);
    else if (parent == "egl_vendor.d" && grandparent == "glvnd" && p.extension() == ".json")
      egl_dirs.insert(p.parent_path());
    else if (parent == "vendors" && grandparent == "OpenCL" && p.extension() == ".icd")
      found.opencl_icds.push_back(p);
    else if (glibc_library(name))
      glibc_dirs.insert(p.parent_path());
    else if (shared_library(name)) {
      library_dirs.insert(p.parent_path());
      if (opencl_vendor_library(name)) found.opencl_libraries.push_back(p);
    }
  }
  found.egl_dirs.assign(egl_dirs.begin(), egl_dirs.end());
  // A folder that holds a C library of its own (NVIDIA's containers mount one beside the driver)
  // must never reach LD_LIBRARY_PATH: ld.so would load that glibc into this process.
  for (const std::string& d : library_dirs)
    if (!glibc_dirs.contains(d)) found.library_dirs.push_back(d);
  std::sort(found.vulkan.begin(), found.vulkan.end());
  std::sort(found.opencl_icds.begin(), found.opencl_icds.end());
  if (found.vulkan.empty() && found.egl_dirs.empty() && found.opencl_icds.empty() &&
      found.library_dirs.empty())
    throw InputError(fmt::format(
        "--driver-dir '{}': holds no Vulkan ICD manifest (vulkan/icd.d/*.json), EGL vendor file "
        "(glvnd/egl_vendor.d/*.json), OpenCL .icd file or shared library",
        dir));
  return found;
}

// True when a driver file the loader reads already names this library (compared by file name):
// the same driver read twice is enumerated twice (seen on the H200: its Vulkan ICD, in the standard
// folder and under --driver-dir, became devices #0 and #1).
bool already_read(const std::vector<DriverFile>& files, const std::string& library) {
  const std::string name = fs::path(library).filename();
  return std::any_of(files.begin(), files.end(), [&](const DriverFile& f) {
    return fs::path(f.library).filename() == name;
  });
}

// What of DIR's drivers the loaders do not read yet.
FoundDrivers unread(FoundDrivers found) {
  const std::vector<DriverFile> vulkan = vulkan_files(), egl = egl_files(), opencl = opencl_files();
  std::erase_if(found.vulkan, [&](const std::string& f) { return already_read(vulkan, json_library(f)); });
  std::erase_if(found.egl_dirs, [&](const std::string& d) {
    const std::vector<fs::path> files = files_in(d, ".json");
    return std::all_of(files.begin(), files.end(),
                       [&](const fs::path& f) { return already_read(egl, json_library(f)); });
  });
  std::erase_if(found.opencl_icds, [&](const std::string& f) { return already_read(opencl, icd_library(f)); });
  std::erase_if(found.opencl_libraries, [&](const std::string& l) { return already_read(opencl, l); });
  return found;
}

// ocl-icd reads one vendors folder (OCL_ICD_VENDORS replaces /etc/OpenCL/vendors), so the
// machine's .icd files and DIR's are merged into one private folder that OCL_ICD_VENDORS names.
void add_opencl(const FoundDrivers& found) {
  std::vector<std::pair<std::string, std::string>> icds;  // file name, contents
  for (const DriverFile& f : opencl_files()) icds.emplace_back(fs::path(f.path).filename(), f.library);
  for (const std::string& f : found.opencl_icds) icds.emplace_back(fs::path(f).filename(), icd_library(f));
  if (found.opencl_icds.empty())
    for (const std::string& lib : found.opencl_libraries)
      icds.emplace_back(fs::path(lib).filename().string() + ".icd", lib);
  if (found.opencl_icds.empty() && found.opencl_libraries.empty()) return;
  std::sort(icds.begin(), icds.end());
  icds.erase(std::unique(icds.begin(), icds.end()), icds.end());
  std::string key;
  for (const auto& [name, library] : icds) key += name + "=" + library + ";";
  const std::string tmp = env("TMPDIR").empty() ? "/tmp" : env("TMPDIR");
  const fs::path merged = fs::path(tmp) / fmt::format("nurbsbench-{}-opencl-vendors-{:016x}", getuid(),
                                                      std::hash<std::string>{}(key));
  std::error_code ec;
  fs::create_directories(merged, ec);
  if (ec) throw InputError(fmt::format("--driver-dir: cannot make '{}': {}", merged.string(), ec.message()));
  for (const auto& [name, library] : icds) {
    const fs::path file = merged / name;
    if (fs::exists(file, ec) && icd_library(file) == library) continue;
    std::ofstream(file) << library << "\n";
  }
  setenv("OCL_ICD_VENDORS", merged.c_str(), 1);
}

}  // namespace

std::vector<DriverFile> driver_files(const std::string& api) {
  if (api == "Vulkan") return vulkan_files();
  if (api == "OpenGL (EGL)") return egl_files();
  if (api == "OpenCL") return opencl_files();
  return {};
}

bool apply_driver_dirs(const std::vector<std::string>& dirs) {
  bool library_path_changed = false;
  for (const std::string& dir : dirs) {
    const FoundDrivers found = unread(scan(dir));
    // Where the user named the drivers (VK_DRIVER_FILES, or the older VK_ICD_FILENAMES), the loader
    // reads that list alone and ignores VK_ADD_DRIVER_FILES (seen with loader 1.3.239): add there.
    const char* vulkan_list = !env("VK_DRIVER_FILES").empty()    ? "VK_DRIVER_FILES"
                              : !env("VK_ICD_FILENAMES").empty() ? "VK_ICD_FILENAMES"
                                                                 : "VK_ADD_DRIVER_FILES";
    add_to_list(vulkan_list, found.vulkan, false, split_colons(env(vulkan_list)));
    if (!env("__EGL_VENDOR_LIBRARY_FILENAMES").empty()) {
      std::vector<std::string> files;
      for (const std::string& d : found.egl_dirs)
        for (const fs::path& f : files_in(d, ".json")) files.push_back(f);
      add_to_list("__EGL_VENDOR_LIBRARY_FILENAMES", files, true,
                  split_colons(env("__EGL_VENDOR_LIBRARY_FILENAMES")));
    } else if (!found.egl_dirs.empty()) {
      const std::string dirs_now = env("__EGL_VENDOR_LIBRARY_DIRS");
      add_to_list("__EGL_VENDOR_LIBRARY_DIRS", found.egl_dirs, true,
                  split_colons(dirs_now.empty() ? kEglVendorDirs : dirs_now));
    }
    add_opencl(found);
    library_path_changed |= add_to_list("LD_LIBRARY_PATH", found.library_dirs, false,
                                        split_colons(env("LD_LIBRARY_PATH")));
  }
  return library_path_changed;
}

void reexecute(char** argv) {
  execv("/proc/self/exe", argv);
}

}  // namespace nurbs
