// cpu-tensor's kernels built for x86-64-v3 (AVX2 + FMA), no clones, into
// nurbs::tensor::isa_avx2: what a CPU without AVX-512 runs (isa_kernels_test.cpp).
#define NURBSBENCH_NO_TARGET_CLONES 1
#define NURBSBENCH_TENSOR_NAMESPACE isa_avx2
#include "strategies/cpu_tensor/tensor_kernels.cpp"  // NOLINT(bugprone-suspicious-include)
