#version 330 core
// 000 §2.2: the product array "is then reduced along the width direction to its per-row sum".
// One reduction pass: output texel (x, row) is the sum of input texels group*x .. group*x +
// group - 1 of the row (those inside `width`). The paper does not say how the reduction is done;
// curve_eval.cpp chooses the group size (2: log2 k ping-pong passes of pairwise sums, the usual
// GPU reduction of the paper's time; k: one pass).
uniform sampler2D partial;  // the previous stage, `width` texels per row
uniform int width;
uniform int group;
out vec4 result;
void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  int first = at.x * group;
  vec4 sum = vec4(0.0);
  for (int t = 0; t < group && first + t < width; ++t)
    sum += texelFetch(partial, ivec2(first + t, at.y), 0);
  result = sum;
}
