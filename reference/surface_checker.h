// The checks shared by validate_surface, validate_trim and the scene reader: each throws a
// ValidationError naming the surface, and takes the field as a path ("knots_u",
// "trim.loops[0].curves[2].knots") so a trim curve's knots are checked by the same code as a
// surface's.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "reference/surface.h"
#include "reference/validation.h"

namespace nurbs {

class SurfaceChecker {
 public:
  SurfaceChecker(const Surface& surface, int surface_index, std::string_view origin)
      : surface_(surface), surface_index_(surface_index), origin_(origin) {}

  [[noreturn]] void fail(std::string field, std::string index, std::string value,
                         std::string rule) const;

  void check_degree(const std::string& field, int degree) const;
  // `count` control points of a direction (or a curve) of degree `degree`: degree+1..max_count.
  // `index` is "" for a count field, kLengthIndex for an array's length.
  void check_count(const std::string& field, const std::string& index, std::int64_t count,
                   int degree, std::int64_t max_count) const;
  // Knot count, finiteness, order, multiplicities, a non-empty domain (docs/design.md §Data model).
  void check_knots(const std::string& field, const std::vector<double>& knots, int degree,
                   int count) const;
  // An array the file gave with more entries than the format allows (checked before allocating).
  void check_at_most(const std::string& field, std::size_t size, std::size_t max,
                     std::string_view what) const;

 private:
  const Surface& surface_;
  int surface_index_;
  std::string_view origin_;
};

// Field paths of a trim's parts, as errors name them: "trim.loops[L]", "trim.loops[L].curves[C]".
std::string trim_loop_path(std::size_t loop);
std::string trim_curve_path(std::size_t loop, std::size_t curve);

}  // namespace nurbs
