// cl-stair's classify pass: direct trimming (Schollmeyer & Fröhlich 2009) of the grid samples of
// one trimmed surface, one work-item per sample, by td_classify of
// strategies/trim_direct/trim_direct.h -- the single-source classifier, prepended to this file by
// cl_stair.cpp (TD_REAL is a build option). `params` holds every trimmed surface's grid parameters
// in its trim's local frame (one buffer, one upload); this surface's u values start at u_base, its
// v values at v_base. inside[k] and reads[k] (the cost counter) per sample in SurfaceSamples order
// (a * nv + b).
__kernel void classify_trim(__global const TD_REAL* td_reals, __global const int* td_ints, int base,
                            __global const TD_REAL* params, int u_base, int nu, int v_base, int nv,
                            TD_REAL epsilon, int iterations, int out_base, __global uchar* inside,
                            __global int* reads) {
  const int k = (int)get_global_id(0);
  if (k >= nu * nv) return;
  const int packed = td_classify(td_reals, td_ints, base, params[u_base + k / nv],
                                 params[v_base + k % nv], epsilon, iterations);
  inside[out_base + k] = (uchar)(packed & 1);
  reads[out_base + k] = packed / 2;
}
