// The language shim of the single-source kernel headers: the stair basis
// (strategies/stair_basis/stair_basis.h), direct trimming (strategies/trim_direct/trim_direct.h),
// vk-compute's basis pass (strategies/vk_compute/tensor_basis.h), the T-spline local basis
// (strategies/gl_tspline/local_basis.h) and de Boor (strategies/glsl_deboor/de_boor_source.h).
// Each is written once in the common subset of C++, OpenCL C and GLSL; what differs between the
// three languages in every one of them is named here once, as OpenSubdiv's
// osd/patchBasisCommonTypes.h does for its patch basis. What differs per header (how a buffer is
// reached: a pointer in C++ and OpenCL, a global storage buffer indexed by offset in GLSL) stays
// in that header, spelled with these macros.
//
// How it reaches each language: C++ and glslang (the Vulkan shaders, compiled at build time with
// GL_GOOGLE_include_directive, whose macro glslang defines) include it from the header that uses
// it; kernels compiled at run time (OpenCL C, GL 3.3 GLSL, neither of which has #include) get it
// prepended to the header when the header is embedded (nurbsbench_embed_kernel_header,
// scripts/cmake/embed.cmake). All three preprocessors honour the include guard.
#ifndef NURBSBENCH_KERNEL_LANGUAGE_H
#define NURBSBENCH_KERNEL_LANGUAGE_H

#if defined(__cplusplus)
#define KL_CPP 1
// A function of the header: inline, since C++ headers are included in several translation units.
#define KL_FN inline
// `x` converted to `type` (the header's scalar: float, double, long double).
#define KL_CAST(type, x) static_cast<type>(x)
// Address spaces of pointer parameters (OpenCL's; nothing in C++).
#define KL_GLOBAL
#define KL_LOCAL
// An array the function fills for its caller, of at most `size` elements.
#define KL_ARRAY_OUT(type, name, size) type* name
// A scalar the function returns through a parameter.
#define KL_OUT(type, name) type& name
#elif defined(__OPENCL_VERSION__)
#define KL_OPENCL 1
#define KL_FN
#define KL_CAST(type, x) ((type)(x))
#define KL_GLOBAL __global
#define KL_LOCAL __local
#define KL_ARRAY_OUT(type, name, size) type* name
// (No KL_OUT: OpenCL C has no references, and no header compiled there returns a scalar through
// a parameter.)
#else
#define KL_GLSL 1
#define KL_FN
#define KL_CAST(type, x) type(x)
#define KL_GLOBAL
#define KL_LOCAL
#define KL_ARRAY_OUT(type, name, size) out type name[size]
#define KL_OUT(type, name) out type name
#endif

#endif  // NURBSBENCH_KERNEL_LANGUAGE_H
