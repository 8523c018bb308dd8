// Every model Debian's occt-misc ships in STEP, IGES and BREP that we name here, imported and
// checked against OpenCASCADE as a peer; prints the per-model figures (docs/cad-import.md).
// Skipped where occt-misc is not installed.
#include <gtest/gtest.h>

#include <cstdio>

#include "occt_peer_check.h"

namespace nurbs::test {
namespace {

class CadModel : public ::testing::TestWithParam<const char*> {};

TEST_P(CadModel, ImportsAndAgreesWithOpenCascade) {
  const std::filesystem::path path =
      std::filesystem::path("/usr/share/opencascade/data") / GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << ": Debian occt-misc not installed";
  const CadImport imported = import_cad_model(path);
  const PeerFigures f = check_against_occt(path, imported, 32);
  std::printf(
      "%s  classification agrees with BRepClass_FaceClassifier on %ld of %ld samples "
      "outside the band (%ld in it; 32x32 per face), %ld where OpenCASCADE is wrong "
      "(outside its p-curves' box, or against its own p-curves as polygons); surface deviation "
      "%.3g; trim on the model's edges %.3g of the "
      "allowance\n",
      imported.report.summary().c_str(), f.agreed, f.compared, f.in_band, f.peer_wrong,
      f.largest_deviation, f.largest_edge_ratio);
  EXPECT_GT(imported.report.faces_converted, 0);
  EXPECT_LE(f.largest_deviation, 1e-9);
  EXPECT_EQ(f.unexplained, 0) << f.first_unexplained;
  EXPECT_LE(f.largest_edge_ratio, 1.0) << f.worst_edge;
}

INSTANTIATE_TEST_SUITE_P(OcctMisc, CadModel,
                         ::testing::Values("iges/bearing.iges", "step/linkrods.step",
                                           "step/screw.step", "occ/bottle.brep", "occ/Ball.brep",
                                           "occ/CrankArm.brep"),
                         [](const auto& info) {
                           std::string name = std::filesystem::path(info.param).stem().string();
                           std::replace_if(
                               name.begin(), name.end(), [](char c) { return !std::isalnum(c); },
                               '_');
                           return name;
                         });

}  // namespace
}  // namespace nurbs::test
