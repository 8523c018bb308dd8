// --driver-dir (harness/drivers.h): what a driver folder adds to each loader's variables, what it
// must never add (a folder holding its own glibc, as NVIDIA's container mount does), and the
// driver files each loader reads.
#include "harness/drivers.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "reference/validation.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;

const char* const kVariables[] = {"VK_ADD_DRIVER_FILES", "VK_DRIVER_FILES", "VK_ICD_FILENAMES",
                                  "__EGL_VENDOR_LIBRARY_FILENAMES", "__EGL_VENDOR_LIBRARY_DIRS",
                                  "OCL_ICD_VENDORS", "LD_LIBRARY_PATH", "TMPDIR", "XDG_DATA_DIRS"};

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

void write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

std::string manifest(const std::string& library) {
  return R"({"file_format_version": "1.0.0", "ICD": {"library_path": ")" + library + R"("}})";
}

// Each test starts from none of the loaders' variables set and leaves the process as it was.
class DriverDir : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* v : kVariables) {
      if (const char* value = std::getenv(v)) saved_[v] = value;
      unsetenv(v);
    }
    root_ = fs::temp_directory_path() / ("nurbsbench-drivers-test-" + std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "tmp");
    setenv("TMPDIR", (root_ / "tmp").c_str(), 1);
  }
  void TearDown() override {
    for (const char* v : kVariables) unsetenv(v);
    for (const auto& [name, value] : saved_) setenv(name.c_str(), value.c_str(), 1);
    fs::remove_all(root_);
  }
  // A driver folder laid out as NVIDIA's container mount: share/vulkan/icd.d, share/glvnd,
  // lib64 with the driver libraries (OpenCL's without an .icd file), glibc/ with a C library.
  fs::path nvidia_like() {
    const fs::path d = root_ / "nvidia";
    write(d / "share/vulkan/icd.d/nvidia_icd.json", manifest("libGLX_nvidia.so.0"));
    write(d / "share/glvnd/egl_vendor.d/10_nvidia.json", manifest("libEGL_nvidia.so.0"));
    write(d / "lib64/libGLX_nvidia.so.0", "");
    write(d / "lib64/libnvidia-opencl.so.1", "");
    write(d / "glibc/libc.so.6", "");
    write(d / "glibc/libpthread.so.0", "");
    write(d / "bin/nvidia-smi", "");
    return d;
  }
  fs::path root_;
  std::map<std::string, std::string> saved_;
};

TEST_F(DriverDir, AddsEachLoadersFilesAndTheLibraryFolderButNeverAFolderHoldingGlibc) {
  const fs::path d = nvidia_like();
  EXPECT_TRUE(apply_driver_dirs({d.string()}));
  EXPECT_EQ(env("VK_ADD_DRIVER_FILES"), (d / "share/vulkan/icd.d/nvidia_icd.json").string());
  // glvnd's default folders stay searched, after the driver's.
  EXPECT_EQ(env("__EGL_VENDOR_LIBRARY_DIRS"),
            (d / "share/glvnd/egl_vendor.d").string() +
                ":/etc/glvnd/egl_vendor.d:/usr/share/glvnd/egl_vendor.d");
  EXPECT_EQ(env("LD_LIBRARY_PATH"), (d / "lib64").string());
  // OpenCL: a private vendors folder with an .icd naming the library by its path, beside the
  // machine's own .icd files.
  const fs::path vendors = env("OCL_ICD_VENDORS");
  ASSERT_TRUE(fs::is_directory(vendors)) << vendors;
  EXPECT_EQ(vendors.parent_path(), root_ / "tmp");
  std::ifstream icd(vendors / "libnvidia-opencl.so.1.icd");
  std::string line;
  ASSERT_TRUE(std::getline(icd, line));
  EXPECT_EQ(line, (d / "lib64/libnvidia-opencl.so.1").string());
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/etc/OpenCL/vendors", ec)) {
    if (entry.path().extension() == ".icd") {
      EXPECT_TRUE(fs::exists(vendors / entry.path().filename())) << entry.path();
    }
  }

  // The same folder again (as the re-executed process does) changes nothing.
  const std::string vulkan = env("VK_ADD_DRIVER_FILES"), library_path = env("LD_LIBRARY_PATH"),
                    egl = env("__EGL_VENDOR_LIBRARY_DIRS"), opencl = env("OCL_ICD_VENDORS");
  EXPECT_FALSE(apply_driver_dirs({d.string()}));
  EXPECT_EQ(env("VK_ADD_DRIVER_FILES"), vulkan);
  EXPECT_EQ(env("LD_LIBRARY_PATH"), library_path);
  EXPECT_EQ(env("__EGL_VENDOR_LIBRARY_DIRS"), egl);
  EXPECT_EQ(env("OCL_ICD_VENDORS"), opencl);
}

TEST_F(DriverDir, KeepsWhatTheUserSetAndAddsWhereTheLoaderStillReads) {
  const fs::path d = nvidia_like();
  // VK_DRIVER_FILES makes the loader ignore VK_ADD_DRIVER_FILES: the driver goes into it.
  setenv("VK_DRIVER_FILES", "/opt/mine.json", 1);
  setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/opt/egl.json", 1);
  setenv("LD_LIBRARY_PATH", "/opt/lib", 1);
  apply_driver_dirs({d.string()});
  EXPECT_EQ(env("VK_DRIVER_FILES"),
            "/opt/mine.json:" + (d / "share/vulkan/icd.d/nvidia_icd.json").string());
  EXPECT_EQ(env("VK_ADD_DRIVER_FILES"), "");
  EXPECT_EQ(env("__EGL_VENDOR_LIBRARY_FILENAMES"),
            (d / "share/glvnd/egl_vendor.d/10_nvidia.json").string() + ":/opt/egl.json");
  EXPECT_EQ(env("__EGL_VENDOR_LIBRARY_DIRS"), "");
  EXPECT_EQ(env("LD_LIBRARY_PATH"), "/opt/lib:" + (d / "lib64").string());

  const std::vector<DriverFile> vulkan = driver_files("Vulkan");
  ASSERT_EQ(vulkan.size(), 2u);
  EXPECT_EQ(vulkan[0].path, "/opt/mine.json");
  EXPECT_EQ(vulkan[0].library, "(unreadable)");
  EXPECT_EQ(vulkan[0].from, "VK_DRIVER_FILES");
  EXPECT_EQ(vulkan[1].library, "libGLX_nvidia.so.0");
  const std::vector<DriverFile> egl = driver_files("OpenGL (EGL)");
  ASSERT_EQ(egl.size(), 2u);
  EXPECT_EQ(egl[0].library, "libEGL_nvidia.so.0");
  EXPECT_EQ(egl[0].from, "__EGL_VENDOR_LIBRARY_FILENAMES");
}

// A driver the loaders already read (here: NVIDIA's manifests in the standard folders too, as on
// the H200) is not added again: the loader would enumerate its devices twice.
TEST_F(DriverDir, ADriverTheLoadersAlreadyReadIsNotAddedAgain) {
  write(root_ / "system/vulkan/icd.d/nvidia_icd.json", manifest("libGLX_nvidia.so.0"));
  write(root_ / "system/glvnd/egl_vendor.d/10_nvidia.json", manifest("libEGL_nvidia.so.0"));
  setenv("XDG_DATA_DIRS", (root_ / "system").c_str(), 1);
  setenv("__EGL_VENDOR_LIBRARY_DIRS", (root_ / "system/glvnd/egl_vendor.d").c_str(), 1);
  const fs::path d = nvidia_like();
  apply_driver_dirs({d.string()});
  EXPECT_EQ(env("VK_ADD_DRIVER_FILES"), "");
  EXPECT_EQ(env("__EGL_VENDOR_LIBRARY_DIRS"), (root_ / "system/glvnd/egl_vendor.d").string());
  // Its libraries' folder and its OpenCL library, which no loader reads yet, still count.
  EXPECT_EQ(env("LD_LIBRARY_PATH"), (d / "lib64").string());
  EXPECT_TRUE(fs::exists(fs::path(env("OCL_ICD_VENDORS")) / "libnvidia-opencl.so.1.icd"));
}

TEST_F(DriverDir, AFolderOfIcdFilesIsReadAsTheLoaderReadsIt) {
  write(root_ / "vendors/OpenCL/vendors/acme.icd", "/opt/acme/libacmecl.so\n");
  apply_driver_dirs({(root_ / "vendors").string()});
  bool found = false;
  for (const DriverFile& f : driver_files("OpenCL")) {
    EXPECT_EQ(f.from, "OCL_ICD_VENDORS");
    if (fs::path(f.path).filename() == "acme.icd") {
      found = true;
      EXPECT_EQ(f.library, "/opt/acme/libacmecl.so");
    }
  }
  EXPECT_TRUE(found);
  EXPECT_EQ(env("LD_LIBRARY_PATH"), "");  // no shared library in that folder
}

TEST_F(DriverDir, RefusesWhatIsNoDriverFolder) {
  const auto refused = [&](const std::string& dir, const std::string& why) {
    try {
      apply_driver_dirs({dir});
      ADD_FAILURE() << dir << " accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find("--driver-dir '" + dir + "': "), 0u) << message;
      EXPECT_NE(message.find(why), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  refused((root_ / "absent").string(), "not a folder");
  write(root_ / "file", "");
  refused((root_ / "file").string(), "not a folder");
  write(root_ / "empty/readme.txt", "");
  refused((root_ / "empty").string(), "holds no Vulkan ICD manifest");
  // glibc alone is no driver, and is never taken.
  write(root_ / "glibc-only/libc.so.6", "");
  refused((root_ / "glibc-only").string(), "holds no Vulkan ICD manifest");
  EXPECT_EQ(env("LD_LIBRARY_PATH"), "");
}

}  // namespace
}  // namespace nurbs::test
