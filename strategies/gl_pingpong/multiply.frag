#version 330 core
// 000 §2.2's multiply pass: "multiplies all the four channels of the control point array
// simultaneously with the basis function values". Texel (j, row) = N_{s-p+j}(u_row) * P_{s-p+j},
// P homogeneous (w x, w y, w z, w), over a width-k array (the basis texture's pad column k is not
// drawn). The curve path is unpacked only: the §2.3 packing would need this pass to unpack four
// parameters per texel, the cost the paper names.
uniform sampler2D basis;    // final order's basis, one row per parameter (basis_order.frag)
uniform sampler2D control;  // width k: the row's k control points, gathered on the CPU (§2.2)
out vec4 result;
void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  result = texelFetch(basis, at, 0).r * texelFetch(control, at, 0);
}
