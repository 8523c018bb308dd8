// The tables vk-compute's host code writes and its shaders read, in the common subset of C++ and
// GLSL (int offsets into int buffers).
#if defined(__cplusplus)
#pragma once
#endif

// Per surface (int[TC_SURFACE_INTS] in `surfaces`).
#define TC_S_NET 0      // first control point in `nets`
#define TC_S_COUNT_U 1  // control points along u
#define TC_S_COUNT_V 2  // along v
#define TC_S_DEGREE_U 3
#define TC_S_DEGREE_V 4
#define TC_S_U_PARAMS 5  // the parameter index (in `params`) of its first u sample
#define TC_S_V_PARAMS 6  // of its first v sample
#define TC_S_NV 7        // v samples (tensor grids; a row's stride)
#define TC_S_OUT 8       // its first sample in the outputs
#define TC_S_KNOTS_U 9   // offset of its u knots in `tb_knots`
#define TC_S_KNOTS_V 10
#define TC_SURFACE_INTS 12

// Per tile = one work-group (int[TC_TILE_INTS] in `tiles`). Tensor grids: rows a0 .. a0+rows-1,
// columns b0 .. b0+cols-1 of one surface; its iso-curves hold the control points first_v ..
// first_v+width-1 (in shared memory, width per row). Explicit lists: samples b0 .. b0+cols-1.
#define TC_T_SURFACE 0
#define TC_T_A0 1
#define TC_T_ROWS 2
#define TC_T_B0 3
#define TC_T_COLS 4
#define TC_T_FIRST_V 5
#define TC_T_WIDTH 6
#define TC_TILE_INTS 8
