// vk-compute's basis pass: one invocation per parameter of every distinct parameter list of the
// scene, span and basis functions (and first derivatives for normals) from the knot vectors by
// the single-source tensor_basis.h. The includer defines TC_F64.
#include "layout.glsl"

void main() {
  // a 2D grid of work-groups where one row would pass maxComputeWorkGroupCount[0]
  const int g = (int(gl_WorkGroupID.y) * launch.tiles_x + int(gl_WorkGroupID.x)) *
                    int(gl_WorkGroupSize.x) +
                int(gl_LocalInvocationID.x);
  if (g >= launch.count) return;
  const int knots = param_axes[3 * g], degree = param_axes[3 * g + 1];
  const int count = param_axes[3 * g + 2];
  const TB_REAL u = params[g];
  const int span = tb_find_span(degree, count, knots, u);
  TB_REAL b[TB_MAX_ORDER];
  TB_REAL d[TB_MAX_ORDER];
  tb_basis(span, u, degree, knots, b, d, launch.normals != 0);
  spans[g] = span;
  for (int j = 0; j <= degree; ++j) basis_values[j * launch.params + g] = b[j];
  if (launch.normals != 0)
    for (int j = 0; j <= degree; ++j)
      basis_values[(TB_MAX_ORDER + j) * launch.params + g] = d[j];
}
