// vk-compute's buffers, push constants and specialization constants, shared by its basis and
// evaluation passes (one descriptor set; vk_compute.cpp writes the tables these read). The
// includer defines TC_F64 (0 or 1) first.
#if TC_F64
#define TB_REAL double
#define TC_VEC3 dvec3
#define TC_VEC4 dvec4
#define TC_EPSILON 2.220446049250313e-16LF
#else
#define TB_REAL float
#define TC_VEC3 vec3
#define TC_VEC4 vec4
#define TC_EPSILON 1.1920929e-7
#endif

// From the device's limits (vk_compute.cpp): invocations per work-group, and curve points per
// shared-memory tile.
layout(local_size_x_id = 0) in;
layout(constant_id = 1) const int kTile = 64;

layout(std430, set = 0, binding = 0) readonly buffer Knots { TB_REAL tb_knots[]; };
// Every distinct parameter list of the scene, one after the other.
layout(std430, set = 0, binding = 1) readonly buffer Params { TB_REAL params[]; };
// Per parameter: its knot vector's offset in tb_knots, degree, control points in that direction.
layout(std430, set = 0, binding = 2) readonly buffer ParamAxes { int param_axes[]; };
// The basis pass's output: per parameter its span; TB_STRIDE values per parameter (tensor_basis.h),
// value j of parameter g at j * launch.params + g.
layout(std430, set = 0, binding = 3) buffer Spans { int spans[]; };
layout(std430, set = 0, binding = 4) buffer BasisValues { TB_REAL basis_values[]; };
// Homogeneous control points (wx, wy, wz, w) of every surface, row-major (i * count_v + j).
layout(std430, set = 0, binding = 5) readonly buffer Nets { TC_VEC4 nets[]; };
layout(std430, set = 0, binding = 6) readonly buffer Surfaces { int surfaces[]; };
layout(std430, set = 0, binding = 7) readonly buffer Tiles { int tiles[]; };
layout(std430, set = 0, binding = 8) writeonly buffer Positions { TB_REAL positions[]; };
layout(std430, set = 0, binding = 9) writeonly buffer Normals { TB_REAL normals[]; };

layout(push_constant) uniform Launch {
  int count;    // parameters (basis pass) or tiles (evaluation pass)
  int normals;  // 1: derivatives and normals too
  int paired;   // 1: explicit lists, sample k = (u[k], v[k]); 0: tensor grids
  int tiles_x;  // work-groups along x (a 2D grid where one row would pass the device's limit)
  int params;   // parameters in `params` (both passes: the stride of `basis_values`)
} launch;

#include "tensor_basis.h"
#include "layout.h"
