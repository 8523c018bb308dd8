// The imported scene held up against OpenCASCADE as a peer: each surface against OpenCASCADE's
// evaluation of the converted face's surface, each loop's closure, and the reference's exact
// classification against BRepClass_FaceClassifier outside the band. Shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <BRepClass_FaceClassifier.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <algorithm>
#include <array>
#include <cmath>
#include <gp_Vec2d.hxx>
#include <string>

#include "reference/curve.h"
#include "reference/reference_evaluator.h"
#include "reference/trim_classify.h"
#include "scenes/cad_import/cad_import.h"
#include "scenes/cad_import/occt_model.h"

namespace nurbs::test {

inline double box_diagonal(const Surface& s) {
  Point3 lo = s.points.front(), hi = lo;
  for (const Point3& p : s.points)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

struct PeerFigures {
  double largest_deviation = 0;  // relative to the control points' bounding-box diagonal
  long compared = 0, agreed = 0, in_band = 0;
  // Disagreements outside the bounding box of the face's p-curves, where the face is not and
  // the reference says so: OpenCASCADE's classifier is wrong there (seen on the last grid row of
  // bearing.iges, on the domain's edge).
  long peer_wrong = 0;
  // ... or where the face's own p-curves, as a fine polygon (polygon_class), classify the sample
  // as the reference does.
  // Disagreements farther from the trim boundary than the importer moved it (closing gaps, moving
  // p-curves into the domain): bounded by the report's largest gap plus largest change.
  long unexplained = 0;
  std::string first_unexplained;  // face, (u, v), distance to the boundary, both classes
  // The imported trim on the imported surface against the model's own 3D edges: the largest
  // distance from the surface point of a trim-curve parameter to the face's nearest edge, over
  // what the model's tolerance and the importer's (u, v) repairs allow there (<= 1: placed
  // right; periods, seams and extensions included).
  double largest_edge_ratio = 0;
  std::string worst_edge;  // face, curve, distance, allowance
};

// A third opinion where the reference and OpenCASCADE's classifier disagree on a face without
// periodic directions: the even-odd class of (u, v) against the face's own p-curves (OpenCASCADE's,
// not the import's) as polygons of 4096 points an edge; -1 where (u, v) lies within `band` plus
// the polygon's chord error of a p-curve (the polygon cannot tell).
inline int polygon_class(const TopoDS_Face& face, double u, double v, double band) {
  constexpr int kPoints = 4096;
  bool inside = false;
  double nearest = HUGE_VAL, chord = 0;
  for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next())
    for (TopExp_Explorer e(w.Current(), TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
      double first, last;
      const Handle(Geom2d_Curve) c = BRep_Tool::CurveOnSurface(edge, face, first, last);
      if (c.IsNull()) return -1;
      gp_Pnt2d a = c->Value(first);
      for (int k = 1; k <= kPoints; ++k) {
        const gp_Pnt2d b = c->Value(first + (last - first) * k / kPoints);
        // Crossings of the ray to +u; orientation does not matter to even-odd.
        if ((a.Y() > v) != (b.Y() > v) &&
            u < a.X() + (v - a.Y()) * (b.X() - a.X()) / (b.Y() - a.Y()))
          inside = !inside;
        const gp_Vec2d ab(a, b), ap(a, gp_Pnt2d(u, v));
        const double t = std::clamp(ab.Dot(ap) / std::max(ab.SquareMagnitude(), 1e-300), 0.0, 1.0);
        nearest = std::min(nearest, (ap - t * ab).Magnitude());
        // The curve between two polygon points strays from the chord by about a quarter of the
        // chord's turn; bounded here by the chord length itself.
        chord = std::max(chord, ab.Magnitude());
        a = b;
      }
    }
  return nearest > band + chord ? int(inside) : -1;
}

// The periods of the face's surface the importer may have placed p-curves across: a periodic
// direction's, or a closed one's where the imported domain is longer than the surface ("closed
// direction wrapped"); 0 elsewhere.
inline std::array<double, 2> wrap_periods(const Geom_Surface& g, const Surface& s) {
  double u0, u1, v0, v1;
  g.Bounds(u0, u1, v0, v1);
  std::array<double, 2> periods{0, 0};
  if (g.IsUPeriodic() || (g.IsUClosed() && s.u_max() - s.u_min() > u1 - u0 + 1e-9))
    periods[0] = g.IsUPeriodic() ? g.UPeriod() : u1 - u0;
  if (g.IsVPeriodic() || (g.IsVClosed() && s.v_max() - s.v_min() > v1 - v0 + 1e-9))
    periods[1] = g.IsVPeriodic() ? g.VPeriod() : v1 - v0;
  return periods;
}

// The face's surface at (u, v) in whatever period (u, v) lies.
inline gp_Pnt wrapped_value(const Geom_Surface& g, const std::array<double, 2>& periods, double u,
                            double v, gp_Vec* du = nullptr, gp_Vec* dv = nullptr) {
  double u0, u1, v0, v1;
  g.Bounds(u0, u1, v0, v1);
  if (periods[0] > 0) u = std::clamp(u - std::floor((u - u0) / periods[0]) * periods[0], u0, u1);
  if (periods[1] > 0) v = std::clamp(v - std::floor((v - v0) / periods[1]) * periods[1], v0, v1);
  gp_Pnt p;
  gp_Vec a, b;
  g.D1(u, v, p, a, b);
  if (du) *du = a;
  if (dv) *dv = b;
  return p;
}

// The trim curves of `s` mapped by `s` at `per_curve` parameters each, against the 3D curves of
// `face`'s edges. The allowance: twice the face's largest vertex/edge tolerance (each curve end
// within it of the shared vertex) plus the importer's largest (u, v) repair times the surface's
// largest first derivative on a 17x17 grid (an estimate of its Lipschitz constant, x1.5).
inline void check_trim_on_edges(const Surface& s, const TopoDS_Face& face, double uv_repair,
                                int per_curve, PeerFigures& figures) {
  std::vector<Handle(Geom_Curve)> edges;
  double tolerance = 0;
  for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(edge));
    double first, last;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);
    if (!curve.IsNull()) edges.push_back(new Geom_TrimmedCurve(curve, first, last));
  }
  for (TopExp_Explorer e(face, TopAbs_VERTEX); e.More(); e.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(e.Current())));
  if (edges.empty()) return;  // degenerate edges only: nothing to measure against
  SurfaceSamples at{false, {}, {}};
  for (const TrimLoop& loop : s.trim->loops)
    for (const TrimCurve& t : loop.curves) {
      Curve c;
      c.degree = t.degree;
      c.knots = t.knots;
      for (std::size_t i = 0; i < t.points.size(); ++i)
        c.homogeneous.push_back(
            {t.points[i][0] * t.weights[i], t.points[i][1] * t.weights[i], 0, t.weights[i]});
      for (int k = 0; k < per_curve; ++k) {
        const Vec3<double> p =
            curve_point(c, c.start() + (c.end() - c.start()) * (k + 0.5) / per_curve);
        at.u.push_back(p[0]);
        at.v.push_back(p[1]);
      }
    }
  Scene one{"edges", "", {s}};
  one.surfaces.front().trim.reset();
  const ReferenceSurface ours = evaluate_reference(one, {at}, false).front();
  const Handle(Geom_Surface) geometry = BRep_Tool::Surface(face);
  const std::array<double, 2> periods = wrap_periods(*geometry, s);
  double slope = 0;
  for (double u : grid_parameters(s.u_min(), s.u_max(), 17))
    for (double v : grid_parameters(s.v_min(), s.v_max(), 17)) {
      gp_Vec du, dv;
      wrapped_value(*geometry, periods, u, v, &du, &dv);
      slope = std::max({slope, du.Magnitude(), dv.Magnitude()});
    }
  const double allowance = 2 * tolerance + 1.5 * slope * uv_repair + 1e-9 * box_diagonal(s);
  for (std::size_t k = 0; k < at.count(); ++k) {
    const Point3& q = ours.positions[k];
    double nearest = HUGE_VAL;
    for (const auto& edge : edges) {
      GeomAPI_ProjectPointOnCurve projection(gp_Pnt(q[0], q[1], q[2]), edge);
      double d = edge->Value(edge->FirstParameter()).Distance(gp_Pnt(q[0], q[1], q[2]));
      d = std::min(d, edge->Value(edge->LastParameter()).Distance(gp_Pnt(q[0], q[1], q[2])));
      if (projection.NbPoints() > 0) d = std::min(d, projection.LowerDistance());
      nearest = std::min(nearest, d);
    }
    if (nearest / allowance > figures.largest_edge_ratio) {
      figures.largest_edge_ratio = nearest / allowance;
      figures.worst_edge = s.name + " trim point " + std::to_string(k) + " at (" +
                           std::to_string(at.u[k]) + ", " + std::to_string(at.v[k]) +
                           "): " + std::to_string(nearest) + " from the nearest edge, allowed " +
                           std::to_string(allowance);
    }
  }
}

// `grid`^2 samples per face; the band is 1e-7 of the face's domain diagonal.
inline PeerFigures check_against_occt(const std::filesystem::path& path, const CadImport& imported,
                                      int grid) {
  const cad::ConvertedFaces peers = cad::convert_faces(cad::read_model(path));
  PeerFigures figures;
  std::vector<SurfaceSamples> samples;
  for (const Surface& s : imported.scene.surfaces)
    samples.push_back({true, grid_parameters(s.u_min(), s.u_max(), grid),
                       grid_parameters(s.v_min(), s.v_max(), grid)});
  const std::vector<ReferenceSurface> reference =
      evaluate_reference(imported.scene, samples, false);
  for (std::size_t i = 0; i < imported.scene.surfaces.size(); ++i) {
    const Surface& s = imported.scene.surfaces[i];
    const std::size_t k = std::stoul(s.name.substr(s.name.find('-') + 1));
    const TopoDS_Face& face = peers.faces.at(k);
    EXPECT_EQ(s.reversed, face.Orientation() == TopAbs_REVERSED) << s.name;
    const Handle(Geom_Surface) geometry = BRep_Tool::Surface(face);
    check_trim_on_edges(s, face,
                        imported.report.largest_domain_excess + imported.report.largest_closure_gap,
                        8, figures);
    const std::array<double, 2> periods = wrap_periods(*geometry, s);
    for (const TrimLoop& loop : s.trim->loops)
      for (std::size_t c = 0; c < loop.curves.size(); ++c)
        EXPECT_EQ(loop.curves[c].points.back(),
                  loop.curves[(c + 1) % loop.curves.size()].points.front())
            << s.name << ": loop not closed after curve " << c;
    const double size = box_diagonal(s), band = 1e-7 * domain_diagonal(s);
    double box_u0, box_u1, box_v0, box_v1;
    BRepTools::UVBounds(face, box_u0, box_u1, box_v0, box_v1);
    for (std::size_t n = 0; n < samples[i].count(); ++n) {
      const double u = samples[i].u_of(n), v = samples[i].v_of(n);
      const gp_Pnt p = wrapped_value(*geometry, periods, u, v);
      const Point3& q = reference[i].positions[n];
      figures.largest_deviation = std::max(
          figures.largest_deviation, std::hypot(p.X() - q[0], p.Y() - q[1], p.Z() - q[2]) / size);
      if (reference[i].trim_distance[n] < band) {
        ++figures.in_band;
        continue;
      }
      // On a periodic surface the importer may have moved the loops by whole periods: the
      // sample is classified in every period that puts it within the face's p-curves' box
      // (OpenCASCADE's classifier works in the p-curves' own period), IN if any says so.
      // A direction unrolled over several periods holds each period once: its loops were
      // moved by the one whole number of periods that takes the domain's origin to at most a
      // period before the p-curves' box.
      const double period_u = periods[0], period_v = periods[1];
      const bool unrolled_u = period_u > 0 && s.u_max() - s.u_min() > 1.5 * period_u;
      const bool unrolled_v = period_v > 0 && s.v_max() - s.v_min() > 1.5 * period_v;
      const int fixed_u = unrolled_u ? int(std::floor((box_u0 - s.u_min()) / period_u + 1e-9)) : 0;
      const int fixed_v = unrolled_v ? int(std::floor((box_v0 - s.v_min()) / period_v + 1e-9)) : 0;
      TopAbs_State state = TopAbs_OUT;
      bool outside_box = true;
      for (int ku = period_u > 0 && !unrolled_u ? -3 : fixed_u;
           ku <= (period_u > 0 && !unrolled_u ? 3 : fixed_u); ++ku)
        for (int kv = period_v > 0 && !unrolled_v ? -3 : fixed_v;
             kv <= (period_v > 0 && !unrolled_v ? 3 : fixed_v); ++kv) {
          const double uk = u + ku * period_u, vk = v + kv * period_v;
          const bool outside =
              uk < box_u0 - band || uk > box_u1 + band || vk < box_v0 - band || vk > box_v1 + band;
          const bool shifted = (period_u > 0 && !unrolled_u) || (period_v > 0 && !unrolled_v);
          if (outside && shifted) continue;
          outside_box = outside;
          const TopAbs_State s = BRepClass_FaceClassifier(face, gp_Pnt2d(uk, vk), 1e-9).State();
          if (s == TopAbs_IN || (s == TopAbs_ON && state == TopAbs_OUT)) state = s;
        }
      if (state == TopAbs_ON) {
        ++figures.in_band;
        continue;
      }
      ++figures.compared;
      if ((state == TopAbs_IN) == (reference[i].inside[n] == 1))
        ++figures.agreed;
      else if (outside_box && reference[i].inside[n] == 0)
        ++figures.peer_wrong;
      else if (periods[0] == 0 && periods[1] == 0 &&
               polygon_class(face, u, v, band) == (reference[i].inside[n] == 1 ? 1 : 0))
        ++figures.peer_wrong;
      else if (reference[i].trim_distance[n] > imported.report.largest_domain_excess +
                                                   imported.report.largest_closure_gap + band &&
               figures.unexplained++ == 0)
        figures.first_unexplained =
            s.name + " at (" + std::to_string(u) + ", " + std::to_string(v) + "), " +
            std::to_string(reference[i].trim_distance[n]) + " from the boundary: reference " +
            (reference[i].inside[n] ? "in" : "out") + ", OpenCASCADE " +
            (state == TopAbs_IN ? "in" : "out");
    }
  }
  return figures;
}

}  // namespace nurbs::test
