// Decomposition of a NURBS surface into rational Bézier patches by knot insertion to full
// multiplicity: Piegl & Tiller, "The NURBS Book" (2nd ed.), A5.6 DecomposeCurve and A5.7
// DecomposeSurface, in homogeneous coordinates (w*x, w*y, w*z, w), templated on the scalar like
// nurbs_math.h. This is the preprocessing of RPNS's baseline (003 §2: "each knot with
// multiplicity lower than the degree ... has to be replicated until it appears p times"), and the
// count of the resulting patches -- one per non-empty (u-span, v-span) pair -- is also RPNS's
// KSQuad count (003 §2). The paper bounds it by (r-2p)(s-2q) with r, s "the number of knots"; a
// domain has count - p = r - 1 - 2p spans, so that bound is one span loose per direction and
// exact with r read as the last knot's index (count + p), reached when no span is empty.
//
// Two generalisations of the book's A5.6, which assumes a clamped knot vector:
// - only the domain [knots[p], knots[count]] is decomposed (an unclamped vector has knots outside
//   it, which belong to no segment);
// - an unclamped start (u_min of multiplicity s < p) is first raised to multiplicity p inside the
//   first segment, by the local part of A5.1 CurveKnotIns; an unclamped end is handled by A5.6
//   itself, which inserts the segment's right knot until it has multiplicity p.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "reference/nurbs_math.h"

namespace nurbs {

// The non-empty knot spans s (knots[s] < knots[s+1]) of the domain, s in [degree, count-1], in
// increasing order: one Bézier segment each.
template <typename T>
std::vector<int> nonempty_spans(int degree, int count, const T* knots) {
  std::vector<int> spans;
  for (int s = degree; s < count; ++s)
    if (knots[s] < knots[s + 1]) spans.push_back(s);
  return spans;
}

// Non-empty spans per direction {u, v}: the decomposition is a grid of u x v Bézier patches.
inline std::array<std::size_t, 2> nonempty_span_counts(const Surface& s) {
  return {nonempty_spans(s.degree_u, s.count_u, s.knots_u.data()).size(),
          nonempty_spans(s.degree_v, s.count_v, s.knots_v.data()).size()};
}

// Patches of the decomposition = RPNS KSQuads: the non-empty (u-span, v-span) pairs. The one place
// both are counted (strategies, the memory table and the tests read it from here).
inline std::size_t ksquad_count(const Surface& s) {
  const std::array<std::size_t, 2> spans = nonempty_span_counts(s);
  return spans[0] * spans[1];
}

// Where a set of curves sharing one knot vector lives: control point i of curve ("lane") l at
// data[i * point_stride + l * lane_stride]. A surface's columns are the lanes of its u-direction
// decomposition, its rows those of its v-direction one (A5.7 runs A5.6 over all of them with one
// set of alphas per knot).
// P is Vec4<T> or const Vec4<T>.
template <typename P>
struct CurveLanes {
  P* data = nullptr;
  std::ptrdiff_t point_stride = 1, lane_stride = 1;
  int lanes = 1;
  P& at(std::ptrdiff_t i, int l) const { return data[i * point_stride + l * lane_stride]; }
};

namespace detail {
// q_k = alpha * q_k + (1 - alpha) * q_{k-1} on every lane (a step of Boehm's knot insertion).
template <typename T>
void blend_lanes(const CurveLanes<Vec4<T>>& out, std::ptrdiff_t k, std::ptrdiff_t k_minus_1,
                 T alpha) {
  const T beta = T(1) - alpha;
  for (int l = 0; l < out.lanes; ++l) {
    Vec4<T>& q = out.at(k, l);
    const Vec4<T>& r = out.at(k_minus_1, l);
    for (int c = 0; c < 4; ++c) q[c] = alpha * q[c] + beta * r[c];
  }
}
template <typename T>
void copy_point(const CurveLanes<Vec4<T>>& out, std::ptrdiff_t to,
                const CurveLanes<const Vec4<T>>& in, std::ptrdiff_t from) {
  for (int l = 0; l < out.lanes; ++l) out.at(to, l) = in.at(from, l);
}
template <typename T>
void copy_point(const CurveLanes<Vec4<T>>& out, std::ptrdiff_t to, std::ptrdiff_t from) {
  for (int l = 0; l < out.lanes; ++l) out.at(to, l) = out.at(from, l);
}
}  // namespace detail

// A5.6 DecomposeCurve over `in.lanes` curves of degree p with `count` control points sharing
// `knots`: writes segment g's p+1 Bézier points of lane l to out.at(g * (p+1) + k, l), k = 0..p,
// for every non-empty span of the domain in order. `in` and `out` must not overlap; out needs
// nonempty_spans(...).size() * (p+1) points per lane. Returns the number of segments.
template <typename T>
int decompose_curves(int degree, int count, const T* knots, const CurveLanes<const Vec4<T>>& in,
                     const CurveLanes<Vec4<T>>& out) {
  const int p = degree;
  const int m = count + p;  // last knot index
  T alphas[kMaxOrder];
  // The first segment starts at the last copy of u_min = knots[p] (a non-empty span follows).
  int a = p;
  while (!(knots[a] < knots[a + 1])) ++a;
  int first_copy = a;
  while (first_copy > 0 && knots[first_copy - 1] == knots[a]) --first_copy;
  const int start_multiplicity = a - first_copy + 1;
  for (int k = 0; k <= p; ++k) detail::copy_point(out, k, in, a - p + k);
  if (start_multiplicity < p) {
    // Unclamped start: insert u_min r = p - s times into the first segment (A5.1 CurveKnotIns
    // with k = a, restricted to the points of span a; its Rw array is the segment's points 0..p-s,
    // and after step j the point p-s-j is final).
    const int s = start_multiplicity, r = p - s;
    for (int j = 1; j <= r; ++j) {
      const int first = a - p + j;
      for (int i = 0; i <= p - j - s; ++i) {
        const T alpha = (knots[a] - knots[first + i]) / (knots[i + a + 1] - knots[first + i]);
        // R_i = alpha R_{i+1} + (1 - alpha) R_i, in place, i ascending (A5.1's order: reads the
        // not-yet-updated R_{i+1}).
        for (int l = 0; l < out.lanes; ++l) {
          Vec4<T>& ri = out.at(i, l);
          const Vec4<T>& rn = out.at(i + 1, l);
          for (int c = 0; c < 4; ++c) ri[c] = alpha * rn[c] + (T(1) - alpha) * ri[c];
        }
      }
    }
    // After the loop the points 0..p-s-1 hold R_0..R_{p-s-1} of the last steps: A5.1 stores
    // Qw[k+r-j-s] = Rw[p-j-s] after step j, i.e. segment point p-s-j = R_{p-s-j} -- which the
    // in-place update above leaves in slot p-s-j, untouched by the later (shorter) steps.
  }

  int segment = 0;
  int b = a + 1;
  for (;;) {
    const std::ptrdiff_t base = static_cast<std::ptrdiff_t>(segment) * (p + 1);
    const int run_start = b;
    while (b < m && knots[b + 1] == knots[b]) ++b;
    const int mult = b - run_start + 1;
    // The segment [knots[a], knots[b]] is the last one when its right knot is u_max.
    const bool last = b >= count;
    if (mult < p) {
      // Insert knots[b] r = p - mult times (A5.6): the alphas depend only on the knots.
      const T numer = knots[b] - knots[a];
      for (int j = p; j > mult; --j) alphas[j - mult - 1] = numer / (knots[a + j] - knots[a]);
      const int r = p - mult;
      for (int j = 1; j <= r; ++j) {
        const int save = r - j, s = mult + j;
        for (int k = p; k >= s; --k)
          detail::blend_lanes(out, base + k, base + k - 1, alphas[k - s]);
        if (!last) detail::copy_point(out, base + (p + 1) + save, base + p);
      }
    }
    ++segment;
    if (last) break;
    // The next segment: its first p - mult points were saved above, the rest are original.
    const std::ptrdiff_t next = static_cast<std::ptrdiff_t>(segment) * (p + 1);
    for (int i = p - mult; i <= p; ++i) detail::copy_point(out, next + i, in, b - p + i);
    a = b;
    b = b + 1;
  }
  return segment;
}

// One surface as rational Bézier patches: patch (g, h) for the g-th non-empty u span and the h-th
// non-empty v span, its (p+1)(q+1) homogeneous points at
// points[((g * segments_v + h) * (p+1) + k) * (q+1) + l].
template <typename T>
struct BezierPatches {
  int degree_u = 0, degree_v = 0;
  int segments_u = 0, segments_v = 0;
  std::vector<int> spans_u, spans_v;  // the knot span of each segment
  std::vector<T> breaks_u, breaks_v;  // segment g covers [breaks_u[g], breaks_u[g+1]]
  std::vector<Vec4<T>> points;

  std::size_t patch_count() const { return static_cast<std::size_t>(segments_u) * segments_v; }
  std::size_t points_per_patch() const {
    return static_cast<std::size_t>(degree_u + 1) * (degree_v + 1);
  }
  const Vec4<T>* patch(int g, int h) const {
    return points.data() + (static_cast<std::size_t>(g) * segments_v + h) * points_per_patch();
  }
};

// Intermediate nets of decompose_surface, kept between calls: a deforming surface is decomposed
// every frame.
template <typename T>
struct DecompositionScratch {
  std::vector<Vec4<T>> by_u;  // after the u direction
  std::vector<Vec4<T>> full;  // after both, as one net with knots of multiplicity p and q
};

// A5.7 DecomposeSurface: A5.6 in u over the count_v columns of the net, then in v over the rows
// of the result, then the patches gathered contiguously.
template <typename T>
void decompose_surface(const SurfaceNet<T>& net, BezierPatches<T>& out,
                       DecompositionScratch<T>& scratch) {
  const int p = net.degree_u, q = net.degree_v;
  out.degree_u = p;
  out.degree_v = q;
  out.spans_u = nonempty_spans(p, net.count_u, net.knots_u.data());
  out.spans_v = nonempty_spans(q, net.count_v, net.knots_v.data());
  out.segments_u = static_cast<int>(out.spans_u.size());
  out.segments_v = static_cast<int>(out.spans_v.size());
  out.breaks_u.clear();
  out.breaks_v.clear();
  for (int s : out.spans_u) out.breaks_u.push_back(net.knots_u[s]);
  out.breaks_u.push_back(net.knots_u[out.spans_u.back() + 1]);
  for (int s : out.spans_v) out.breaks_v.push_back(net.knots_v[s]);
  out.breaks_v.push_back(net.knots_v[out.spans_v.back() + 1]);

  // u direction: rows_u = segments_u * (p+1) rows of count_v points, row-major like the net.
  const std::ptrdiff_t rows_u = static_cast<std::ptrdiff_t>(out.segments_u) * (p + 1);
  const std::ptrdiff_t columns_v = static_cast<std::ptrdiff_t>(out.segments_v) * (q + 1);
  scratch.by_u.resize(static_cast<std::size_t>(rows_u) * net.count_v);
  decompose_curves<T>(p, net.count_u, net.knots_u.data(),
                      {net.homogeneous.data(), net.count_v, 1, net.count_v},
                      {scratch.by_u.data(), net.count_v, 1, net.count_v});

  // v direction: each of the rows_u rows is a curve; the result is rows_u x columns_v.
  std::vector<Vec4<T>>& full = scratch.full;
  full.resize(static_cast<std::size_t>(rows_u * columns_v));
  decompose_curves<T>(q, net.count_v, net.knots_v.data(),
                      {scratch.by_u.data(), 1, net.count_v, static_cast<int>(rows_u)},
                      {full.data(), 1, columns_v, static_cast<int>(rows_u)});

  // Gather each patch's (p+1)(q+1) points contiguously.
  out.points.resize(out.patch_count() * out.points_per_patch());
  Vec4<T>* dst = out.points.data();
  for (int g = 0; g < out.segments_u; ++g)
    for (int h = 0; h < out.segments_v; ++h)
      for (int k = 0; k <= p; ++k)
        for (int l = 0; l <= q; ++l)
          *dst++ = full[static_cast<std::size_t>((g * (p + 1) + k) * columns_v + h * (q + 1) + l)];
}

// Convenience for tests and one-off callers.
template <typename T>
BezierPatches<T> decompose_surface(const SurfaceNet<T>& net) {
  BezierPatches<T> out;
  DecompositionScratch<T> scratch;
  decompose_surface(net, out, scratch);
  return out;
}
}  // namespace nurbs
