// The stair basis (003 §3.2) in GLSL: mirrors strategies/cl_stair/stair_basis.h (stair_basis)
// line by line; the derivation and why the paper's printed closed form is not used beyond
// degree 3 are there. The per-span constants (StairConstants<float>, computed once per KSQuad
// direction on the host by the tested C++ stair_constants) are read from the `consts` buffer at
// `c`: knots[18] at c, r[9][9] at c + 18, column A[10] at c + 99, diagonal B[10] at c + 109.
#define MAX_DEG 9  // kStairMaxDegree
#define MAX_ORDER (MAX_DEG + 1)
#define C_KNOT(c, t) consts[(c) + (t)]
#define C_R(c, s, t) consts[(c) + 18 + (s) * MAX_DEG + (t)]
#define C_COLUMN(c, m) consts[(c) + 99 + (m)]
#define C_DIAGONAL(c, m) consts[(c) + 109 + (m)]

// stair_basis.h: stair_basis. basis[j] = N_{i-p+j,p}(u), j = 0..p; knot_degree: the degree the
// constants were built for (GLSL has no default arguments: pass `degree`).
void stair_basis(int c, int degree, float u, out float basis[MAX_ORDER], int knot_degree) {
  const int p = degree;
  const int o = knot_degree;
  float dl[MAX_ORDER], dr[MAX_ORDER];  // u - x_{i-s}, x_{i+1+t} - u
  for (int s = 0; s < p; ++s) {
    dl[s] = u - C_KNOT(c, o - 1 - s);
    dr[s] = C_KNOT(c, o + s) - u;
  }
  float col[MAX_ORDER], diag[MAX_ORDER];
  col[0] = 1.0;
  diag[0] = 1.0;
  float pow_l = 1.0, pow_r = 1.0;
  for (int m = 1; m <= p; ++m) {
    pow_l *= dl[0];
    pow_r *= dr[0];
    col[m] = pow_l * C_COLUMN(c, m);
    diag[m] = pow_r * C_DIAGONAL(c, m);
  }
  basis[p] = col[p];
  basis[0] = diag[p];
  for (int k = 1; k < p; ++k) {
    const int w = p - k;
    float t[MAX_DEG];
    float sum = 0.0;
    for (int r = 0; r < k; ++r) {
      for (int l = 0; l < w; ++l) {
        const float from_above =
            r > 0 ? t[l] * (dr[w - l] * C_R(c, k - r, w - l)) : (l == 0 ? 1.0 : 0.0);
        const float from_left = l == 0 ? 0.0 : t[l - 1] * (dl[k - r] * C_R(c, k - r, w - l));
        t[l] = from_above + from_left;
      }
      sum += t[w - 1] * (dl[k - r] * C_R(c, k - r, 0)) * diag[k - r];
    }
    for (int l = 0; l < w; ++l) sum += t[l] * (dr[w - l] * C_R(c, 0, w - l)) * col[w - l];
    basis[p - k] = sum;
  }
}

// stair_basis.h: stair_derivative. derivative[j] = d/du N_{i-p+j,p}(u), j = 0..p.
void stair_derivative(int c, int degree, float u, out float derivative[MAX_ORDER]) {
  const int p = degree;
  float lower[MAX_ORDER];
  stair_basis(c, p - 1, u, lower, p);
  for (int j = 0; j <= p; ++j) {
    const float left = j >= 1 ? lower[j - 1] * C_R(c, p - j, j - 1) : 0.0;
    const float right = j <= p - 1 ? lower[j] * C_R(c, p - j - 1, j) : 0.0;
    derivative[j] = float(p) * (left - right);
  }
}
