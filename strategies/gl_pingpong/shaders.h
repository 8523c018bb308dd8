// gl-pingpong's shaders, embedded at build time (CMakeLists.txt, nurbsbench_embed): declared once
// for the surface path (basis_passes.cpp) and the curve path (curve_eval.cpp).
#pragma once

#include <string_view>

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
extern const std::string_view gl_pingpong_basis_order_frag;
extern const std::string_view gl_pingpong_accumulate_frag;
extern const std::string_view gl_pingpong_divide_frag;
extern const std::string_view gl_pingpong_multiply_frag;
extern const std::string_view gl_pingpong_reduce_frag;
}  // namespace nurbs::embedded
