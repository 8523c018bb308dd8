// Real CAD models in: STEP (.stp, .step), IGES (.igs, .iges) and OpenCASCADE BREP (.brep) files
// become scenes of trimmed NURBS surfaces, one surface per face (docs/cad-import.md).
// OpenCASCADE reads and converts the file; every face is then checked against OpenCASCADE's own
// evaluation and its loops against the model's tolerance, and a face that fails is skipped with a
// reason, never trusted. Built without OpenCASCADE data exchange, import_cad_model throws.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "reference/surface.h"

namespace nurbs {

// True for the extensions the importer reads (case-insensitive), whether or not it is built.
bool is_cad_model_path(const std::filesystem::path& path);

struct CadImportOptions {
  // Any skipped face makes the import fail (InputError) instead of a warning.
  bool strict = false;
  // Called with each skipped face's one-line warning ("face-<k>: <reason>: <detail>") as it
  // happens; the warnings are also in the report.
  std::function<void(const std::string&)> warn;
};

// What the import did, for the closing summary and the tests.
struct CadImportReport {
  std::string file;
  std::string format;  // STEP, IGES or BREP
  int faces_read = 0;
  int faces_converted = 0;
  std::map<std::string, int> skipped;  // reason -> faces
  // How faces whose p-curves lay in another period or past the domain were placed (exactly):
  // "moved by whole periods", "seam moved", "domain extended" -> faces (cad_import_occt.cpp).
  std::map<std::string, int> placed;
  std::vector<std::string> warnings;  // one line per skipped face
  int loops = 0;
  int curves = 0;
  // Largest gap between consecutive p-curve ends of a loop in (u, v), before it was closed.
  double largest_closure_gap = 0;
  // Largest change of a p-curve, beyond its retraction onto the surface's domain, made by moving
  // its control points outside the domain onto the domain's edge, in (u, v) (cad_import_occt.cpp).
  double largest_domain_excess = 0;
  // Largest distance between an imported surface (reference evaluator) and OpenCASCADE's
  // evaluation of the face's converted surface on the check grid, over the face's size.
  double largest_surface_deviation = 0;
  std::map<std::string, int> degrees;  // "p x q" -> surfaces
  double seconds = 0;                  // reading, conversion and checks

  int faces_skipped() const;
  // Several lines: faces read/converted/skipped (by reason), loops, largest closure gap and
  // surface deviation, degrees, time.
  std::string summary() const;
};

struct CadImport {
  Scene scene;
  CadImportReport report;
};

// Reads a model file into a validated scene whose surfaces are named face-<k>, k the face's index
// in TopExp_Explorer order over the file's shape. Throws InputError naming the file for a
// missing, unreadable or malformed file, a model without faces, one whose every face was skipped,
// and with options.strict any skipped face.
CadImport import_cad_model(const std::filesystem::path& path, const CadImportOptions& options = {});

}  // namespace nurbs
