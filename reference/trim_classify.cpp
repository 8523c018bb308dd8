#include "reference/trim_classify.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <type_traits>

#include "reference/trim_crossings.h"

namespace nurbs {

double domain_diagonal(const Surface& s) {
  return std::hypot(s.u_max() - s.u_min(), s.v_max() - s.v_min());
}

namespace {

// ---- Distance to the trim curves ------------------------------------------------------------
// Branch and bound over de Casteljau halves of each piece, in double: the distance decides the
// boundary band, a tolerance, so it needs no extended precision (the classification does). A
// rational piece with positive weights lies in the convex hull of its Cartesian control points,
// so (1) the distance to their bounding box is a lower bound, and (2) when every control point is
// within `flatness` of the chord, every curve point is within `flatness` of the chord and every
// chord point within `flatness` of the curve (the curve joins the chord's ends), so the distance
// to the curve is the distance to the chord ± flatness. Refinement stops when the flatness is
// below the tolerance below: the distance returned is within it of the true one.
constexpr double kDistanceRelativeTolerance = 1e-4;
constexpr double kDistanceAbsoluteTolerance = 1e-12;
// Beyond this fraction of the loops' extent a sample is far from any band a user would choose,
// and the distance is only needed to 1%: most samples are there, and the search is ~10x cheaper.
constexpr double kDistanceNearFraction = 1e-3;
constexpr double kDistanceFarRelativeTolerance = 1e-2;
constexpr int kDistanceMaxDepth = 60;

struct DistancePiece {
  int degree = 0;
  std::array<std::array<double, 3>, kMaxOrder> h{};
  double lo_u = 0, hi_u = 0, lo_v = 0, hi_v = 0;
};

// sqrt of the sum of squares, not std::hypot: (u, v) are O(1) parameters (no overflow to guard
// against) and hypot was a third of the distance search's time.
double length(double du, double dv) {
  return std::sqrt(du * du + dv * dv);
}

double box_distance(double u, double v, double lo_u, double hi_u, double lo_v, double hi_v) {
  const double du = std::max({lo_u - u, 0.0, u - hi_u});
  const double dv = std::max({lo_v - v, 0.0, v - hi_v});
  return length(du, dv);
}

double segment_distance(double u, double v, double au, double av, double bu, double bv) {
  const double eu = bu - au, ev = bv - av;
  const double length2 = eu * eu + ev * ev;
  double s = length2 > 0 ? ((u - au) * eu + (v - av) * ev) / length2 : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  return length(u - (au + s * eu), v - (av + s * ev));
}

void set_bounds(DistancePiece& piece) {
  piece.lo_u = piece.lo_v = std::numeric_limits<double>::infinity();
  piece.hi_u = piece.hi_v = -std::numeric_limits<double>::infinity();
  for (int i = 0; i <= piece.degree; ++i) {
    const double u = piece.h[i][0] / piece.h[i][2], v = piece.h[i][1] / piece.h[i][2];
    piece.lo_u = std::min(piece.lo_u, u);
    piece.hi_u = std::max(piece.hi_u, u);
    piece.lo_v = std::min(piece.lo_v, v);
    piece.hi_v = std::max(piece.hi_v, v);
  }
}

// The halves t in [0, 1/2] and [1/2, 1] of a piece, with their bounds.
void split(const DistancePiece& p, DistancePiece& left, DistancePiece& right) {
  const int n = p.degree;
  left.degree = right.degree = n;
  for (int c = 0; c < 3; ++c) {
    double coefficients[kMaxOrder] = {}, lo[kMaxOrder] = {}, hi[kMaxOrder] = {};
    for (int i = 0; i <= n; ++i) coefficients[i] = p.h[i][c];
    trim_detail::bernstein_halves(coefficients, n, lo, hi);
    for (int i = 0; i <= n; ++i) {
      left.h[i][c] = lo[i];
      right.h[i][c] = hi[i];
    }
  }
  set_bounds(left);
  set_bounds(right);
}

struct DistanceNode {
  DistancePiece piece;
  int depth;
};

struct DistanceTolerance {
  double absolute, near;  // kDistanceAbsoluteTolerance and kDistanceNearFraction of the extent
  double at(double distance) const {
    return distance < near ? std::max(kDistanceRelativeTolerance * distance, absolute)
                           : kDistanceFarRelativeTolerance * distance;
  }
};

// min(best, distance from (u, v) to the piece), within the tolerances above. `stack` is scratch
// space reused between calls.
double piece_distance(const DistancePiece& root, double u, double v, double best,
                      const DistanceTolerance& tolerances, std::vector<DistanceNode>& stack) {
  if (box_distance(u, v, root.lo_u, root.hi_u, root.lo_v, root.hi_v) >= best) return best;
  using Node = DistanceNode;
  stack.assign(1, {root, 0});
  while (!stack.empty()) {
    Node node = std::move(stack.back());
    stack.pop_back();
    const DistancePiece& p = node.piece;
    if (box_distance(u, v, p.lo_u, p.hi_u, p.lo_v, p.hi_v) >= best) continue;
    const int n = p.degree;
    const double au = p.h[0][0] / p.h[0][2], av = p.h[0][1] / p.h[0][2];
    const double bu = p.h[n][0] / p.h[n][2], bv = p.h[n][1] / p.h[n][2];
    best = std::min({best, length(u - au, v - av), length(u - bu, v - bv)});
    double flatness = 0;
    for (int i = 1; i < n; ++i)
      flatness = std::max(
          flatness, segment_distance(p.h[i][0] / p.h[i][2], p.h[i][1] / p.h[i][2], au, av, bu, bv));
    const double chord = segment_distance(u, v, au, av, bu, bv);
    if (chord - flatness >= best) continue;
    const double tolerance = tolerances.at(best);
    if (flatness <= tolerance || node.depth >= kDistanceMaxDepth) {
      best = std::min(best, chord);  // within `flatness` of the distance to this part
      continue;
    }
    Node left{p, node.depth + 1}, right{p, node.depth + 1};
    split(p, left.piece, right.piece);
    // Depth first, the nearer half last on the stack so it is refined first (tightens `best`).
    const double d_left =
        box_distance(u, v, left.piece.lo_u, left.piece.hi_u, left.piece.lo_v, left.piece.hi_v);
    const double d_right =
        box_distance(u, v, right.piece.lo_u, right.piece.hi_u, right.piece.lo_v, right.piece.hi_v);
    if (d_left < d_right) {
      stack.push_back(std::move(right));
      stack.push_back(std::move(left));
    } else {
      stack.push_back(std::move(left));
      stack.push_back(std::move(right));
    }
  }
  return best;
}

// The pieces cut into leaves no flatter than kLeafFlatness of the loops' extent and no longer than
// kLeafLength of it, binned into a uniform grid over the loops: a sample's search looks at the
// cells around it in growing rings and stops at the first ring farther than its best distance, so
// it costs a few leaves, not every piece of every loop. Far samples are settled by a leaf's chord
// (within its flatness); near ones refine the leaf by the branch and bound above.
constexpr double kLeafFlatness = 1e-4;
constexpr double kLeafLength = 1.0 / 32;
constexpr int kLeafMaxDepth = 24;
constexpr int kMaxCellsPerSide = 256;

struct DistanceScratch {
  std::vector<DistanceNode> stack;
  std::vector<std::uint32_t> seen;  // per leaf: the query that last looked at it
  std::uint32_t query = 0;
};

class DistanceIndex {
 public:
  explicit DistanceIndex(const TrimPieces<double>& trim) {
    std::vector<DistancePiece> pieces;
    for (const auto& loop : trim.loops)
      for (const TrimPiece<double>& piece : loop) {
        DistancePiece& d = pieces.emplace_back();
        d.degree = piece.degree;
        d.h = piece.h;
        set_bounds(d);
      }
    double lo_u = std::numeric_limits<double>::infinity(), lo_v = lo_u, hi_u = -lo_u, hi_v = -lo_u;
    for (const DistancePiece& p : pieces) {
      lo_u = std::min(lo_u, p.lo_u);
      lo_v = std::min(lo_v, p.lo_v);
      hi_u = std::max(hi_u, p.hi_u);
      hi_v = std::max(hi_v, p.hi_v);
    }
    const double extent = std::max({hi_u - lo_u, hi_v - lo_v, std::fabs(lo_u), std::fabs(hi_u),
                                    std::fabs(lo_v), std::fabs(hi_v), 1e-300});
    tolerances_ = {kDistanceAbsoluteTolerance * extent, kDistanceNearFraction * extent};
    for (const DistancePiece& p : pieces)
      add_leaves(p, kLeafFlatness * extent, kLeafLength * extent, 0);

    const double width = std::max({hi_u - lo_u, hi_v - lo_v, 1e-300});
    const int side = std::clamp(static_cast<int>(std::ceil(std::sqrt(double(leaves_.size())))), 1,
                                kMaxCellsPerSide);
    cell_ = width / side;
    lo_u_ = lo_u;
    lo_v_ = lo_v;
    cells_u_ = std::clamp(static_cast<int>(std::ceil((hi_u - lo_u) / cell_)), 1, kMaxCellsPerSide);
    cells_v_ = std::clamp(static_cast<int>(std::ceil((hi_v - lo_v) / cell_)), 1, kMaxCellsPerSide);
    cells_.resize(static_cast<std::size_t>(cells_u_) * cells_v_);
    for (std::uint32_t k = 0; k < leaves_.size(); ++k) {
      const DistancePiece& p = leaves_[k].piece;
      for (int i = cell_u(p.lo_u); i <= cell_u(p.hi_u); ++i)
        for (int j = cell_v(p.lo_v); j <= cell_v(p.hi_v); ++j) cell(i, j).push_back(k);
    }
  }

  // min(best, the distance from (u, v) to the loops), within the tolerances above.
  double distance(double u, double v, double best, DistanceScratch& scratch) const {
    if (leaves_.empty()) return best;
    if (scratch.seen.size() != leaves_.size()) scratch.seen.assign(leaves_.size(), 0);
    if (++scratch.query == 0) {  // wrapped: forget every mark
      std::fill(scratch.seen.begin(), scratch.seen.end(), 0);
      scratch.query = 1;
    }
    const int ci = cell_u(u), cj = cell_v(v);
    for (int ring = 0; ring <= std::max(cells_u_, cells_v_); ++ring) {
      bool ring_within_best = false;
      auto visit = [&](int i, int j) {
        if (i < 0 || j < 0 || i >= cells_u_ || j >= cells_v_) return;
        const double cell_lo_u = lo_u_ + i * cell_, cell_lo_v = lo_v_ + j * cell_;
        if (box_distance(u, v, cell_lo_u, cell_lo_u + cell_, cell_lo_v, cell_lo_v + cell_) >= best)
          return;
        ring_within_best = true;
        for (std::uint32_t k : cell(i, j)) {
          if (scratch.seen[k] == scratch.query) continue;
          scratch.seen[k] = scratch.query;
          best = leaf_distance(leaves_[k], u, v, best, scratch);
        }
      };
      if (ring == 0) {
        visit(ci, cj);
      } else {  // the ring's four sides
        for (int i = ci - ring; i <= ci + ring; ++i) {
          visit(i, cj - ring);
          visit(i, cj + ring);
        }
        for (int j = cj - ring + 1; j <= cj + ring - 1; ++j) {
          visit(ci - ring, j);
          visit(ci + ring, j);
        }
      }
      // Distances to the cells of later rings are no smaller than to this ring's (each axis'
      // distance grows with the index offset from the sample's clamped cell).
      if (!ring_within_best && ring > 0) break;
    }
    return best;
  }

 private:
  struct Leaf {
    DistancePiece piece;
    double au, av, bu, bv, flatness;
  };

  void add_leaves(const DistancePiece& p, double flatness_limit, double length_limit, int depth) {
    const int n = p.degree;
    Leaf leaf{p,
              p.h[0][0] / p.h[0][2],
              p.h[0][1] / p.h[0][2],
              p.h[n][0] / p.h[n][2],
              p.h[n][1] / p.h[n][2],
              0};
    for (int i = 1; i < n; ++i)
      leaf.flatness =
          std::max(leaf.flatness, segment_distance(p.h[i][0] / p.h[i][2], p.h[i][1] / p.h[i][2],
                                                   leaf.au, leaf.av, leaf.bu, leaf.bv));
    const double size = std::max(p.hi_u - p.lo_u, p.hi_v - p.lo_v);
    if (depth >= kLeafMaxDepth || (leaf.flatness <= flatness_limit && size <= length_limit)) {
      leaves_.push_back(leaf);
      return;
    }
    DistancePiece left = p, right = p;
    split(p, left, right);
    add_leaves(left, flatness_limit, length_limit, depth + 1);
    add_leaves(right, flatness_limit, length_limit, depth + 1);
  }

  double leaf_distance(const Leaf& leaf, double u, double v, double best,
                       DistanceScratch& scratch) const {
    const DistancePiece& p = leaf.piece;
    if (box_distance(u, v, p.lo_u, p.hi_u, p.lo_v, p.hi_v) >= best) return best;
    const double chord = segment_distance(u, v, leaf.au, leaf.av, leaf.bu, leaf.bv);
    if (chord - leaf.flatness >= best) return best;
    if (leaf.flatness <= tolerances_.at(std::min(best, chord + leaf.flatness)))
      return std::min(best, chord);
    return piece_distance(p, u, v, best, tolerances_, scratch.stack);
  }

  int cell_u(double u) const {
    return std::clamp(static_cast<int>(std::floor((u - lo_u_) / cell_)), 0, cells_u_ - 1);
  }
  int cell_v(double v) const {
    return std::clamp(static_cast<int>(std::floor((v - lo_v_) / cell_)), 0, cells_v_ - 1);
  }
  std::vector<std::uint32_t>& cell(int i, int j) {
    return cells_[static_cast<std::size_t>(i) * cells_v_ + j];
  }
  const std::vector<std::uint32_t>& cell(int i, int j) const {
    return cells_[static_cast<std::size_t>(i) * cells_v_ + j];
  }

  std::vector<Leaf> leaves_;
  std::vector<std::vector<std::uint32_t>> cells_;
  double lo_u_ = 0, lo_v_ = 0, cell_ = 1;
  int cells_u_ = 1, cells_v_ = 1;
  DistanceTolerance tolerances_{};
};

// ---- Samples grouped by their v: one crossing list per distinct v ---------------------------

struct Rows {
  std::vector<double> v;                      // distinct v, one row each
  std::vector<std::vector<std::size_t>> ids;  // sample indices of each row, in ascending u
};

Rows rows_of(const SurfaceSamples& samples) {
  Rows rows;
  if (samples.tensor) {
    // Sample (a, b) at a * nv + b lies in row b.
    const std::size_t nu = samples.u.size(), nv = samples.v.size();
    rows.v = samples.v;
    rows.ids.resize(nv);
    std::vector<std::size_t> by_u(nu);
    std::iota(by_u.begin(), by_u.end(), std::size_t{0});
    std::stable_sort(by_u.begin(), by_u.end(),
                     [&](std::size_t x, std::size_t y) { return samples.u[x] < samples.u[y]; });
    for (std::size_t b = 0; b < nv; ++b)
      for (std::size_t a : by_u) rows.ids[b].push_back(a * nv + b);
    return rows;
  }
  std::vector<std::size_t> order(samples.count());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return samples.v[x] != samples.v[y] ? samples.v[x] < samples.v[y] : samples.u[x] < samples.u[y];
  });
  for (std::size_t k : order) {
    if (rows.v.empty() || rows.v.back() != samples.v[k]) {
      rows.v.push_back(samples.v[k]);
      rows.ids.emplace_back();
    }
    rows.ids.back().push_back(k);
  }
  return rows;
}

template <typename T>
TrimClassification classify(const Trim& trim, const SurfaceSamples& samples, bool with_distance,
                            int threads) {
  const TrimPieces<T> pieces = trim_pieces<T>(trim);
  const Rows rows = rows_of(samples);
  TrimClassification out;
  out.inside.assign(samples.count(), 0);
  std::optional<DistanceIndex> index;
  if (with_distance) {
    out.distance.assign(samples.count(), std::numeric_limits<double>::infinity());
    if constexpr (std::is_same_v<T, double>)
      index.emplace(pieces);
    else
      index.emplace(trim_pieces<double>(trim));
  }
  const std::ptrdiff_t row_count = static_cast<std::ptrdiff_t>(rows.v.size());
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads())
  {
    std::vector<T> events, scratch;
    DistanceScratch scratch_distance;
#pragma omp for schedule(dynamic, 4)
    for (std::ptrdiff_t r = 0; r < row_count; ++r) {
      const T v = T(rows.v[r]);
      crossing_events(pieces, v, events, scratch);
      double previous_u = 0, previous_distance = std::numeric_limits<double>::infinity();
      for (std::size_t k : rows.ids[r]) {
        const T u = T(samples.u_of(k));
        out.inside[k] = inside_by_events(events, u) ? 1 : 0;
        if (!with_distance) continue;
        // Upper bounds before the search: the row's crossings are points of the loops at this v
        // (a junction's lies on its closing segment, within the trim's tolerance of the curves),
        // and the distance is 1-Lipschitz along the row.
        double best = previous_distance + std::fabs(samples.u_of(k) - previous_u);
        for (const T& e : events) best = std::min(best, static_cast<double>(std::fabs(e - u)));
        best = index->distance(samples.u_of(k), rows.v[r], best, scratch_distance);
        out.distance[k] = best;
        previous_u = samples.u_of(k);
        previous_distance = best;
      }
    }
  }
  return out;
}

}  // namespace

TrimClassification classify_trim_samples(const Trim& trim, const SurfaceSamples& samples,
                                         bool with_distance, TrimScalar scalar, int threads) {
  return scalar == TrimScalar::f64 ? classify<double>(trim, samples, with_distance, threads)
                                   : classify<long double>(trim, samples, with_distance, threads);
}

}  // namespace nurbs
