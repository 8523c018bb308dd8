// tensor_kernels.cpp again, into nurbs::tensor::no_simd, compiled without vectorisation (see
// CMakeLists.txt): the baseline that isolates SIMD's share of cpu-tensor's speed.
#define NURBSBENCH_TENSOR_NO_SIMD 1
#include "strategies/cpu_tensor/tensor_kernels.cpp"  // NOLINT(bugprone-suspicious-include)
