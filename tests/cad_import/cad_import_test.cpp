// The importer on OpenCASCADE's hammer and on shapes built here (periodic, seam-carrying,
// reversed), checked against OpenCASCADE as a peer; bad model files refused by the CLI.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepLib.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GCE2d_MakeSegment.hxx>
#include <Geom2d_Circle.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Plane.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <STEPControl_Writer.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <cstdio>

#include "../cli/run_cli.h"
#include "occt_peer_check.h"
#include "scenes/builtin_scenes.h"
#include "scenes/scene_json.h"

namespace nurbs::test {
namespace {

std::filesystem::path hammer_path() {
  for (const char* p : {NURBSBENCH_SOURCE_DIR "/../shared/data/models/hammer.iges",
                        "/usr/share/opencascade/data/iges/hammer.iges"})
    if (std::filesystem::exists(p)) return p;
  return {};
}

void expect_agreement(const PeerFigures& f, const std::string& what) {
  std::printf(
      "%s: surface deviation %.3g, classification agrees on %ld of %ld samples outside "
      "the band (%ld in it), trim on the model's edges %.3g of the allowance\n",
      what.c_str(), f.largest_deviation, f.agreed, f.compared, f.in_band, f.largest_edge_ratio);
  EXPECT_LE(f.largest_deviation, 1e-9) << what;
  EXPECT_GT(f.compared, 0) << what;
  EXPECT_EQ(f.unexplained, 0) << what << ": " << f.first_unexplained;
  EXPECT_LE(f.largest_edge_ratio, 1.0) << what << ": " << f.worst_edge;
}

TEST(CadImport, HammerMatchesOpenCascade) {
  const std::filesystem::path path = hammer_path();
  if (path.empty()) GTEST_SKIP() << "hammer.iges not found (shared data or Debian occt-misc)";
  const CadImport imported = import_cad_model(path);
  std::printf("%s", imported.report.summary().c_str());
  EXPECT_EQ(imported.report.faces_read, 45);
  EXPECT_EQ(imported.scene.surfaces.size(), std::size_t(imported.report.faces_converted));
  expect_agreement(check_against_occt(path, imported, 32), "hammer");
  // Written as nurbs-scene/2 and read back unchanged, trims and orientation included; the
  // committed built-in hammer is this import (regenerate it when the importer changes).
  const std::string json = scene_to_json(imported.scene);
  EXPECT_NE(json.find("\"format\": \"nurbs-scene/2\""), std::string::npos);
  const Scene back = parse_scene_json(json, "hammer.json");
  ASSERT_EQ(back.surfaces.size(), imported.scene.surfaces.size());
  for (std::size_t k = 0; k < back.surfaces.size(); ++k) {
    ASSERT_TRUE(back.surfaces[k].trim);
    EXPECT_EQ(back.surfaces[k].trim->loops.size(), imported.scene.surfaces[k].trim->loops.size());
    EXPECT_EQ(back.surfaces[k].reversed, imported.scene.surfaces[k].reversed);
  }
  EXPECT_EQ(scene_to_json(back), json);
  EXPECT_EQ(scene_to_json(*make_builtin_scene("hammer")), json)
      << "scenes/data/hammer.json is not the current import of " << path;
}

// A cylinder (periodic in u, seam), a sphere (seam, degenerated pole edges), a torus (periodic
// both ways, two seams) and a reversed copy of the cylinder, written as one BREP file.
TEST(CadImport, PeriodicSeamAndReversedFaces) {
  TempDir dir;
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  const TopoDS_Shape cylinder = BRepPrimAPI_MakeCylinder(2.0, 3.0).Shape();
  builder.Add(compound, cylinder);
  builder.Add(compound, BRepPrimAPI_MakeSphere(gp_Pnt(10, 0, 0), 1.5).Shape());
  builder.Add(compound, BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 10, 0), gp::DZ()), 3, 1).Shape());
  builder.Add(compound, cylinder.Reversed());
  const std::string path = dir / "shapes.brep";
  ASSERT_TRUE(BRepTools::Write(compound, path.c_str()));

  const CadImport imported = import_cad_model(path);
  EXPECT_EQ(imported.report.faces_skipped(), 0) << imported.report.summary();
  // 3 cylinder faces, 1 sphere, 1 torus, 3 reversed cylinder faces.
  ASSERT_EQ(imported.scene.surfaces.size(), 8u);
  const Surface& side = imported.scene.surfaces[0];
  const Surface& sphere = imported.scene.surfaces[3];
  const Surface& torus = imported.scene.surfaces[4];
  // Points on the analytic shapes: independent of OpenCASCADE's evaluation.
  const std::vector<ReferenceSurface> on =
      evaluate_reference(imported.scene, sample_parameters(imported.scene, Sampling{}), false);
  for (const Point3& p : on[0].positions) EXPECT_NEAR(std::hypot(p[0], p[1]), 2.0, 1e-12);
  for (const Point3& p : on[3].positions)
    EXPECT_NEAR(std::hypot(p[0] - 10, p[1], p[2]), 1.5, 1e-12);
  for (const Point3& p : on[4].positions)
    EXPECT_NEAR(std::hypot(std::hypot(p[0], p[1] - 10) - 3, p[2]), 1.0, 1e-12);
  // Seam edges kept twice: each loop has a curve on each of u = u_min and u = u_max (up to the
  // conversion's rounding).
  auto on_line = [](const TrimCurve& c, int axis, double value) {
    return std::all_of(c.points.begin(), c.points.end(),
                       [&](const Point2& p) { return std::abs(p[axis] - value) < 1e-12; });
  };
  for (const Surface* s : {&side, &sphere, &torus}) {
    ASSERT_TRUE(s->trim);
    const auto& curves = s->trim->loops.at(0).curves;
    EXPECT_TRUE(std::any_of(curves.begin(), curves.end(), [&](const TrimCurve& c) {
      return on_line(c, 0, s->u_min());
    })) << s->name;
    EXPECT_TRUE(std::any_of(curves.begin(), curves.end(), [&](const TrimCurve& c) {
      return on_line(c, 0, s->u_max());
    })) << s->name;
  }
  // The sphere's wire: seam twice and the two degenerated pole edges.
  EXPECT_EQ(sphere.trim->loops.at(0).curves.size(), 4u);
  // Orientation as the file has it, the reversed copy's faces flipped.
  const std::vector<TopoDS_Face> faces = cad::model_faces(cad::read_model(path));
  for (std::size_t k = 0; k < 8; ++k)
    EXPECT_EQ(imported.scene.surfaces[k].reversed, faces[k].Orientation() == TopAbs_REVERSED)
        << "face-" << k;
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NE(imported.scene.surfaces[k].reversed, imported.scene.surfaces[k + 5].reversed);
  // The side's normal points away from the axis (the solid's outside), into it on the reversed
  // copy (its outside is the cylinder's inside).
  const std::vector<ReferenceSurface> normals =
      evaluate_reference(imported.scene, sample_parameters(imported.scene, Sampling{}), true);
  for (std::size_t k : {0u, 5u})
    for (std::size_t n = 0; n < normals[k].normals.size(); ++n) {
      const Point3& p = normals[k].positions[n];
      const Point3& normal = normals[k].normals[n];
      const double outward = (normal[0] * p[0] + normal[1] * p[1]) / std::hypot(p[0], p[1]);
      EXPECT_NEAR(outward, k == 0 ? 1.0 : -1.0, 1e-12) << "face-" << k;
    }
  expect_agreement(check_against_occt(path, imported, 48), "cylinder, sphere, torus, reversed");
}

TEST(CadImport, BadModelFilesAreRefused) {
  TempDir dir;
  const std::string step = dir / "cylinder.step", truncated = dir / "truncated.step";
  STEPControl_Writer writer;
  writer.Transfer(BRepPrimAPI_MakeCylinder(2.0, 3.0).Shape(), STEPControl_AsIs);
  ASSERT_EQ(writer.Write(step.c_str()), IFSelect_RetDone);
  const std::string text = read_text(step);
  write_text(truncated, text.substr(0, text.size() / 2));
  std::string garbage(4096, '\0');
  for (std::size_t k = 0; k < garbage.size(); ++k) garbage[k] = static_cast<char>(k * 131 % 251);
  write_text(dir / "garbage.igs", garbage);
  write_text(dir / "garbage.brep", garbage);
  const std::string edge = dir / "edge.brep", unknown = dir / "model.obj";
  ASSERT_TRUE(BRepTools::Write(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(1, 0, 0)).Edge(),
                               edge.c_str()));
  write_text(unknown, "v 0 0 0\n");

  EXPECT_EQ(run_cli({"import", step, "--out", dir / "ok.json"}).exit_code, 0);
  for (const std::string& bad : {dir / "missing.step", unknown, truncated, dir / "garbage.igs",
                                 dir / "garbage.brep", edge}) {
    const std::string out = dir / "out.json";
    const CliResult r = run_cli({"import", bad, "--out", out});
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_TRUE(is_one_error_line(r.err)) << r.err;
    EXPECT_NE(r.err.find(bad), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << bad;
    // The same file where a scene is expected.
    EXPECT_EQ(run_cli({"eval", "--scene", bad, "--strategy", "cpu-coxdeboor"}).exit_code, 2);
  }
}

// Periodic B-splines as OpenCASCADE makes them from a cylinder, a sphere and a torus (periodic in
// u; the torus in v too), the torus also raised to degree 12 as in the IGES model of issue 28.
Handle(Geom_BSplineSurface) periodic_cylinder() {
  return GeomConvert::SurfaceToBSplineSurface(new Geom_RectangularTrimmedSurface(
      new Geom_CylindricalSurface(gp_Ax3(), 2.0), 0.0, 3.0, Standard_False));
}
Handle(Geom_BSplineSurface) periodic_sphere() {
  return GeomConvert::SurfaceToBSplineSurface(new Geom_SphericalSurface(gp_Ax3(), 1.5));
}
Handle(Geom_BSplineSurface) periodic_torus(int degree) {
  const Handle(Geom_BSplineSurface) torus =
      GeomConvert::SurfaceToBSplineSurface(new Geom_ToroidalSurface(gp_Ax3(), 3.0, 1.0));
  if (degree > torus->UDegree()) torus->IncreaseDegree(degree, degree);
  return torus;
}

// A face of `surface` over [u0, u1] x [v0, v1], its p-curves then moved by (du, dv): whole
// periods (BRepBuilderAPI_MakeFace itself brings the parameters into the surface's period).
struct RangeFace {
  std::string what;
  Handle(Geom_BSplineSurface) surface;
  double u0, u1, v0, v1, du = 0, dv = 0;
};

TopoDS_Face make_range_face(const RangeFace& f) {
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(f.surface, f.u0, f.u1, f.v0, f.v1, 1e-9).Face();
  BRep_Builder builder;
  const gp_Vec2d by(f.du, f.dv);
  auto moved = [&](const Handle(Geom2d_Curve) & c) {
    return Handle(Geom2d_Curve)::DownCast(c->Translated(by));
  };
  TopTools_MapOfShape done;
  for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge edge = TopoDS::Edge(e.Current());
    if (!done.Add(edge.Oriented(TopAbs_FORWARD))) continue;
    double first, last;
    const double tolerance = BRep_Tool::Tolerance(edge);
    if (BRep_Tool::IsClosed(edge, face)) {  // a seam: both p-curves
      const auto forward =
          BRep_Tool::CurveOnSurface(TopoDS::Edge(edge.Oriented(TopAbs_FORWARD)), face, first, last);
      const auto reversed = BRep_Tool::CurveOnSurface(TopoDS::Edge(edge.Oriented(TopAbs_REVERSED)),
                                                      face, first, last);
      builder.UpdateEdge(TopoDS::Edge(edge.Oriented(TopAbs_FORWARD)), moved(forward),
                         moved(reversed), face, tolerance);
    } else {
      builder.UpdateEdge(edge, moved(BRep_Tool::CurveOnSurface(edge, face, first, last)), face,
                         tolerance);
    }
    builder.Range(edge, face, first, last);
  }
  return face;
}

// Faces whose p-curves lie 1 or 2 periods away from their periodic surface's domain (-2, -1,
// +1, +2), a full cylinder band (seam edges) one period away, a sphere wedge with its poles
// (degenerated edges) and a degree-12 torus face straddling the u seam (u in [-pi/2, pi/2] on a
// surface over [0, 2 pi]): every one imports, equal to OpenCASCADE's evaluation of the face's
// surface, classified as OpenCASCADE classifies, and covering the fraction of its domain the
// face's parameter ranges give (computed here from the construction, not from the import).
TEST(CadImport, PeriodicFacesInOtherPeriodsAndAcrossTheSeam) {
  TempDir dir;
  const double T = 2 * M_PI;
  std::vector<RangeFace> faces;
  for (int k : {-2, -1, 1, 2}) {
    faces.push_back({fmt::format("cylinder, u {:+} periods", k), periodic_cylinder(), 0.5, 2.5, 0.0,
                     3.0, k * T});
    faces.push_back({fmt::format("sphere, u {:+} periods, both poles", k), periodic_sphere(), 1.0,
                     4.0, -M_PI / 2, M_PI / 2, k * T});
    faces.push_back({fmt::format("torus, u {:+} and v {:+} periods", k, -k), periodic_torus(2), 0.5,
                     2.0, 1.0, 3.0, k * T, -k * T});
  }
  faces.push_back({"cylinder band, u +1 period (seam)", periodic_cylinder(), 0, T, 0.0, 3.0, T});
  faces.push_back(
      {"degree-12 torus across the u seam", periodic_torus(12), -M_PI / 2, M_PI / 2, 0.5, 2.5});
  faces.push_back({"torus across both seams", periodic_torus(2), -1.0, 1.0, T - 0.5, T + 0.5});
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  for (const RangeFace& f : faces) builder.Add(compound, make_range_face(f));
  const std::string path = dir / "periodic.brep";
  ASSERT_TRUE(BRepTools::Write(compound, path.c_str()));

  const CadImport imported = import_cad_model(path);
  std::printf("%s", imported.report.summary().c_str());
  EXPECT_EQ(imported.report.faces_skipped(), 0) << imported.report.summary();
  ASSERT_EQ(imported.scene.surfaces.size(), faces.size());
  EXPECT_GT(imported.report.placed.count("moved by whole periods"), 0u);
  EXPECT_GT(imported.report.placed.count("seam moved"), 0u);
  expect_agreement(check_against_occt(path, imported, 48), "faces in other periods");

  constexpr int kGrid = 64;
  std::vector<SurfaceSamples> samples;
  for (const Surface& s : imported.scene.surfaces)
    samples.push_back({true, grid_parameters(s.u_min(), s.u_max(), kGrid),
                       grid_parameters(s.v_min(), s.v_max(), kGrid)});
  const std::vector<ReferenceSurface> on = evaluate_reference(imported.scene, samples, false);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const Surface& s = imported.scene.surfaces[k];
    // A periodic direction's domain is one whole period (or the face's range where the
    // conversion trimmed it); the trim covers the face's share of it.
    double u0, u1, v0, v1;
    faces[k].surface->Bounds(u0, u1, v0, v1);
    const double expected = (faces[k].u1 - faces[k].u0) / (s.u_max() - s.u_min()) *
                            (faces[k].v1 - faces[k].v0) / (s.v_max() - s.v_min());
    EXPECT_NEAR(s.u_max() - s.u_min(), u1 - u0, 1e-9) << faces[k].what;
    const long inside = std::count(on[k].inside.begin(), on[k].inside.end(), 1);
    // Within a grid row or column per side of the face's rectangle: samples on the boundary
    // (the grid includes the domain's edges, which a full band's loop runs along) go either way.
    EXPECT_NEAR(double(inside) / (kGrid * kGrid), expected, 4.5 / kGrid) << faces[k].what;
  }
}

// A helical strip winding twice around a cylinder: a parallelogram in (u, v) over two periods
// of u on a periodic B-spline cylinder. It imports over two whole periods, on the model's edges,
// classified as OpenCASCADE classifies, covering the strip's share of the domain (from its
// construction). The closed, non-periodic case ("closed direction wrapped") is bottle.brep's
// thread in cad_models_test: built here on an analytic cylinder, OpenCASCADE's own conversion
// re-approximates the p-curves over one turn (BRepBuilderAPI_NurbsConvert), a face no importer
// could place.
TEST(CadImport, HelicalStripUnrolledOverTwoPeriods) {
  TempDir dir;
  const double T = 2 * M_PI, height = 0.5, rise = 2.0;
  const gp_Pnt2d corners[4] = {{0.3, 0.2},
                               {0.3 + 2 * T, 0.2 + rise},
                               {0.3 + 2 * T, 0.2 + rise + height},
                               {0.3, 0.2 + height}};
  auto strip_on = [&](const Handle(Geom_Surface) & surface) {
    BRepBuilderAPI_MakeWire wire;
    for (int k = 0; k < 4; ++k) {
      TopoDS_Edge edge = BRepBuilderAPI_MakeEdge(
                             GCE2d_MakeSegment(corners[k], corners[(k + 1) % 4]).Value(), surface)
                             .Edge();
      BRepLib::BuildCurves3d(edge);
      wire.Add(edge);
    }
    return BRepBuilderAPI_MakeFace(surface, wire.Wire()).Face();
  };
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  builder.Add(compound, strip_on(periodic_cylinder()));
  const std::string path = dir / "helical-strip.brep";
  ASSERT_TRUE(BRepTools::Write(compound, path.c_str()));

  const CadImport imported = import_cad_model(path);
  std::printf("%s", imported.report.summary().c_str());
  EXPECT_EQ(imported.report.faces_skipped(), 0) << imported.report.summary();
  ASSERT_EQ(imported.scene.surfaces.size(), 1u);
  EXPECT_EQ(imported.report.placed.at("unrolled over 2 periods"), 1);
  expect_agreement(check_against_occt(path, imported, 64), "helical strips");
  constexpr int kGrid = 96;
  std::vector<SurfaceSamples> samples;
  for (const Surface& s : imported.scene.surfaces) {
    EXPECT_NEAR(s.u_max() - s.u_min(), 2 * T, 1e-9);
    samples.push_back({true, grid_parameters(s.u_min(), s.u_max(), kGrid),
                       grid_parameters(s.v_min(), s.v_max(), kGrid)});
  }
  const std::vector<ReferenceSurface> on = evaluate_reference(imported.scene, samples, false);
  for (std::size_t k = 0; k < imported.scene.surfaces.size(); ++k) {
    const Surface& s = imported.scene.surfaces[k];
    const double expected = 2 * T * height / ((s.u_max() - s.u_min()) * (s.v_max() - s.v_min()));
    const long inside = std::count(on[k].inside.begin(), on[k].inside.end(), 1);
    EXPECT_NEAR(double(inside) / (kGrid * kGrid), expected, 2.0 / kGrid) << "face " << k;
    // Every point of the strip on the cylinder of radius 2.
    for (std::size_t n = 0; n < samples[k].count(); ++n)
      EXPECT_NEAR(std::hypot(on[k].positions[n][0], on[k].positions[n][1]), 2.0, 1e-12);
  }
}

// A bilinear patch on [0,1]^2 trimmed by a circle of radius 0.8 about its middle: the p-curve runs
// 0.3 past the domain, on the plane OpenCASCADE continues the patch to; the domain is extended to
// it and the face imports, the extension exactly that plane.
TEST(CadImport, PCurvePastTheDomainExtendsIt) {
  TempDir dir;
  // The plane z = 0 over [0,1]^2 as a degree-1 B-spline: x = u, y = v.
  const Handle(Geom_BSplineSurface) patch = GeomConvert::SurfaceToBSplineSurface(
      new Geom_RectangularTrimmedSurface(new Geom_Plane(gp_Ax3()), 0.0, 1.0, 0.0, 1.0));
  const Handle(Geom2d_Circle) circle =
      new Geom2d_Circle(gp_Ax2d(gp_Pnt2d(0.5, 0.5), gp_Dir2d(1, 0)), 0.8);
  TopoDS_Edge edge = BRepBuilderAPI_MakeEdge(circle, patch).Edge();
  BRepLib::BuildCurves3d(edge);
  const std::string path = dir / "circle-past-the-patch.brep";
  ASSERT_TRUE(BRepTools::Write(
      BRepBuilderAPI_MakeFace(patch, BRepBuilderAPI_MakeWire(edge).Wire()).Face(), path.c_str()));
  const CadImport imported = import_cad_model(path);
  EXPECT_EQ(imported.report.faces_skipped(), 0) << imported.report.summary();
  EXPECT_EQ(imported.report.placed.count("domain extended"), 1u);
  ASSERT_EQ(imported.scene.surfaces.size(), 1u);
  const Surface& s = imported.scene.surfaces[0];
  // At least the circle's extent, -0.3 .. 1.3, both ways.
  EXPECT_LE(s.u_min(), -0.3 + 1e-12);
  EXPECT_GE(s.u_max(), 1.3 - 1e-12);
  EXPECT_LE(s.v_min(), -0.3 + 1e-12);
  EXPECT_GE(s.v_max(), 1.3 - 1e-12);
  const std::vector<ReferenceSurface> on =
      evaluate_reference(imported.scene, sample_parameters(imported.scene, Sampling{}), false);
  const std::vector<SurfaceSamples> at = sample_parameters(imported.scene, Sampling{});
  for (std::size_t n = 0; n < at[0].count(); ++n) {
    EXPECT_NEAR(on[0].positions[n][0], at[0].u_of(n), 1e-12);
    EXPECT_NEAR(on[0].positions[n][1], at[0].v_of(n), 1e-12);
    EXPECT_NEAR(on[0].positions[n][2], 0.0, 1e-12);
    const double r = std::hypot(at[0].u_of(n) - 0.5, at[0].v_of(n) - 0.5);
    if (std::abs(r - 0.8) > 1e-6) {
      EXPECT_EQ(on[0].inside[n], r < 0.8 ? 1 : 0) << r;
    }
  }
}

// A full cylinder band with a hole across its seam: every seam position crosses a loop (the band
// fills the period, the hole straddles its ends), so no period holds the face without splitting a
// loop at the seam, which the importer does not do: that face is skipped, naming why, and
// --strict refuses it.
TEST(CadImport, FaceThatFailsIsSkippedAndStrictRefusesIt) {
  TempDir dir;
  const Handle(Geom_BSplineSurface) cylinder = periodic_cylinder();
  const TopoDS_Face band = BRepBuilderAPI_MakeFace(cylinder, 0, 2 * M_PI, 0, 3, 1e-9).Face();
  const Handle(Geom2d_Circle) circle =
      new Geom2d_Circle(gp_Ax2d(gp_Pnt2d(0.0, 1.5), gp_Dir2d(1, 0)), 0.3);
  TopoDS_Edge edge = BRepBuilderAPI_MakeEdge(circle, cylinder).Edge();
  BRepLib::BuildCurves3d(edge);
  const TopoDS_Face holed =
      BRepBuilderAPI_MakeFace(band, TopoDS::Wire(BRepBuilderAPI_MakeWire(edge).Wire().Reversed()))
          .Face();
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  builder.Add(compound, BRepPrimAPI_MakeSphere(1.0).Shape());
  builder.Add(compound, holed);
  const std::string path = dir / "one-bad-face.brep";
  ASSERT_TRUE(BRepTools::Write(compound, path.c_str()));

  const CliResult loose = run_cli({"import", path, "--out", dir / "scene.json"});
  EXPECT_EQ(loose.exit_code, 0) << loose.err;
  const std::vector<std::string> warnings = split_lines(loose.err);
  ASSERT_EQ(warnings.size(), 1u) << loose.err;
  EXPECT_TRUE(warnings[0].starts_with("nurbsbench: warning: " + path +
                                      ": face-1: skipped every seam position is crossed by a loop"))
      << warnings[0];
  EXPECT_NE(loose.out.find("faces read 2, converted 1, skipped 1 (every seam position is crossed "
                           "by a loop: 1)"),
            std::string::npos)
      << loose.out;

  const std::string strict_out = dir / "strict.json";
  const CliResult strict = run_cli({"import", path, "--strict", "--out", strict_out});
  EXPECT_EQ(strict.exit_code, 2);
  EXPECT_TRUE(
      split_lines(strict.err).back().starts_with("nurbsbench: error: " + path + ": --strict"))
      << strict.err;
  EXPECT_FALSE(std::filesystem::exists(strict_out));
}

TEST(CadImport, ModelPathsRunWhereScenesDo) {
  TempDir dir;
  const std::string path = dir / "torus.brep";
  ASSERT_TRUE(BRepTools::Write(BRepPrimAPI_MakeTorus(3, 1).Shape(), path.c_str()));
  const CliResult r = run_cli({"run", "--scenes", path, "--strategies", "all", "--samples", "8x8",
                               "--repetitions", "1", "--out", dir / "results"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(read_text(dir / "results/results.csv").find("torus"), std::string::npos);
}

}  // namespace
}  // namespace nurbs::test
