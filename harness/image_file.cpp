#include "harness/image_file.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <unistd.h>

#include <stdexcept>
#include <system_error>

namespace nurbs {

namespace fs = std::filesystem;

namespace {

using WriteFn = void (*)(const ImageFile&, const char*, std::string&);

struct Module {
  WriteFn write = nullptr;
  std::string error;  // why it could not be loaded
};

#ifdef NURBSBENCH_IMAGE_MODULE
// Beside the running binary first (a build tree copied elsewhere), then where the build put it.
const Module& image_module() {
  static const Module module = [] {
    Module m;
    const fs::path name = fs::path(NURBSBENCH_IMAGE_MODULE).filename();
    std::error_code ignored;
    const fs::path beside = fs::read_symlink("/proc/self/exe", ignored).parent_path() / name;
    std::string tried;
    for (const fs::path& candidate : {beside, fs::path(NURBSBENCH_IMAGE_MODULE)}) {
      if (!fs::exists(candidate, ignored)) {
        tried += fmt::format("{}{} (missing)", tried.empty() ? "" : ", ", candidate.string());
        continue;
      }
      void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (handle == nullptr) {
        tried +=
            fmt::format("{}{} ({})", tried.empty() ? "" : ", ", candidate.string(), ::dlerror());
        continue;
      }
      m.write = reinterpret_cast<WriteFn>(::dlsym(handle, "nurbsbench_write_image_file"));
      if (m.write != nullptr) return m;
      tried += fmt::format("{}{} (no nurbsbench_write_image_file)", tried.empty() ? "" : ", ",
                           candidate.string());
    }
    m.error = "cannot load the OpenImageIO module: tried " + tried;
    return m;
  }();
  return module;
}
#else
const Module& image_module() {
  static const Module module{nullptr,
                             "this build has no OpenImageIO (install libopenimageio-dev, see "
                             "scripts/setup.sh, and reconfigure)"};
  return module;
}
#endif

}  // namespace

bool image_files_built() {
#ifdef NURBSBENCH_IMAGE_MODULE
  return true;
#else
  return false;
#endif
}

void write_image_file(const fs::path& path, const ImageFile& image) {
  const Module& module = image_module();
  if (module.write == nullptr) throw std::runtime_error(path.string() + ": " + module.error);
  const fs::path tmp = path.parent_path() / fmt::format(".{}.tmp{}{}", path.stem().string(),
                                                        ::getpid(), path.extension().string());
  std::string error;
  module.write(image, tmp.c_str(), error);
  if (!error.empty()) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error(fmt::format("{}: {}", path.string(), error));
  }
  fs::rename(tmp, path);
}

}  // namespace nurbs
