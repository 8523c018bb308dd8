// The exact part of trimming: where the trim loops cross the line v = const, computed on the
// curves themselves. Each trim curve is decomposed into rational Bézier pieces (The NURBS Book A5.6
// in homogeneous 2D, shared with the surface decomposition); on each piece the roots of
// g(t) = w(t)·(v(t) − v) = Σ B_i(t)·(w_i·v_i − v·w_i) are isolated by Bernstein subdivision
// (Descartes' rule of signs holds for Bernstein coefficients: no sign variation, no root; one
// variation, exactly one root) and refined by bisection in the scalar T. Templated on T so the
// reference runs it in long double and a double evaluator (cpu-coxdeboor) runs the same code.
//
// Counting rule (even-odd with a half-open convention, which makes tangencies and vertices on the
// line exact): a point of a loop is "above" when g >= 0. Along every loop the above/below state is
// tracked: at each piece's ends (from its end coefficients), between consecutive roots (from g at
// the midpoint) and across the junction to the next piece; every change of state is an event at
// the u where it happens. A sample (u, v) is inside when an odd number of events lie at u' > u.
// A tangency gives two events at the same u (no parity change); a piece lying on the line is
// "above" throughout, so the line is crossed once where the loop arrives from below or leaves
// downwards. Consecutive pieces that do not meet exactly (loops are closed within
// Trim::tolerance) are joined by the straight segment between their ends: a junction whose two
// states differ gives one event on that segment, so every loop is exactly closed for counting.
//
// A fast classifier (cpu-tensor) runs the same counting on a subset of the pieces: a line outside
// a piece's event-free bounds (event_free_outside) gets no event from it, so an index over those
// bounds lets a row visit only the pieces that can cross it; and it may refine roots by
// safeguarded Newton instead of bisection (RootRefinement), the same root in a few steps.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "reference/bezier_decomposition.h"
#include "reference/nurbs_math.h"
#include "reference/trim.h"

namespace nurbs {

// One rational Bézier piece of a trim curve: homogeneous points (w·u, w·v, w).
template <typename T>
struct TrimPiece {
  int degree = 0;
  std::array<std::array<T, 3>, kMaxOrder> h{};
};

// Every loop of a trim as pieces in loop order; consecutive pieces (and the last with the first)
// meet within the trim's tolerance.
template <typename T>
struct TrimPieces {
  std::vector<std::vector<TrimPiece<T>>> loops;
};

// How a root isolated on (0, 1) is refined: bisection (the reference: one bit per step, no
// derivative to trust) or Newton kept inside the shrinking sign-change bracket (a double
// classifier's fast path: quadratic once near the root, bisection where a step would leave it;
// a piece crossing the line once, ends on either side, is then one event without probing).
enum class RootRefinement { bisection, newton };

namespace trim_detail {

// The helpers below take `Capacity`, the most coefficients they hold (n < Capacity): kMaxOrder
// for the pieces and their line polynomials; direct trimming's extrema (the derivative numerator
// x'w - xw' of a degree-15 piece has degree 29) isolate roots with 2 * kMaxDegree.

// Bernstein coefficients c[0..n] evaluated at s (de Casteljau; stable for s in [0, 1]).
template <typename T, int Capacity = kMaxOrder>
T bernstein_value(const T* c, int n, T s) {
  T work[Capacity] = {};
  for (int i = 0; i <= n && i < Capacity; ++i) work[i] = c[i];
  for (int r = 1; r <= n; ++r)
    for (int i = 0; i <= n - r; ++i) work[i] = (T(1) - s) * work[i] + s * work[i + 1];
  return work[0];
}

// The coefficients of the halves [0, 1/2] and [1/2, 1]; left[n] == right[0] == value at 1/2.
template <typename T, int Capacity = kMaxOrder>
void bernstein_halves(const T* c, int n, T* left, T* right) {
  T work[Capacity] = {};
  for (int i = 0; i <= n && i < Capacity; ++i) work[i] = c[i];
  left[0] = work[0];
  right[n] = work[n];
  for (int r = 1; r <= n; ++r) {
    for (int i = 0; i <= n - r; ++i) work[i] = (work[i] + work[i + 1]) / T(2);
    left[r] = work[0];
    right[n - r] = work[n - r];
  }
}

template <typename T>
int sign_of(T x) {
  return (x > T(0)) - (x < T(0));
}

// Sign variations of the non-zero coefficients.
template <typename T>
int sign_variations(const T* c, int n) {
  int variations = 0, last = 0;
  for (int i = 0; i <= n; ++i) {
    const int s = sign_of(c[i]);
    if (s == 0) continue;
    if (last != 0 && s != last) ++variations;
    last = s;
  }
  return variations;
}

// The sign of c near t = 0 (its first non-zero coefficient's): the side of a single root's
// bracket that t = 0 is on.
template <typename T>
int sign_near_zero(const T* c) {
  int first = 0;
  while (c[first] == T(0)) ++first;
  return sign_of(c[first]);
}

// The one sign-changing root of c on (0, 1) when sign_variations(c) == 1, by bisection until the
// interval cannot shrink in T.
template <typename T, int Capacity = kMaxOrder>
T bisect_single_root(const T* c, int n) {
  const int sign_low = sign_near_zero(c);
  T lo = 0, hi = 1;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const T mid = (lo + hi) / T(2);
    if (!(mid > lo && mid < hi)) break;
    const int s = sign_of(bernstein_value<T, Capacity>(c, n, mid));
    if (s == 0) return mid;
    (s == sign_low ? lo : hi) = mid;
  }
  return (lo + hi) / T(2);
}

// The same root as bisect_single_root (sign_variations(c) == 1), by Newton steps from the chord's
// root; a step that leaves the bracket, or a flat derivative, bisects instead. Stops when a step
// moves t by under a few ulps or the bracket cannot shrink.
template <typename T, int Capacity = kMaxOrder>
T newton_single_root(const T* c, int n) {
  const int sign_low = sign_near_zero(c);
  const T step_limit = T(4) * std::numeric_limits<T>::epsilon();
  T lo = 0, hi = 1;
  T t = c[0] / (c[0] - c[n]);  // c[0] and c[n] differ in sign or one is 0: the chord's root
  if (!(t > lo && t < hi)) t = T(0.5);
  for (int iteration = 0; iteration < 200; ++iteration) {
    // Value and derivative from one de Casteljau pass: the last level's two points.
    T work[Capacity];
    for (int i = 0; i <= n; ++i) work[i] = c[i];
    for (int r = 1; r < n; ++r)
      for (int i = 0; i <= n - r; ++i) work[i] = (T(1) - t) * work[i] + t * work[i + 1];
    const T value = n > 0 ? (T(1) - t) * work[0] + t * work[1] : work[0];
    const T derivative = n > 0 ? T(n) * (work[1] - work[0]) : T(0);
    const int s = sign_of(value);
    if (s == 0) return t;
    (s == sign_low ? lo : hi) = t;
    // A converged step is taken before the bracket test: t, now one end of the bracket, is then
    // the root, and a step of a few ulps may land on or just past that end.
    T next = derivative != T(0) ? t - value / derivative : lo;
    if (std::fabs(next - t) <= step_limit) return std::clamp(next, lo, hi);
    if (!(next > lo && next < hi)) {
      next = (lo + hi) / T(2);
      if (!(next > lo && next < hi)) return next;
    }
    t = next;
  }
  return t;
}

// Subdivision depth at which a cluster of roots (a tangency) is taken as one candidate: 2^-48 of
// a piece's parameter range.
inline constexpr int kMaxIsolationDepth = 48;

// Candidate roots of c on the open interval (t0, t1), in increasing order.
template <typename T, int Capacity = kMaxOrder>
void isolate_roots(const T* c, int n, T t0, T t1, int depth, std::vector<T>& roots,
                   RootRefinement refinement = RootRefinement::bisection) {
  const int variations = sign_variations(c, n);
  if (variations == 0) return;
  if (variations == 1) {
    const T root = refinement == RootRefinement::newton ? newton_single_root<T, Capacity>(c, n)
                                                        : bisect_single_root<T, Capacity>(c, n);
    roots.push_back(t0 + (t1 - t0) * root);
    return;
  }
  const T mid = (t0 + t1) / T(2);
  if (depth >= kMaxIsolationDepth) {
    roots.push_back(mid);
    return;
  }
  T left[Capacity], right[Capacity];
  bernstein_halves<T, Capacity>(c, n, left, right);
  isolate_roots<T, Capacity>(left, n, t0, mid, depth + 1, roots, refinement);
  if (left[n] == T(0)) roots.push_back(mid);  // a root exactly at the split point
  isolate_roots<T, Capacity>(right, n, mid, t1, depth + 1, roots, refinement);
}

template <typename T>
T piece_u_at(const TrimPiece<T>& piece, T t) {
  T hu[kMaxOrder], w[kMaxOrder];
  for (int i = 0; i <= piece.degree; ++i) {
    hu[i] = piece.h[i][0];
    w[i] = piece.h[i][2];
  }
  return bernstein_value(hu, piece.degree, t) / bernstein_value(w, piece.degree, t);
}

// g's coefficient i on the line v: w_i·v_i − v·w_i.
template <typename T>
T line_coefficient(const TrimPiece<T>& piece, int i, T v) {
  return piece.h[i][1] - v * piece.h[i][2];
}

// Appends the u of every change of the above/below state inside one piece (its ends included).
template <typename T>
void piece_events(const TrimPiece<T>& piece, T v, std::vector<T>& roots, std::vector<T>& events,
                  RootRefinement refinement) {
  const int n = piece.degree;
  T c[kMaxOrder];
  bool any_positive = false, any_negative = false;
  for (int i = 0; i <= n; ++i) {
    c[i] = line_coefficient(piece, i, v);
    any_positive |= c[i] > T(0);
    any_negative |= c[i] < T(0);
  }
  if (!(any_positive && any_negative)) {
    // No interior sign change; a state change can only happen at an end where g == 0 while the
    // rest is below (zero counts as above).
    if (!any_negative) return;  // above (or on the line) throughout
    if (c[0] == T(0)) events.push_back(piece_u_at(piece, T(0)));
    if (c[n] == T(0)) events.push_back(piece_u_at(piece, T(1)));
    return;
  }
  if (refinement == RootRefinement::newton && c[0] != T(0) && c[n] != T(0) &&
      sign_variations(c, n) == 1) {
    // Exactly one root on (0, 1), simple, and the ends on either side of the line: the state
    // changes once, there, so the stretches between need no probing (the reference probes them
    // anyway; both agree whenever g's sign is computed right).
    events.push_back(piece_u_at(piece, newton_single_root(c, n)));
    return;
  }
  roots.clear();
  isolate_roots(c, n, T(0), T(1), 0, roots, refinement);
  // States: at t = 0, between consecutive candidates (and the ends), at t = 1; the change between
  // two neighbouring states happens at the point that separates them.
  bool state = c[0] >= T(0);
  T previous = 0;
  for (std::size_t k = 0; k <= roots.size(); ++k) {
    const T next = k < roots.size() ? roots[k] : T(1);
    const bool between = bernstein_value(c, n, (previous + next) / T(2)) >= T(0);
    if (between != state) events.push_back(piece_u_at(piece, previous));
    state = between;
    previous = next;
  }
  if ((c[n] >= T(0)) != state) events.push_back(piece_u_at(piece, T(1)));
}

}  // namespace trim_detail

// The trim's curves as rational Bézier pieces in T.
template <typename T>
TrimPieces<T> trim_pieces(const Trim& trim) {
  TrimPieces<T> out;
  for (const TrimLoop& loop : trim.loops) {
    std::vector<TrimPiece<T>>& pieces = out.loops.emplace_back();
    for (const TrimCurve& curve : loop.curves) {
      const int p = curve.degree, count = static_cast<int>(curve.points.size());
      std::vector<T> knots(curve.knots.begin(), curve.knots.end());
      std::vector<Vec4<T>> homogeneous(curve.points.size());
      for (std::size_t i = 0; i < curve.points.size(); ++i) {
        const T w = T(curve.weights[i]);
        homogeneous[i] = {T(curve.points[i][0]) * w, T(curve.points[i][1]) * w, T(0), w};
      }
      const std::size_t segments = nonempty_spans(p, count, knots.data()).size();
      std::vector<Vec4<T>> bezier(segments * static_cast<std::size_t>(p + 1));
      decompose_curves<T>(p, count, knots.data(), {homogeneous.data(), 1, 1, 1},
                          {bezier.data(), 1, 1, 1});
      for (std::size_t g = 0; g < segments; ++g) {
        TrimPiece<T>& piece = pieces.emplace_back();
        piece.degree = p;
        for (int k = 0; k <= p; ++k) {
          const Vec4<T>& q = bezier[g * (p + 1) + k];
          piece.h[k] = {q[0], q[1], q[3]};
        }
      }
    }
  }
  return out;
}

// Appends the u of the crossing events of the line v on `piece` and on the junction from its end
// to the start of `next` (the following piece of its loop), unsorted. `scratch` is reused between
// calls.
template <typename T>
void piece_crossing_events(const TrimPiece<T>& piece, const TrimPiece<T>& next, T v,
                           std::vector<T>& events, std::vector<T>& scratch,
                           RootRefinement refinement = RootRefinement::bisection) {
  const TrimPiece<T>& a = piece;
  const TrimPiece<T>& b = next;
  trim_detail::piece_events(a, v, scratch, events, refinement);
  const T ca = trim_detail::line_coefficient(a, a.degree, v);
  const T cb = trim_detail::line_coefficient(b, 0, v);
  if ((ca >= T(0)) == (cb >= T(0))) return;
  // The junction's segment from a's end to b's start crosses the line: one event on it.
  const T ua = a.h[a.degree][0] / a.h[a.degree][2], va = a.h[a.degree][1] / a.h[a.degree][2];
  const T ub = b.h[0][0] / b.h[0][2], vb = b.h[0][1] / b.h[0][2];
  T s = vb != va ? (v - va) / (vb - va) : T(0.5);
  s = std::clamp(s, T(0), T(1));
  events.push_back(ua + (ub - ua) * s);
}

// [lo, hi] such that piece_crossing_events(piece, next, v) appends nothing for v < lo or v > hi:
// with positive weights every g coefficient of the piece, and the junction's two ends, are then
// of one strict sign (the piece lies in the hull of its control points). The range is widened by
// far more than the rounding of g's coefficients, so the claim holds in T, not only exactly.
template <typename T>
std::array<T, 2> event_free_outside(const TrimPiece<T>& piece, const TrimPiece<T>& next) {
  T lo = next.h[0][1] / next.h[0][2], hi = lo;
  for (int i = 0; i <= piece.degree; ++i) {
    const T v = piece.h[i][1] / piece.h[i][2];
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  const T margin = T(1024) * std::numeric_limits<T>::epsilon() *
                       std::max({std::fabs(lo), std::fabs(hi), hi - lo}) +
                   std::numeric_limits<T>::min();
  return {lo - margin, hi + margin};
}

// The sorted u of every crossing event of the line v (see the counting rule above). `scratch` is
// reused between calls.
template <typename T>
void crossing_events(const TrimPieces<T>& trim, T v, std::vector<T>& events,
                     std::vector<T>& scratch) {
  events.clear();
  for (const std::vector<TrimPiece<T>>& pieces : trim.loops)
    for (std::size_t k = 0; k < pieces.size(); ++k)
      piece_crossing_events(pieces[k], pieces[(k + 1) % pieces.size()], v, events, scratch);
  std::sort(events.begin(), events.end());
}

// Inside by the even-odd rule: an odd number of events to the right of u.
template <typename T>
bool inside_by_events(const std::vector<T>& sorted_events, T u) {
  const auto right =
      sorted_events.end() - std::upper_bound(sorted_events.begin(), sorted_events.end(), u);
  return (right % 2) == 1;
}

}  // namespace nurbs
