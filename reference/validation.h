// Structural rules every surface must satisfy before anything evaluates it (docs/design.md §Data
// model). Checked once, at load/construct time; a violation is a typed error naming where the
// surface came from, which surface, which field, which index and which value.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "reference/surface.h"

namespace nurbs {

inline constexpr int kMaxDegree = 15;
// Bounds that keep an absurd file from making us allocate: checked before any allocation.
inline constexpr std::int64_t kMaxCountPerDirection = 1 << 20;
inline constexpr std::int64_t kMaxControlPointsPerSurface = 1 << 24;
inline constexpr std::int64_t kMaxSurfacesPerScene = 1 << 20;

// Bad input (a scene file, a scene name, a sampling): the CLI turns it into exit code 2 and one
// line on stderr. what() is that line.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One line: "<origin>: surface '<name>' (#<i>): <field>[<index>] = <value>: <rule>"; a wrong
// array length reads "<field> length = <n>: <rule>".
inline constexpr const char* kLengthIndex = "length";
class ValidationError : public InputError {
 public:
  ValidationError(std::string origin, std::string surface, int surface_index, std::string field,
                  std::string index, std::string value, std::string rule);

  const std::string& origin() const { return origin_; }
  const std::string& surface() const { return surface_; }
  int surface_index() const { return surface_index_; }
  const std::string& field() const { return field_; }
  const std::string& index() const { return index_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }

 private:
  std::string origin_, surface_;
  int surface_index_;
  std::string field_, index_, value_, rule_;
};

// Formats a double the way error messages and files show it: shortest round-trip form.
std::string format_number(double value);

// Throws ValidationError for the first violated rule. `origin` is the file path or
// "built-in scene NAME".
void validate_surface(const Surface& surface, int surface_index, std::string_view origin);
// The degree and count rules alone: a loader checks them before it allocates anything.
void validate_surface_sizes(const Surface& surface, int surface_index, std::string_view origin);
void validate_scene(const Scene& scene, std::string_view origin);
// The trim rules of nurbs-scene/2 (reference/trim.h): rule, tolerance, finite values, degrees
// 1..15, knot counts and order, positive weights, bounded counts, each loop closed within the
// tolerance and every curve inside the surface's domain within it. Errors name the loop and curve
// in the field: "trim.loops[L].curves[C].knots[K] = ...". validate_surface calls it.
void validate_trim(const Surface& surface, int surface_index, std::string_view origin);

}  // namespace nurbs
