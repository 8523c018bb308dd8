// The storage buffers of vk-ksquad (003 Fig 8's two-level indirection): the Info-KSQuad table
// (one row per patch) points into the surface table, which points into the surface data. The
// record layouts are written by strategies/vk_ksquad/vk_ksquad.cpp (kSurfaceInts, kPatchInts).
layout(std430, set = 0, binding = 0) readonly buffer Surfaces { int surfaces[]; };
layout(std430, set = 0, binding = 1) readonly buffer Patches { int patches[]; };
layout(std430, set = 0, binding = 2) readonly buffer Constants { float consts[]; };
layout(std430, set = 0, binding = 3) readonly buffer Points { vec4 points[]; };
layout(std430, set = 0, binding = 4) readonly buffer Params { float params[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Positions { float positions[]; };

// surfaces: degree_u, degree_v, count_u, count_v, first point, first u parameter,
//           first v parameter, v parameters (nv), first output sample, 3 x pad
#define SURFACE_INTS 12
// patches: surface, span_u, span_v, u constants, v constants, u_begin, u_count, v_begin, v_count,
//          level_u, level_v, pad
#define PATCH_INTS 12
