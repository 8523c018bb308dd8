// cpu-tensor's kernels built for baseline x86-64 (SSE2), no clones, into
// nurbs::tensor::isa_baseline: what a CPU without AVX2 runs (isa_kernels_test.cpp).
#define NURBSBENCH_NO_TARGET_CLONES 1
#define NURBSBENCH_TENSOR_NAMESPACE isa_baseline
#include "strategies/cpu_tensor/tensor_kernels.cpp"  // NOLINT(bugprone-suspicious-include)
