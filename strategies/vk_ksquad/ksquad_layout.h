// The host side of ksquad_tables.glsl: record layouts of the tables every vk-ksquad mapping
// shares (and vk-bezier, which draws through the same control stage), the push constants, and the
// host copies of the tables the mappings read back against.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace nurbs::vk_ksquad {

inline constexpr int kSurfaceInts = 16;                    // SURFACE_INTS
inline constexpr int kPatchInts = 24;                      // PATCH_INTS
inline constexpr int kPatchLevelU = 9, kPatchLevelV = 10;  // a patch row's tessellation levels
inline constexpr int kPatchPiece = 11;                     // adaptive: the piece of its KSQuad
inline constexpr int kSlotFloats = 5;                      // SLOT_FLOATS
inline constexpr int kCornerInts = 8;                      // CORNER_INTS

// ksquad_tables.glsl: Mode (push constants).
struct ModeConstants {
  float view_projection[16];
  float viewport[2];
  float mu;
  std::int32_t adaptive, max_level, region, normals, patch_base, span_grid, pieces;
  float epsilon, eta;
  std::int32_t nonuniform;
  std::int32_t eq3_literal;
};
static_assert(sizeof(ModeConstants) == 120);

// ksquad_nonuniform.glsl: the nonuniform mapping's geometry stage subdivides a KSDie at most
// kNuDepth times (a kNuLattice^2 lattice), writes kNuKsdieInts per KSDie and kNuVertexFloats per
// emitted vertex slot.
inline constexpr int kNuDepth = 2;
inline constexpr int kNuLattice = (1 << kNuDepth) + 1;
inline constexpr int kNuKsdieInts = 4;
inline constexpr int kNuVertexFloats = 8;
// status of a KSDie record
inline constexpr int kKsdieEmitted = 1, kKsdieFrustumCulled = 2, kKsdieBackCulled = 3;
// the surface table's row: the mask of the domain sides shared with a surface that is not a
// friend (003 §3.1's boundary-region test), the row's first pad int
inline constexpr int kSurfaceFriendless = 9;
// the surface table's row: the factor of its μ, ε, η (float bits; 1 unless vk-thresholds=surface)
inline constexpr int kSurfaceThresholdScale = 10;

// Host copies of the surface table, the Info-KSQuad table and the stair constants.
struct HostTables {
  std::vector<int> surfaces, patches;
  std::vector<float> constants;
  std::size_t patch_count() const { return patches.size() / kPatchInts; }
};

}  // namespace nurbs::vk_ksquad
