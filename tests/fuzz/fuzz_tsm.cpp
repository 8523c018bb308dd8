// The Rhino #TS0200 reader (scenes/tsm/tsm_reader.h): what it accepts is a T-mesh that passes
// validate_tmesh, and whose inferred T-spline either passes validate_tspline or is refused with
// InputError; anything else it refuses with one clean InputError line naming the file.
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.h"
#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "scenes/tsm/tsm_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace nurbs;
  const std::string origin = "fuzz.tsm";
  TMesh mesh;
  try {
    mesh = parse_tsm(std::string_view(reinterpret_cast<const char*>(data), size), origin);
  } catch (const InputError& e) {
    fuzz::check_error_line(e, origin);
    return 0;
  }
  try {
    validate_tmesh(mesh, origin);
  } catch (const InputError& e) {
    fuzz::finding("an accepted mesh fails validate_tmesh", e.what());
  }
  try {
    const TSplineSurface surface = infer_tspline(mesh, origin);
    validate_tspline(surface, origin);
  } catch (const InputError& e) {
    fuzz::check_error_line(e, origin);
  }
  return 0;
}
