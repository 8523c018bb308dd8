// vk-compute's evaluation pass: one work-group per tile of the scene's tile table, every surface
// in one dispatch. Tensor grids (cpu-tensor's separation, strategies/cpu_tensor/): the u
// contraction of the (p+1) control-point rows of each of the tile's rows into the homogeneous
// iso-curve at that u (only the control points its columns need), held in shared memory; then per
// sample the (q+1)-term v contraction and the divide. Explicit lists: per sample the direct
// (p+1)(q+1) sum. The includer defines TC_F64.
#include "layout.glsl"

// The degrees, where every surface of the scene has the same pair (vk_compute.cpp picks the
// pipeline at prepare): constant loop bounds the compiler unrolls, the basis values in registers.
// On lavapipe, patch144 at 1024^2 took 50 ms with the degrees read from the surface table and
// 33 ms with them constant. 0: each surface's own, from the table (scenes of mixed degrees).
layout(constant_id = 2) const int kDegreeU = 0;
layout(constant_id = 3) const int kDegreeV = 0;
int degree_u(int base) { return kDegreeU > 0 ? kDegreeU : surfaces[base + TC_S_DEGREE_U]; }
int degree_v(int base) { return kDegreeV > 0 ? kDegreeV : surfaces[base + TC_S_DEGREE_V]; }

shared TC_VEC4 curve[kTile];
shared TC_VEC4 curve_du[kTile];

bool normalize_if_resolved(TC_VEC3 n, TC_VEC3 a, TC_VEC3 b, out TC_VEC3 unit) {
  // reference/nurbs_math.h detail::normalize_if_resolved, in the pass's precision
  const TB_REAL scale = length(a) + length(b);
  const TB_REAL len = length(n);
  unit = TC_VEC3(0);
  if (!(len > TB_REAL(1024) * TC_EPSILON * scale * scale) || isinf(len) || isnan(len))
    return false;
  unit = n / len;
  return true;
}

// The unit normal from the homogeneous sums A and its derivatives (the quotient rule, A4.4 to
// first order in each direction): Su x Sv, or where a tangent vanishes the limit along the
// surface -- the first two stages of the reference's surface_normal, line by line. Its third
// stage (a neighbour nudged toward the domain centre) is not done here: the zero vector is
// returned and the host finishes those samples with the reference's code (vk_compute.cpp).
TC_VEC3 normal_from_sums(int s, TC_VEC4 a, TC_VEC4 au, TC_VEC4 av, TC_VEC4 auv, TB_REAL u,
                         TB_REAL v) {
  const TC_VEC3 point = a.xyz / a.w;
  const TC_VEC3 su = (au.xyz - au.w * point) / a.w;
  const TC_VEC3 sv = (av.xyz - av.w * point) / a.w;
  const TC_VEC3 suv = (auv.xyz - auv.w * point - au.w * sv - av.w * su) / a.w;
  TC_VEC3 n;
  if (normalize_if_resolved(cross(su, sv), su, sv, n)) return n;
  const int base = TC_SURFACE_INTS * s;
  if (length(su) <= length(sv)) {
    const int k = surfaces[base + TC_S_KNOTS_V];
    const TB_REAL v0 = tb_knots[k + surfaces[base + TC_S_DEGREE_V]];
    const TB_REAL v1 = tb_knots[k + surfaces[base + TC_S_COUNT_V]];
    const TB_REAL side = (v - v0) <= (v1 - v) ? TB_REAL(1) : TB_REAL(-1);
    normalize_if_resolved(side * cross(suv, sv), suv, sv, n);
  } else {
    const int k = surfaces[base + TC_S_KNOTS_U];
    const TB_REAL u0 = tb_knots[k + surfaces[base + TC_S_DEGREE_U]];
    const TB_REAL u1 = tb_knots[k + surfaces[base + TC_S_COUNT_U]];
    const TB_REAL side = (u - u0) <= (u1 - u) ? TB_REAL(1) : TB_REAL(-1);
    normalize_if_resolved(side * cross(su, suv), su, suv, n);
  }
  return n;
}

void store(int k, int s, TC_VEC4 a, TC_VEC4 au, TC_VEC4 av, TC_VEC4 auv, int gu, int gv) {
  const TC_VEC3 p = a.xyz / a.w;
  positions[3 * k] = p.x;
  positions[3 * k + 1] = p.y;
  positions[3 * k + 2] = p.z;
  if (launch.normals == 0) return;
  const TC_VEC3 n = normal_from_sums(s, a, au, av, auv, params[gu], params[gv]);
  normals[3 * k] = n.x;
  normals[3 * k + 1] = n.y;
  normals[3 * k + 2] = n.z;
}

// Function-major (value j of every parameter together): neighbouring invocations, neighbouring
// samples, read neighbouring values.
TB_REAL basis_at(int g, int j) { return basis_values[j * launch.params + g]; }
TB_REAL derivative_at(int g, int j) {
  return basis_values[(TB_MAX_ORDER + j) * launch.params + g];
}

// Explicit lists: sample k of surface s, the (p+1)(q+1) sum (rows first: each row's v sums are
// shared by the four sums).
void evaluate_paired(int s, int k) {
  const int base = TC_SURFACE_INTS * s;
  const int gu = surfaces[base + TC_S_U_PARAMS] + k, gv = surfaces[base + TC_S_V_PARAMS] + k;
  const int p = degree_u(base), q = degree_v(base);
  const int count_v = surfaces[base + TC_S_COUNT_V];
  const int first_u = spans[gu] - p, first_v = spans[gv] - q;
  const bool d = launch.normals != 0;
  TC_VEC4 a = TC_VEC4(0), au = TC_VEC4(0), av = TC_VEC4(0), auv = TC_VEC4(0);
  for (int i = 0; i <= p; ++i) {
    const int row = surfaces[base + TC_S_NET] + (first_u + i) * count_v + first_v;
    TC_VEC4 r = TC_VEC4(0), rv = TC_VEC4(0);
    for (int j = 0; j <= q; ++j) {
      const TC_VEC4 point = nets[row + j];
      r += basis_at(gv, j) * point;
      if (d) rv += derivative_at(gv, j) * point;
    }
    a += basis_at(gu, i) * r;
    if (d) {
      au += derivative_at(gu, i) * r;
      av += basis_at(gu, i) * rv;
      auv += derivative_at(gu, i) * rv;
    }
  }
  store(surfaces[base + TC_S_OUT] + k, s, a, au, av, auv, gu, gv);
}

void main() {
  const int t = int(gl_WorkGroupID.y) * launch.tiles_x + int(gl_WorkGroupID.x);
  // uniform across the work-group: the barrier below stays in uniform control flow
  if (t >= launch.count) return;
  const int lid = int(gl_LocalInvocationID.x), size = int(gl_WorkGroupSize.x);
  const int tb = TC_TILE_INTS * t;
  const int s = tiles[tb + TC_T_SURFACE];
  const int b0 = tiles[tb + TC_T_B0], cols = tiles[tb + TC_T_COLS];
  if (launch.paired != 0) {
    for (int k = lid; k < cols; k += size) evaluate_paired(s, b0 + k);
    return;
  }
  const int base = TC_SURFACE_INTS * s;
  const int a0 = tiles[tb + TC_T_A0], rows = tiles[tb + TC_T_ROWS];
  const int first_v = tiles[tb + TC_T_FIRST_V], width = tiles[tb + TC_T_WIDTH];
  const int p = degree_u(base), q = degree_v(base);
  const int count_v = surfaces[base + TC_S_COUNT_V], net = surfaces[base + TC_S_NET];
  const int u_params = surfaces[base + TC_S_U_PARAMS], v_params = surfaces[base + TC_S_V_PARAMS];
  const bool d = launch.normals != 0;
  // u contraction: the iso-curve of each row, control points first_v .. first_v + width - 1
  for (int k = lid; k < rows * width; k += size) {
    const int r = k / width, j = k - r * width;
    const int gu = u_params + a0 + r;
    const int row = net + (spans[gu] - p) * count_v + first_v + j;
    TC_VEC4 c = TC_VEC4(0), cu = TC_VEC4(0);
    for (int i = 0; i <= p; ++i) {
      const TC_VEC4 point = nets[row + i * count_v];
      c += basis_at(gu, i) * point;
      if (d) cu += derivative_at(gu, i) * point;
    }
    curve[k] = c;
    curve_du[k] = cu;
  }
  barrier();
  // v contraction and divide: columns across the invocations, each column's span and basis read
  // once for all the rows it does (no division per sample); a tile narrower than the work-group
  // has `stripes` rows in flight, each invocation every stripes-th row of its column.
  const int nv = surfaces[base + TC_S_NV], out_base = surfaces[base + TC_S_OUT];
  const bool wide = cols >= size;
  const int stripes = wide ? 1 : size / cols;
  const int r0 = wide ? 0 : lid / cols;
  for (int c = wide ? lid : lid - r0 * cols; c < cols && r0 < stripes; c += wide ? size : cols) {
    const int b = b0 + c, gv = v_params + b;
    const int first = spans[gv] - q - first_v;
    TB_REAL nb[TB_MAX_ORDER];
    TB_REAL db[TB_MAX_ORDER];
    for (int l = 0; l <= q; ++l) {
      nb[l] = basis_at(gv, l);
      db[l] = d ? derivative_at(gv, l) : TB_REAL(0);
    }
    for (int r = r0; r < rows; r += stripes) {
      const int at = r * width + first;
      TC_VEC4 a = TC_VEC4(0), au = TC_VEC4(0), av = TC_VEC4(0), auv = TC_VEC4(0);
      for (int l = 0; l <= q; ++l) {
        a += nb[l] * curve[at + l];
        if (d) {
          au += nb[l] * curve_du[at + l];
          av += db[l] * curve[at + l];
          auv += db[l] * curve_du[at + l];
        }
      }
      store(out_base + (a0 + r) * nv + b, s, a, au, av, auv, u_params + a0 + r, gv);
    }
  }
}
