// The --uv reader (harness/uv_file.h) against uv_test_scene.h's two surfaces: what it accepts is a
// non-empty explicit list whose every (u, v) lies in its surface's domain (never -0) and which
// sample_parameters takes; anything else it refuses with InputError.
#include <bit>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz_check.h"
#include "harness/uv_file.h"
#include "uv_test_scene.h"

namespace nurbs::fuzz {
namespace {

constexpr std::string_view kOrigin = "fuzz-uv.csv";

}  // namespace
}  // namespace nurbs::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace nurbs;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  const Scene& scene = fuzz::uv_test_scene();
  Sampling sampling;
  try {
    sampling = read_uv_stream(in, fuzz::kOrigin, scene);
  } catch (const InputError& e) {
    fuzz::check_error_line(e, fuzz::kOrigin);
    return 0;
  }
  fuzz::check(sampling.mode == SamplingMode::explicit_list, "not an explicit list");
  fuzz::check(sampling.explicit_uv.size() == scene.surfaces.size(), "list per surface missing");
  std::size_t count = 0;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    for (const auto& [u, v] : sampling.explicit_uv[i]) {
      fuzz::check(std::isfinite(u) && std::isfinite(v), "non-finite sample accepted");
      fuzz::check(u >= s.u_min() && u <= s.u_max() && v >= s.v_min() && v <= s.v_max(),
                  "sample outside its surface's domain accepted");
      fuzz::check(!std::signbit(u) || u != 0, "-0 kept for u");
      fuzz::check(!std::signbit(v) || v != 0, "-0 kept for v");
      ++count;
    }
  }
  fuzz::check(count > 0 && count <= kMaxSamplesPerRequest, "sample count out of bounds");
  // Fewer samples than bytes: each sample costs a line of at least "0,0,0".
  fuzz::check(count <= size / 5, "more samples than lines");
  try {
    fuzz::check(total_samples(sample_parameters(scene, sampling)) == count,
                "sample_parameters changed the count");
  } catch (const InputError& e) {
    fuzz::finding("sample_parameters refuses what the reader accepted", e.what());
  }
  return 0;
}
