// Where the GPU APIs' loaders find vendor drivers, and `--driver-dir DIR` for a driver installed
// where they do not look (a GPU node's driver under /usr/local/nvidia, a driver unpacked by a
// user without root). The loaders are the bundle's own (scripts/bundle.sh): the Vulkan loader, the
// GL vendor-neutral dispatch (glvnd, for EGL) and the OpenCL ICD loader; the drivers are always the
// machine's. Everything here works through the loaders' documented environment variables, so this
// process and every isolated measurement it starts (they inherit the environment) see the same.
#pragma once

#include <string>
#include <vector>

namespace nurbs {

// One driver file a loader would read: a Vulkan ICD manifest, a glvnd EGL vendor file or an
// OpenCL .icd file, and the library it names.
struct DriverFile {
  std::string path;
  std::string library;  // as written in the file (a path or a bare soname)
  std::string from;     // why the loader reads it: "VK_DRIVER_FILES", "/usr/share/vulkan/icd.d"...
};

// The files each loader reads here, in its own search order and with its environment variables:
// api is "Vulkan", "OpenGL (EGL)" or "OpenCL". Files that cannot be read are listed with
// library "(unreadable)".
std::vector<DriverFile> driver_files(const std::string& api);

// Adds what each DIR holds — Vulkan ICD manifests (…/vulkan/icd.d/*.json), glvnd EGL vendor files
// (…/glvnd/egl_vendor.d/*.json), OpenCL .icd files (…/OpenCL/vendors/*.icd, or a vendor's OpenCL
// library with none, for which an .icd is written), and the folders of its shared libraries — to
// the loaders' variables, keeping what the user set. Idempotent. Returns true when the library
// search path (LD_LIBRARY_PATH) changed: it is read at process start, so the caller re-executes.
// Throws InputError (exit 2) naming the option and the folder when DIR is not a folder or holds
// no driver file and no driver library.
bool apply_driver_dirs(const std::vector<std::string>& dirs);

// Re-executes this binary with the same arguments and the environment as it is now; returns only
// on failure (then the caller goes on: the drivers' libraries may still be in the system's cache).
void reexecute(char** argv);

}  // namespace nurbs
