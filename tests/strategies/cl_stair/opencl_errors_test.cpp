// The failure paths of the shared OpenCL plumbing, as a user meets them: no platform is a result
// ("unavailable"), a kernel that does not compile is an error carrying the compiler's build log.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "strategies/opencl/cl_device.h"

namespace nurbs {
namespace {

TEST(OpenCl, BuildErrorCarriesTheBuildLog) {
  const opencl::Context context(opencl::kPreferGpu);
  try {
    context.build("__kernel void broken(__global float* x) { x[0] = undeclared_name; }", "");
    FAIL() << "a kernel with an undeclared identifier built";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("undeclared_name"), std::string::npos) << message;
  }
}

TEST(OpenCl, NoPlatformIsUnavailableNotACrash) {
  // The ICD loader finds no vendor file: every OpenCL strategy must list as unavailable.
  const std::string command = std::string("OCL_ICD_VENDORS=/nonexistent-nurbsbench-icd \"") +
                              NURBSBENCH_CLI + "\" list --json 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  EXPECT_EQ(::pclose(pipe), 0) << output;
  const auto at = output.find("\"name\": \"cl-stair\"");
  ASSERT_NE(at, std::string::npos) << output;
  const std::string entry = output.substr(at > 400 ? at - 400 : 0, 800);
  EXPECT_NE(entry.find("no OpenCL platform"), std::string::npos) << entry;
}

}  // namespace
}  // namespace nurbs
