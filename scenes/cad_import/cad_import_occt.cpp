// The importer with OpenCASCADE: each converted face -> one Surface with its trim, checked.
#include <fmt/format.h>

#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Geom2dConvert.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomAdaptor_Surface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <chrono>
#include <cmath>
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

// The converted face's surface, made non-periodic with its parameters kept, as a Surface; then
// checked against OpenCASCADE's evaluation of the periodic original.
Surface face_surface(const TopoDS_Face& face, double& deviation) {
  Handle(Geom_Surface) geometry = BRep_Tool::Surface(face);  // with the face's location applied
  if (auto trimmed = Handle(Geom_RectangularTrimmedSurface)::DownCast(geometry))
    geometry = trimmed->BasisSurface();
  const auto bspline = Handle(Geom_BSplineSurface)::DownCast(geometry);
  if (bspline.IsNull())
    throw FaceSkip{"not a B-spline after conversion", geometry->DynamicType()->Name()};
  double u0, u1, v0, v1;
  bspline->Bounds(u0, u1, v0, v1);
  // SetNotPeriodic keeps the parameters but leaves unclamped end knots; Segment over the same
  // bounds clamps them (knot insertion: the surface and its parameters unchanged).
  const auto flat = Handle(Geom_BSplineSurface)::DownCast(bspline->Copy());
  if (flat->IsUPeriodic()) flat->SetUNotPeriodic();
  if (flat->IsVPeriodic()) flat->SetVNotPeriodic();
  if (bspline->IsUPeriodic() || bspline->IsVPeriodic()) flat->Segment(u0, u1, v0, v1);
  Surface surface = to_surface(*flat);

  if (surface.u_min() != u0 || surface.u_max() != u1 || surface.v_min() != v0 ||
      surface.v_max() != v1)
    throw FaceSkip{
        "parameters changed by the conversion",
        fmt::format("domain [{}, {}] x [{}, {}] became [{}, {}] x [{}, {}]", u0, u1, v0, v1,
                    surface.u_min(), surface.u_max(), surface.v_min(), surface.v_max())};
  SurfaceSamples samples;
  samples.u = grid_parameters(u0, u1, kCheckGrid);
  samples.v = grid_parameters(v0, v1, kCheckGrid);
  Scene one{"check", "", {surface}};
  one.surfaces.front().name = "check";
  const ReferenceSurface ours = evaluate_reference(one, {samples}, false).front();
  double largest = 0;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    const gp_Pnt p = bspline->Value(samples.u_of(k), samples.v_of(k));
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

// The p-curve of `edge` on `face` as a non-periodic 2D B-spline running in the wire's direction.
// A curve inside the domain can have control points outside it (a circle's square of points):
// knot insertion, which leaves the curve unchanged, pulls them onto the curve first.
EdgeCurve edge_curve(const TopoDS_Edge& edge, const TopoDS_Face& face, const Domain& domain,
                     double tolerance, double repair, int loop, int index) {
  double first = 0, last = 0;
  const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, first, last);
  if (pcurve.IsNull())
    throw FaceSkip{"edge without p-curve", fmt::format("loop {} edge {}", loop, index)};
  Handle(Geom2d_BSplineCurve) curve =
      Geom2dConvert::CurveToBSplineCurve(new Geom2d_TrimmedCurve(pcurve, first, last));
  if (curve->IsPeriodic()) curve->SetNotPeriodic();
  if (edge.Orientation() == TopAbs_REVERSED) curve->Reverse();
  // Refined while that pays: until the bound is within the tolerance, or stops shrinking (the
  // curve itself runs outside), or the curve grows too long.
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

// The face's wires as trimming loops, the outer wire first, each edge's p-curve in wire order
// (seam edges twice, once per orientation; a degenerated edge's p-curve closes a pole).
//
// Each loop is closed by moving every curve's end onto the next curve's start -- never by a new
// segment -- when the two ends are within the model's tolerance: their surface points within
// twice the face's largest 3D vertex/edge tolerance (each end lies within it of the vertex they
// share), and the (u, v) gap within kMaxUvRepair. Control
// points outside the domain (after refinement: the curve itself runs outside, as OpenCASCADE
// allows) are moved onto its edge when that changes the curve by at most kMaxUvRepair beyond its
// retraction onto the domain (clamp_change; the curve refined first until it is within that), so
// the trimmed region changes at most that close to where the curve leaves the domain.
// Trim::tolerance is the face's (u, v) uncertainty: the largest of OpenCASCADE's parameter
// resolution of the 3D tolerance, the gaps closed and the distances moved.
FaceTrimFigures face_trim(const TopoDS_Face& face, Surface& surface) {
  const double tolerance_3d = face_tolerance_3d(face);
  const GeomAdaptor_Surface adaptor(BRep_Tool::Surface(face));
  const double resolution =
      std::max({adaptor.UResolution(tolerance_3d), adaptor.VResolution(tolerance_3d), 1e-12});
  const double repair = kMaxUvRepair * domain_diagonal(surface);
  const Domain domain{surface.u_min(), surface.u_max(), surface.v_min(), surface.v_max()};
  std::vector<TopoDS_Wire> wires;
  const TopoDS_Wire outer = BRepTools::OuterWire(face);
  if (!outer.IsNull()) wires.push_back(outer);
  for (TopExp_Explorer e(face, TopAbs_WIRE); e.More(); e.Next())
    if (!e.Current().IsSame(outer)) wires.push_back(TopoDS::Wire(e.Current()));
  if (wires.empty()) throw FaceSkip{"face without wires", "no trimming loop"};

  Trim trim;
  FaceTrimFigures figures;
  for (const TopoDS_Wire& wire : wires) {
    const int loop = static_cast<int>(trim.loops.size());
    int edges = 0;
    for (TopExp_Explorer e(wire, TopAbs_EDGE); e.More(); e.Next()) ++edges;
    TrimLoop out;
    for (BRepTools_WireExplorer e(wire, face); e.More(); e.Next()) {
      const int index = static_cast<int>(out.curves.size());
      const auto [curve, change] =
          edge_curve(e.Current(), face, domain, resolution, repair, loop, index);
      if (!(change <= repair))
        throw FaceSkip{"p-curve outside the surface's domain",
                       fmt::format("loop {} curve {}: moving it onto the domain changes it by "
                                   "{:.3g} (u,v) > {:.3g}",
                                   loop, index, change, repair)};
      figures.largest_excess = std::max(figures.largest_excess, change);
      out.curves.push_back(to_trim_curve(*curve));
    }
    if (static_cast<int>(out.curves.size()) != edges)
      throw FaceSkip{"wire not connected",
                     fmt::format("loop {}: {} of its {} edges follow each other", loop,
                                 out.curves.size(), edges)};
    for (std::size_t c = 0; c < out.curves.size(); ++c) {
      Point2& end = out.curves[c].points.back();
      const Point2& start = out.curves[(c + 1) % out.curves.size()].points.front();
      const double gap = std::hypot(end[0] - start[0], end[1] - start[1]);
      const double gap_3d =
          adaptor.Value(end[0], end[1]).Distance(adaptor.Value(start[0], start[1]));
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
    if (!skip) {
      const std::string failure = cad::run_guarded([&] {
        try {
          surface = face_surface(converted.faces[k], deviation);
          figures = face_trim(converted.faces[k], surface);
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
