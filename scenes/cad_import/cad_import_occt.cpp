// The importer with OpenCASCADE: each converted face -> one Surface with its trim, checked.
#include <fmt/format.h>

#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <BndLib_Add2dCurve.hxx>
#include <Bnd_Box2d.hxx>
#include <Geom2dConvert.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomAdaptor_Surface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <gp_Vec2d.hxx>
#include <optional>

#include "reference/reference_evaluator.h"
#include "reference/trim_classify.h"
#include "reference/validation.h"
#include "scenes/cad_import/cad_import.h"
#include "scenes/cad_import/occt_model.h"

namespace nurbs {
namespace {

// The surface check: imported surface vs OpenCASCADE's evaluation on kCheckGrid^2 parameters,
// within kMaxSurfaceDeviation of the face's size (its control points' bounding-box diagonal).
constexpr int kCheckGrid = 17;
constexpr double kMaxSurfaceDeviation = 1e-9;
// Knot-insertion rounds (each halves every span) that pull a p-curve's control points onto the
// curve, and the pole count past which we stop refining.
constexpr int kMaxRefinements = 8;
constexpr int kMaxRefinedPoles = 1 << 12;

// Why a face is skipped: `reason` groups faces in the summary, `detail` is this face's value.
struct FaceSkip {
  std::string reason, detail;
};

Surface to_surface(const Geom_BSplineSurface& b) {
  Surface s;
  s.degree_u = b.UDegree();
  s.degree_v = b.VDegree();
  s.count_u = b.NbUPoles();
  s.count_v = b.NbVPoles();
  const TColStd_Array1OfReal knots_u = b.UKnotSequence(), knots_v = b.VKnotSequence();
  s.knots_u.assign(knots_u.begin(), knots_u.end());
  s.knots_v.assign(knots_v.begin(), knots_v.end());
  for (int i = 1; i <= s.count_u; ++i)
    for (int j = 1; j <= s.count_v; ++j) {
      const gp_Pnt& p = b.Pole(i, j);
      s.points.push_back({p.X(), p.Y(), p.Z()});
      s.weights.push_back(b.Weight(i, j));
    }
  return s;
}

TrimCurve to_trim_curve(const Geom2d_BSplineCurve& c) {
  TrimCurve t;
  t.degree = c.Degree();
  const TColStd_Array1OfReal knots = c.KnotSequence();
  t.knots.assign(knots.begin(), knots.end());
  for (int i = 1; i <= c.NbPoles(); ++i) {
    t.points.push_back({c.Pole(i).X(), c.Pole(i).Y()});
    t.weights.push_back(c.Weight(i));
  }
  return t;
}

struct Domain {
  double u0, u1, v0, v1;
  double excess(const gp_Pnt2d& p) const {
    return std::max({u0 - p.X(), p.X() - u1, v0 - p.Y(), p.Y() - v1, 0.0});
  }
  Point2 clamp(const Point2& p) const {
    return {std::clamp(p[0], u0, u1), std::clamp(p[1], v0, v1)};
  }
};

// How far moving the control points outside the domain onto its edge (r, the nearest point) can
// move the curve C from its own retraction r(C) onto the domain, which leaves every inside
// point's even-odd class unchanged (the straight homotopy from C to r(C) never crosses the
// domain's interior). Two bounds, the smaller holds: |sum N_i r(P_i) - r(C(t))| <= max |P_i -
// C(t)| over the poles of t's span (r is 1-Lipschitz), at most the span's control-polygon
// diameter, itself at most twice the largest distance from one of its poles (an outside one, or
// the span does not move) to the others; and moving each pole by its excess e_i moves C by at
// most max e_i, while C itself leaves the domain by at most max e_i (convex hull), so 2 max e_i.
// Knot insertion shrinks both (the poles close in on the curve); a pole within `tolerance`
// counts only its excess.
double clamp_change(const Geom2d_BSplineCurve& c, const Domain& domain, double tolerance) {
  double diameter = 0, excess = 0;
  const int degree = c.Degree();
  for (int i = 1; i <= c.NbPoles(); ++i) {
    const double e = domain.excess(c.Pole(i));
    excess = std::max(excess, e);
    diameter = std::max(diameter, e);
    if (e <= tolerance) continue;
    for (int j = std::max(1, i - degree); j <= std::min(c.NbPoles(), i + degree); ++j)
      diameter = std::max(diameter, 2 * c.Pole(i).Distance(c.Pole(j)));
  }
  return std::min(diameter, 2 * excess);
}

// A face's p-curves, one vector per wire (the outer wire first), each curve a non-periodic 2D
// B-spline running in the wire's direction, before they are placed on the surface's domain.
using Loops = std::vector<std::vector<Handle(Geom2d_BSplineCurve)>>;

// The converted face's surface as OpenCASCADE evaluates it: a B-spline, periodic or not, with its
// location applied.
Handle(Geom_BSplineSurface) face_bspline(const TopoDS_Face& face) {
  Handle(Geom_Surface) geometry = BRep_Tool::Surface(face);
  if (auto trimmed = Handle(Geom_RectangularTrimmedSurface)::DownCast(geometry))
    geometry = trimmed->BasisSurface();
  const auto bspline = Handle(Geom_BSplineSurface)::DownCast(geometry);
  if (bspline.IsNull())
    throw FaceSkip{"not a B-spline after conversion", geometry->DynamicType()->Name()};
  return bspline;
}

// Where the face's loops go on its surface, per direction (0: u, 1: v): the domain the imported
// surface will have, and how it was found. Every route is exact -- the surface on the new domain
// is OpenCASCADE's own surface there, the p-curves are moved only by whole periods:
// - a periodic direction: each loop is moved by whole periods into one period [s, s + T] that no
//   loop crosses; s is the surface's own origin where the loops allow it, else a new seam
//   ("seam moved"): Segment over [s, s + T] re-clamps the periodic surface there by knot
//   insertion (the surface unchanged), its knots then shifted by a whole period to start at s.
// - a non-periodic direction: a loop that runs past the domain by more than the (u, v)
//   tolerance gets the domain extended to it ("domain extended"): OpenCASCADE evaluates a
//   B-spline past its end knots by continuing the end span's polynomial, and so the model's
//   edges were made on that continuation; extend_end writes the same polynomial over the longer
//   span. Chosen over splitting the loop or clamping it, which would change the face.
// - a loop longer than a period (a helical strip winding twice around a cylinder): the domain
//   spans N whole periods ("unrolled over N periods"), the surface written as N copies of one
//   clamped period side by side (unroll_periods) -- the same points, each period once more.
// - a closed but non-periodic direction (a periodic surface OpenCASCADE converted to a clamped
//   B-spline) whose loops run past its end by more than a period: its p-curves were made on the
//   periodic surface, so the direction is wrapped like a periodic one ("closed direction
//   wrapped"), with the surface's own origin as the seam; exact only where the end rows coincide
//   as homogeneous points up to one factor (unroll_periods checks).
struct Placement {
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  bool periodic[2] = {false, false};
  bool wrapped[2] = {false, false};  // closed, non-periodic, treated as periodic
  int periods[2] = {1, 1};           // whole periods the domain spans (periodic or wrapped)
  std::vector<std::string> routes;   // for the summary, in the order found, each once
  void add(const std::string& route) {
    if (std::find(routes.begin(), routes.end(), route) == routes.end()) routes.push_back(route);
  }
};

// The u (axis 0) or v (axis 1) range the curves actually cover (not their control polygons).
std::pair<double, double> curve_range(const std::vector<Handle(Geom2d_BSplineCurve)>& curves,
                                      int axis) {
  Bnd_Box2d box;
  for (const auto& c : curves)
    BndLib_Add2dCurve::AddOptimal(c, c->FirstParameter(), c->LastParameter(), 0.0, box);
  double x0, y0, x1, y1;
  box.Get(x0, y0, x1, y1);
  return axis == 0 ? std::pair{x0, x1} : std::pair{y0, y1};
}

void translate(const Handle(Geom2d_BSplineCurve) & curve, int axis, double by) {
  curve->Translate(gp_Vec2d(axis == 0 ? by : 0.0, axis == 0 ? 0.0 : by));
}

// How far past a non-periodic end (of the domain's width) a loop must run to extend the domain;
// closer, the control points are moved onto the edge (their change is in the figures).
constexpr double kExtendPast = 1e-9;

// A loop winding around more often than this is refused rather than unrolled (the surface grows
// by a copy of its period each time).
constexpr int kMaxUnrolledPeriods = 16;

// How a non-periodic direction's domain may grow, tried in this order (import_cad_model): to the
// loops' control points where the curves themselves leave the domain (to the curves alone would
// leave them tangent to the new edge, their control points outside: moving those is not exact);
// to the control points wherever they leave it (a circle touching the domain's edge); not at all
// (the fallback when extending fails: a weight would not stay positive).
enum class Extend { where_curves_leave, to_control_points, never };

// The u (axis 0) or v (axis 1) range of the curves' control points.
std::pair<double, double> pole_range(const std::vector<Handle(Geom2d_BSplineCurve)>& curves,
                                     int axis) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const auto& c : curves)
    for (int i = 1; i <= c->NbPoles(); ++i) {
      lo = std::min(lo, c->Pole(i).Coord(axis + 1));
      hi = std::max(hi, c->Pole(i).Coord(axis + 1));
    }
  return {lo, hi};
}

// The loops' periodic placement is the same for every `extend`.
Placement place_loops(const Geom_BSplineSurface& bspline, Loops& loops, double tolerance,
                      Extend extend) {
  Placement placed;
  double bounds[4];
  bspline.Bounds(bounds[0], bounds[1], bounds[2], bounds[3]);
  for (int axis = 0; axis < 2; ++axis) {
    const double first = bounds[2 * axis], last = bounds[2 * axis + 1];
    placed.lo[axis] = first;
    placed.hi[axis] = last;
    const bool periodic = axis == 0 ? bspline.IsUPeriodic() : bspline.IsVPeriodic();
    const bool closed = axis == 0 ? bspline.IsUClosed() : bspline.IsVClosed();
    placed.periodic[axis] = periodic;
    // A closed direction is wrapped only where no other reading is possible: loops longer than
    // the surface (continuing its end polynomial past a whole period would not close it).
    if (!periodic && closed) {
      double lo = first, hi = last;
      for (const auto& loop : loops) {
        const auto [a, b] = curve_range(loop, axis);
        lo = std::min(lo, a);
        hi = std::max(hi, b);
      }
      placed.wrapped[axis] = hi - lo > last - first + tolerance;
    }
    if (periodic || placed.wrapped[axis]) {
      const double period = last - first;
      bool moved = false;
      // Within a loop, a curve that starts a whole period away from the previous curve's end
      // follows it (seam edges stay where they are: their ends meet in the same period).
      for (auto& loop : loops)
        for (std::size_t c = 1; c < loop.size(); ++c) {
          const double end = loop[c - 1]->EndPoint().Coord(axis + 1);
          const double k = std::round((end - loop[c]->StartPoint().Coord(axis + 1)) / period);
          if (k != 0) translate(loop[c], axis, k * period), moved = true;
        }
      // The domain spans as many whole periods as the longest loop needs (one, but for a loop
      // winding more than once around).
      std::vector<std::pair<double, double>> ranges;
      int periods = 1;
      for (const auto& loop : loops) {
        ranges.push_back(curve_range(loop, axis));
        const double length = ranges.back().second - ranges.back().first;
        periods = std::max(periods, static_cast<int>(std::ceil((length - tolerance) / period)));
      }
      if (periods > kMaxUnrolledPeriods)
        throw FaceSkip{"loop longer than a period",
                       fmt::format("a loop winds {} times around in {} (period {:.6g}), more "
                                   "than {}",
                                   periods, "uv"[axis], period, kMaxUnrolledPeriods)};
      const double window = periods * period;
      // A seam no loop crosses: the surface's own first, else a loop's start (if any seam is
      // free, moving it forward to the next loop start keeps it free). A wrapped direction keeps
      // its own origin: its surface exists only from there.
      auto shift_into = [&](double s, const std::pair<double, double>& r) -> std::optional<double> {
        const double k = std::ceil((s - tolerance - r.first) / period);
        if (r.second + k * period <= s + window + tolerance) return k;
        return std::nullopt;
      };
      std::vector<double> seams{first};
      if (!placed.wrapped[axis])
        for (const auto& r : ranges) seams.push_back(r.first);
      std::optional<double> seam;
      for (double s : seams)
        if (std::all_of(ranges.begin(), ranges.end(),
                        [&](const auto& r) { return shift_into(s, r).has_value(); })) {
          seam = s;
          break;
        }
      if (!seam)
        throw FaceSkip{"every seam position is crossed by a loop",
                       fmt::format("in {} (period {:.6g}): the loops would have to be split at "
                                   "the seam",
                                   "uv"[axis], period)};
      // Unrolled, a hole must lie within the outer loop's periods: one that leaves them crosses
      // a seam edge of the outer loop, which unrolling does not split.
      if (periods > 1)
        for (std::size_t l = 1; l < loops.size(); ++l) {
          const double k0 = *shift_into(*seam, ranges[0]), k = *shift_into(*seam, ranges[l]);
          if (ranges[l].first + k * period < ranges[0].first + k0 * period - tolerance ||
              ranges[l].second + k * period > ranges[0].second + k0 * period + tolerance)
            throw FaceSkip{"every seam position is crossed by a loop",
                           fmt::format("in {} (period {:.6g}): loop {} leaves the outer loop's "
                                       "{} periods: the loops would have to be split at the seam",
                                       "uv"[axis], period, l, periods)};
        }
      for (std::size_t l = 0; l < loops.size(); ++l) {
        const double k = *shift_into(*seam, ranges[l]);
        if (k != 0) {
          for (const auto& c : loops[l]) translate(c, axis, k * period);
          moved = true;
        }
      }
      if (moved) placed.add("moved by whole periods");
      const double origin = std::abs(*seam - first) > tolerance ? *seam : first;
      if (origin != first) placed.add("seam moved");
      placed.lo[axis] = origin;
      placed.hi[axis] = origin + window;
      placed.periods[axis] = periods;
      if (periods > 1) placed.add(fmt::format("unrolled over {} periods", periods));
      if (placed.wrapped[axis]) placed.add("closed direction wrapped");
    } else if (extend != Extend::never) {
      double lo = first, hi = last, pole_lo = first, pole_hi = last;
      for (const auto& loop : loops) {
        const auto [a, b] = curve_range(loop, axis);
        lo = std::min(lo, a);
        hi = std::max(hi, b);
        const auto [c, d] = pole_range(loop, axis);
        pole_lo = std::min(pole_lo, c);
        pole_hi = std::max(pole_hi, d);
      }
      // Any excess past rounding: extending is exact, moving control points is not.
      const double past = kExtendPast * (last - first);
      if (extend == Extend::to_control_points || lo < first - past || hi > last + past) {
        if (pole_lo < first - past) placed.lo[axis] = pole_lo;
        if (pole_hi > last + past) placed.hi[axis] = pole_hi;
      }
      if (placed.lo[axis] != first || placed.hi[axis] != last) {
        placed.add("domain extended");
      }
    }
  }
  return placed;
}

// Writes the end span's polynomial of a clamped, non-periodic B-spline over [new_first, ...]
// (at_start) or [..., new_last] in u: knot insertion makes the end span a Bezier patch (the surface
// unchanged), de Casteljau at the parameter past its end gives that polynomial's Bezier points
// over the longer span, in homogeneous coordinates (Piegl & Tiller A5.6 read backwards).
void extend_end(Geom_BSplineSurface& s, bool at_start, double to) {
  const int p = s.UDegree();
  const int inner = at_start ? 2 : s.NbUKnots() - 1;
  if (s.NbUKnots() > 2 && s.UMultiplicity(inner) < p)
    s.InsertUKnot(s.UKnot(inner), p, 0.0, Standard_False);
  const double a = s.UKnot(at_start ? 1 : s.NbUKnots() - 1);
  const double b = s.UKnot(at_start ? 2 : s.NbUKnots());
  const double t = (to - a) / (b - a);  // < 0 at the start, > 1 at the end
  const int base = at_start ? 1 : s.NbUPoles() - p;
  for (int j = 1; j <= s.NbVPoles(); ++j) {
    std::vector<std::array<double, 4>> h(p + 1);
    for (int i = 0; i <= p; ++i) {
      const gp_Pnt& q = s.Pole(base + i, j);
      const double w = s.Weight(base + i, j);
      h[i] = {q.X() * w, q.Y() * w, q.Z() * w, w};
    }
    // Level r of de Casteljau: the extended span's points are the first of each level (end) or
    // the last of each level (start).
    std::vector<std::array<double, 4>> out(p + 1);
    out[at_start ? p : 0] = at_start ? h[p] : h[0];
    for (int r = 1; r <= p; ++r) {
      for (int i = 0; i <= p - r; ++i)
        for (int c = 0; c < 4; ++c) h[i][c] = (1 - t) * h[i][c] + t * h[i + 1][c];
      if (at_start)
        out[p - r] = h[p - r];
      else
        out[r] = h[0];
    }
    for (int i = 0; i <= p; ++i) {
      const double w = out[i][3];
      if (!(w > 0))
        throw FaceSkip{"extending the domain makes a weight non-positive",
                       fmt::format("u to {:.6g}: weight {:.3g}", to, w)};
      s.SetPole(base + i, j, gp_Pnt(out[i][0] / w, out[i][1] / w, out[i][2] / w), w);
    }
  }
  s.SetUKnot(at_start ? 1 : s.NbUKnots(), to);
}

// `copies` periods of a clamped surface side by side in u, each shifted by its period: the
// junction knots get multiplicity p (a C0 join in the representation; the surface is the
// periodic one, however smooth), copy c's weights scaled by ratio^c so that the shared rows agree
// as homogeneous points. Exact when the end rows are the same points and their weights differ by
// one factor (a periodic surface clamped, or a closed one that was).
Handle(Geom_BSplineSurface) unroll_periods(const Geom_BSplineSurface& s, int copies) {
  const int p = s.UDegree(), n = s.NbUPoles(), m = s.NbVPoles(), knots = s.NbUKnots();
  const double period = s.UKnot(knots) - s.UKnot(1);
  const double ratio = s.Weight(n, 1) / s.Weight(1, 1);
  for (int j = 1; j <= m; ++j) {
    const double size = std::max(1.0, s.Pole(1, j).XYZ().Modulus());
    if (s.Pole(1, j).Distance(s.Pole(n, j)) > 1e-12 * size ||
        std::abs(s.Weight(n, j) - ratio * s.Weight(1, j)) > 1e-12 * s.Weight(n, j))
      throw FaceSkip{
          "closed surface's ends are not one period",
          fmt::format("row {}: end points {:.3g} apart, weights {:.6g} and {:.6g}", j,
                      s.Pole(1, j).Distance(s.Pole(n, j)), s.Weight(1, j), s.Weight(n, j))};
  }
  const int rows = copies * (n - 1) + 1, count = copies * (knots - 1) + 1;
  TColgp_Array2OfPnt poles(1, rows, 1, m);
  TColStd_Array2OfReal weights(1, rows, 1, m);
  TColStd_Array1OfReal uknots(1, count);
  TColStd_Array1OfInteger umults(1, count);
  double scale = 1;
  for (int c = 0; c < copies; ++c, scale *= ratio) {
    for (int i = c == 0 ? 1 : 2; i <= n; ++i)
      for (int j = 1; j <= m; ++j) {
        poles(c * (n - 1) + i, j) = s.Pole(i, j);
        weights(c * (n - 1) + i, j) = scale * s.Weight(i, j);
      }
    for (int k = c == 0 ? 1 : 2; k <= knots; ++k) {
      uknots(c * (knots - 1) + k) = s.UKnot(k) + c * period;
      umults(c * (knots - 1) + k) = s.UMultiplicity(k);
    }
    if (c > 0) umults(c * (knots - 1) + 1) = p;
  }
  TColStd_Array1OfReal vknots(1, s.NbVKnots());
  TColStd_Array1OfInteger vmults(1, s.NbVKnots());
  s.VKnots(vknots);
  s.VMultiplicities(vmults);
  return new Geom_BSplineSurface(poles, weights, uknots, vknots, umults, vmults, p, s.VDegree());
}

// The face's own surface at (u, v) as its p-curves read it: OpenCASCADE wraps a periodic
// direction itself; a wrapped (closed, non-periodic) one is wrapped here.
gp_Pnt face_point(const Geom_BSplineSurface& bspline, const Placement& placed, double u, double v) {
  double b[4];
  bspline.Bounds(b[0], b[1], b[2], b[3]);
  double uv[2] = {u, v};
  for (int axis = 0; axis < 2; ++axis)
    if (placed.wrapped[axis]) {
      const double first = b[2 * axis], period = b[2 * axis + 1] - first;
      uv[axis] = std::clamp(uv[axis] - std::floor((uv[axis] - first) / period) * period, first,
                            first + period);
    }
  return bspline.Value(uv[0], uv[1]);
}

// The converted face's surface on the placed domain, non-periodic and clamped, as a Surface;
// checked against OpenCASCADE's evaluation of the face's own surface over that whole domain
// (periodic: in whatever period; past a non-periodic end: OpenCASCADE's continuation).
Surface face_surface(const TopoDS_Face& face, const Geom_BSplineSurface& bspline,
                     const Placement& placed, double& deviation) {
  double u0, u1, v0, v1;
  bspline.Bounds(u0, u1, v0, v1);
  // Segment over the placed period clamps a periodic direction there (knot insertion: the
  // surface and its parameters unchanged) -- in the period OpenCASCADE normalises to, so the
  // knots are shifted back by whole periods after. A non-periodic direction keeps its bounds
  // here and is extended below.
  const auto flat = Handle(Geom_BSplineSurface)::DownCast(bspline.Copy());
  // One period here; unrolled over the rest below.
  const double s0 = placed.periodic[0] ? placed.lo[0] : u0;
  const double s1 = placed.periodic[0] ? placed.lo[0] + (u1 - u0) : u1;
  const double t0 = placed.periodic[1] ? placed.lo[1] : v0;
  const double t1 = placed.periodic[1] ? placed.lo[1] + (v1 - v0) : v1;
  if (placed.periodic[0] || placed.periodic[1]) {
    flat->Segment(s0, s1, t0, t1);
    double f0, f1, g0, g1;
    if (flat->IsUPeriodic() || flat->IsVPeriodic()) {
      // SetNotPeriodic keeps the parameters but leaves unclamped end knots; Segment over the same
      // bounds clamps them.
      if (flat->IsUPeriodic()) flat->SetUNotPeriodic();
      if (flat->IsVPeriodic()) flat->SetVNotPeriodic();
      flat->Bounds(f0, f1, g0, g1);
      flat->Segment(f0, f1, g0, g1);
    }
    for (int axis = 0; axis < 2; ++axis) {
      if (!placed.periodic[axis]) continue;
      flat->Bounds(f0, f1, g0, g1);
      const double now = axis == 0 ? f0 : g0, period = axis == 0 ? u1 - u0 : v1 - v0;
      const double by = std::round((placed.lo[axis] - now) / period) * period;
      if (by == 0) continue;
      TColStd_Array1OfReal knots = axis == 0 ? flat->UKnots() : flat->VKnots();
      for (double& k : knots) k += by;
      if (axis == 0)
        flat->SetUKnots(knots);
      else
        flat->SetVKnots(knots);
    }
  }
  Handle(Geom_BSplineSurface) placed_surface = flat;
  for (int axis = 0; axis < 2; ++axis) {
    if (axis == 1) placed_surface->ExchangeUV();
    double f0, f1, g0, g1;
    placed_surface->Bounds(f0, f1, g0, g1);
    // Unclamped end knots (uniform B-splines from some files) clamped first: extend_end and
    // unroll_periods need the end knots to be the domain's ends.
    if ((placed.lo[axis] < f0 || placed.hi[axis] > f1) &&
        (placed_surface->UKnot(1) != f0 || placed_surface->UKnot(placed_surface->NbUKnots()) != f1))
      placed_surface->Segment(f0, f1, g0, g1);
    if (placed.periodic[axis] || placed.wrapped[axis]) {
      if (placed.periods[axis] > 1)
        placed_surface = unroll_periods(*placed_surface, placed.periods[axis]);
    } else {
      if (placed.lo[axis] < placed_surface->UKnot(1))
        extend_end(*placed_surface, true, placed.lo[axis]);
      if (placed.hi[axis] > placed_surface->UKnot(placed_surface->NbUKnots()))
        extend_end(*placed_surface, false, placed.hi[axis]);
    }
    if (axis == 1) placed_surface->ExchangeUV();
  }
  Surface surface = to_surface(*placed_surface);
  // Shifting knots by a whole period rounds; the domain must be the placed one to an ulp or so.
  const double slack = 1e-12 * std::max({1.0, std::abs(placed.lo[0]), std::abs(placed.hi[0]),
                                         std::abs(placed.lo[1]), std::abs(placed.hi[1])});
  if (std::abs(surface.u_min() - placed.lo[0]) > slack ||
      std::abs(surface.u_max() - placed.hi[0]) > slack ||
      std::abs(surface.v_min() - placed.lo[1]) > slack ||
      std::abs(surface.v_max() - placed.hi[1]) > slack)
    throw FaceSkip{"parameters changed by the conversion",
                   fmt::format("domain [{}, {}] x [{}, {}] became [{}, {}] x [{}, {}]",
                               placed.lo[0], placed.hi[0], placed.lo[1], placed.hi[1],
                               surface.u_min(), surface.u_max(), surface.v_min(), surface.v_max())};
  SurfaceSamples samples;
  samples.u = grid_parameters(surface.u_min(), surface.u_max(), kCheckGrid);
  samples.v = grid_parameters(surface.v_min(), surface.v_max(), kCheckGrid);
  Scene one{"check", "", {surface}};
  one.surfaces.front().name = "check";
  const ReferenceSurface ours = evaluate_reference(one, {samples}, false).front();
  double largest = 0;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    const gp_Pnt p = face_point(bspline, placed, samples.u_of(k), samples.v_of(k));
    const Point3& q = ours.positions[k];
    largest = std::max(largest, std::hypot(p.X() - q[0], p.Y() - q[1], p.Z() - q[2]));
  }
  const double size = one.bounding_box_diagonal();
  deviation = size > 0 ? largest / size : largest;
  if (!(deviation <= kMaxSurfaceDeviation))
    throw FaceSkip{"surface differs from OpenCASCADE's",
                   fmt::format("deviation {:.3g} of the face's size > {:.0e}", deviation,
                               kMaxSurfaceDeviation)};
  surface.reversed = face.Orientation() == TopAbs_REVERSED;
  return surface;
}

// The model's 3D tolerance at this face: the largest of its vertices and edges.
double face_tolerance_3d(const TopoDS_Face& face) {
  double tolerance = 0;
  for (TopExp_Explorer e(face, TopAbs_VERTEX); e.More(); e.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(e.Current())));
  for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(e.Current())));
  return tolerance;
}

// How far past its domain a p-curve may run and how long a (u, v) gap may be, as a fraction of
// the domain diagonal: beyond this a face is skipped rather than moved (a gap that is small in 3D
// but long in (u, v), along a pole, would otherwise slide a curve end across the face).
constexpr double kMaxUvRepair = 1e-3;

struct FaceTrimFigures {
  double largest_gap = 0;     // (u, v), before closing
  double largest_excess = 0;  // (u, v), bound of clamp_change
};

// A p-curve and its clamp_change bound.
struct EdgeCurve {
  Handle(Geom2d_BSplineCurve) curve;
  double change;
};

// The face's wires as loops of p-curves, the outer wire first, each edge's p-curve in wire order
// as a non-periodic 2D B-spline running in the wire's direction (seam edges twice, once per
// orientation; a degenerated edge's p-curve closes a pole).
Loops face_loops(const TopoDS_Face& face) {
  std::vector<TopoDS_Wire> wires;
  const TopoDS_Wire outer = BRepTools::OuterWire(face);
  if (!outer.IsNull()) wires.push_back(outer);
  for (TopExp_Explorer e(face, TopAbs_WIRE); e.More(); e.Next())
    if (!e.Current().IsSame(outer)) wires.push_back(TopoDS::Wire(e.Current()));
  if (wires.empty()) throw FaceSkip{"face without wires", "no trimming loop"};
  Loops loops;
  for (const TopoDS_Wire& wire : wires) {
    const int loop = static_cast<int>(loops.size());
    int edges = 0;
    for (TopExp_Explorer e(wire, TopAbs_EDGE); e.More(); e.Next()) ++edges;
    std::vector<Handle(Geom2d_BSplineCurve)> curves;
    for (BRepTools_WireExplorer e(wire, face); e.More(); e.Next()) {
      const TopoDS_Edge& edge = e.Current();
      double first = 0, last = 0;
      const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, first, last);
      if (pcurve.IsNull())
        throw FaceSkip{"edge without p-curve", fmt::format("loop {} edge {}", loop, curves.size())};
      Handle(Geom2d_BSplineCurve) curve =
          Geom2dConvert::CurveToBSplineCurve(new Geom2d_TrimmedCurve(pcurve, first, last));
      if (curve->IsPeriodic()) curve->SetNotPeriodic();
      if (edge.Orientation() == TopAbs_REVERSED) curve->Reverse();
      curves.push_back(curve);
    }
    if (static_cast<int>(curves.size()) != edges)
      throw FaceSkip{
          "wire not connected",
          fmt::format("loop {}: {} of its {} edges follow each other", loop, curves.size(), edges)};
    loops.push_back(std::move(curves));
  }
  return loops;
}

// A curve inside the domain can have control points outside it (a circle's square of points):
// knot insertion, which leaves the curve unchanged, pulls them onto the curve. Refined while that
// pays: until the bound is within the tolerance, or stops shrinking (the curve itself runs
// outside), or the curve grows too long.
EdgeCurve refine_into(Handle(Geom2d_BSplineCurve) curve, const Domain& domain, double tolerance,
                      double repair) {
  double change = clamp_change(*curve, domain, tolerance);
  for (int round = 0;
       round < kMaxRefinements && change > tolerance && curve->NbPoles() < kMaxRefinedPoles;
       ++round) {
    const auto refined = Handle(Geom2d_BSplineCurve)::DownCast(curve->Copy());
    const TColStd_Array1OfReal knots = refined->Knots();
    for (int k = knots.Lower(); k < knots.Upper(); ++k)
      refined->InsertKnot(0.5 * (knots(k) + knots(k + 1)));
    const double refined_change = clamp_change(*refined, domain, tolerance);
    if (refined_change > 0.75 * change && change <= repair) break;
    curve = refined;
    change = refined_change;
  }
  return {curve, change};
}

// The face's (u, v) uncertainty from its 3D tolerance: OpenCASCADE's parameter resolution of it.
double face_resolution(const TopoDS_Face& face) {
  const GeomAdaptor_Surface adaptor(BRep_Tool::Surface(face));
  const double tolerance_3d = face_tolerance_3d(face);
  return std::max({adaptor.UResolution(tolerance_3d), adaptor.VResolution(tolerance_3d), 1e-12});
}

// The placed loops as the surface's trim.
//
// Each loop is closed by moving every curve's end onto the next curve's start -- never by a new
// segment -- when the two ends are within the model's tolerance: their surface points within
// twice the face's largest 3D vertex/edge tolerance (each end lies within it of the vertex they
// share), and the (u, v) gap within kMaxUvRepair. Control points still outside the domain
// (within the tolerance of its edge after placement, or a circle's square of points) are moved
// onto its edge when that changes the curve by at most kMaxUvRepair beyond its retraction onto
// the domain (clamp_change; the curve refined first until it is within that), so the trimmed
// region changes at most that close to where the curve leaves the domain.
// Trim::tolerance is the face's (u, v) uncertainty: the largest of OpenCASCADE's parameter
// resolution of the 3D tolerance, the gaps closed and the distances moved.
FaceTrimFigures face_trim(const TopoDS_Face& face, const Geom_BSplineSurface& bspline,
                          const Placement& placed, const Loops& loops, Surface& surface) {
  const double tolerance_3d = face_tolerance_3d(face);
  const double resolution = face_resolution(face);
  const double repair = kMaxUvRepair * domain_diagonal(surface);
  const Domain domain{surface.u_min(), surface.u_max(), surface.v_min(), surface.v_max()};
  Trim trim;
  FaceTrimFigures figures;
  for (std::size_t loop = 0; loop < loops.size(); ++loop) {
    TrimLoop out;
    for (std::size_t index = 0; index < loops[loop].size(); ++index) {
      const auto [curve, change] = refine_into(loops[loop][index], domain, resolution, repair);
      if (!(change <= repair))
        throw FaceSkip{"p-curve outside the surface's domain",
                       fmt::format("loop {} curve {}: moving it onto the domain changes it by "
                                   "{:.3g} (u,v) > {:.3g}",
                                   loop, index, change, repair)};
      figures.largest_excess = std::max(figures.largest_excess, change);
      out.curves.push_back(to_trim_curve(*curve));
    }
    for (std::size_t c = 0; c < out.curves.size(); ++c) {
      Point2& end = out.curves[c].points.back();
      const Point2& start = out.curves[(c + 1) % out.curves.size()].points.front();
      const double gap = std::hypot(end[0] - start[0], end[1] - start[1]);
      // The face's own surface: in any period, and past a non-periodic end as OpenCASCADE
      // continues it -- the surface the placed curves lie on.
      const double gap_3d = face_point(bspline, placed, end[0], end[1])
                                .Distance(face_point(bspline, placed, start[0], start[1]));
      if (!(gap <= repair && gap_3d <= 2 * tolerance_3d))
        throw FaceSkip{"loop not closed",
                       fmt::format("loop {} gap after curve {}: {:.3g} (u,v), {:.3g} in 3D > "
                                   "2 x tolerance {:.3g}",
                                   loop, c, gap, gap_3d, tolerance_3d)};
      figures.largest_gap = std::max(figures.largest_gap, gap);
      end = start;
    }
    for (TrimCurve& curve : out.curves)
      for (Point2& p : curve.points) p = domain.clamp(p);
    trim.loops.push_back(std::move(out));
  }
  trim.tolerance = std::max({resolution, figures.largest_gap, figures.largest_excess});
  surface.trim = std::move(trim);
  return figures;
}

}  // namespace

CadImport import_cad_model(const std::filesystem::path& path, const CadImportOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CadImport result;
  CadImportReport& report = result.report;
  report.file = path.string();
  report.format = std::string(cad::model_format(path));
  const TopoDS_Shape shape = cad::read_model(path);
  const cad::ConvertedFaces converted = cad::convert_faces(shape);
  report.faces_read = static_cast<int>(converted.faces.size());
  result.scene.name = path.stem().string();

  for (std::size_t k = 0; k < converted.faces.size(); ++k) {
    const std::string name = fmt::format("face-{}", k);
    std::optional<FaceSkip> skip;
    if (!converted.errors[k].empty()) skip = FaceSkip{"conversion failed", converted.errors[k]};
    Surface surface;
    double deviation = 0;
    FaceTrimFigures figures;
    Placement placed;
    if (!skip) {
      const std::string failure = cad::run_guarded([&] {
        try {
          const TopoDS_Face& face = converted.faces[k];
          const Handle(Geom_BSplineSurface) bspline = face_bspline(face);
          Loops loops = face_loops(face);
          // The first route that imports the face exactly wins; a skip names every route's
          // reason.
          std::optional<FaceSkip> failed;
          for (const Extend extend :
               {Extend::where_curves_leave, Extend::to_control_points, Extend::never}) {
            placed = place_loops(*bspline, loops, face_resolution(face), extend);
            try {
              surface = face_surface(face, *bspline, placed, deviation);
              figures = face_trim(face, *bspline, placed, loops, surface);
              failed.reset();
              break;
            } catch (const FaceSkip& route) {
              if (!failed)
                failed = route;
              else if (route.reason != failed->reason || route.detail != failed->detail)
                failed->detail += "; then " + route.reason + ": " + route.detail;
            }
          }
          if (failed) throw *failed;
          surface.name = name;
          validate_surface(surface, static_cast<int>(result.scene.surfaces.size()), report.file);
        } catch (const FaceSkip& face_skip) {
          skip = face_skip;
        } catch (const ValidationError& error) {
          skip = FaceSkip{"invalid as a scene surface", error.field() + ": " + error.rule()};
        }
      });
      if (!failure.empty()) skip = FaceSkip{"OpenCASCADE failed", failure};
    }
    if (skip) {
      ++report.skipped[skip->reason];
      report.warnings.push_back(
          fmt::format("{}: {}: skipped {}: {}", report.file, name, skip->reason, skip->detail));
      if (options.warn) options.warn(report.warnings.back());
      continue;
    }
    ++report.faces_converted;
    for (const std::string& route : placed.routes) ++report.placed[route];
    report.loops += static_cast<int>(surface.trim->loops.size());
    for (const TrimLoop& loop : surface.trim->loops)
      report.curves += static_cast<int>(loop.curves.size());
    report.largest_closure_gap = std::max(report.largest_closure_gap, figures.largest_gap);
    report.largest_domain_excess = std::max(report.largest_domain_excess, figures.largest_excess);
    report.largest_surface_deviation = std::max(report.largest_surface_deviation, deviation);
    ++report.degrees[fmt::format("{}x{}", surface.degree_u, surface.degree_v)];
    result.scene.surfaces.push_back(std::move(surface));
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (options.strict && report.faces_skipped() > 0)
    throw InputError(fmt::format("{}: --strict: {} of {} faces skipped (first: {})", report.file,
                                 report.faces_skipped(), report.faces_read,
                                 report.warnings.front()));
  if (result.scene.surfaces.empty())
    throw InputError(fmt::format("{}: every one of its {} faces was skipped (first: {})",
                                 report.file, report.faces_read, report.warnings.front()));
  result.scene.description = fmt::format(
      "imported from {} ({}): {} of {} faces as trimmed NURBS surfaces", path.filename().string(),
      report.format, report.faces_converted, report.faces_read);
  validate_scene(result.scene, report.file);
  return result;
}

}  // namespace nurbs
