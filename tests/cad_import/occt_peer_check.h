// The imported scene held up against OpenCASCADE as a peer: each surface against OpenCASCADE's
// evaluation of the converted face's surface, each loop's closure, and the reference's exact
// classification against BRepClass_FaceClassifier outside the band. Shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <BRepClass_FaceClassifier.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Surface.hxx>
#include <algorithm>
#include <cmath>
#include <string>

#include "reference/reference_evaluator.h"
#include "reference/trim_classify.h"
#include "scenes/cad_import/cad_import.h"
#include "scenes/cad_import/occt_model.h"

namespace nurbs::test {

struct PeerFigures {
  double largest_deviation = 0;  // relative to the control points' bounding-box diagonal
  long compared = 0, agreed = 0, in_band = 0;
  // Disagreements outside the bounding box of the face's p-curves, where the face is not and
  // the reference says so: OpenCASCADE's classifier is wrong there (seen on the last grid row of
  // bearing.iges, on the domain's edge).
  long peer_wrong = 0;
  // Disagreements farther from the trim boundary than the importer moved it (closing gaps, moving
  // p-curves into the domain): bounded by the report's largest gap plus largest change.
  long unexplained = 0;
  std::string first_unexplained;  // face, (u, v), distance to the boundary, both classes
};

inline double box_diagonal(const Surface& s) {
  Point3 lo = s.points.front(), hi = lo;
  for (const Point3& p : s.points)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
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
      const gp_Pnt p = geometry->Value(u, v);
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
      const double period_u = geometry->IsUPeriodic() ? geometry->UPeriod() : 0;
      const double period_v = geometry->IsVPeriodic() ? geometry->VPeriod() : 0;
      TopAbs_State state = TopAbs_OUT;
      bool outside_box = true;
      for (int ku = period_u > 0 ? -3 : 0; ku <= (period_u > 0 ? 3 : 0); ++ku)
        for (int kv = period_v > 0 ? -3 : 0; kv <= (period_v > 0 ? 3 : 0); ++kv) {
          const double uk = u + ku * period_u, vk = v + kv * period_v;
          const bool outside = uk < box_u0 - band || uk > box_u1 + band ||
                               vk < box_v0 - band || vk > box_v1 + band;
          if (outside && (period_u > 0 || period_v > 0)) continue;
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
