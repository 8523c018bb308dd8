// The OpenCASCADE side of the CAD import, shared by the importer and its tests (which hold
// OpenCASCADE's own classifier and evaluation up against the imported scene): read a file, list
// its faces, convert them to NURBS. Only built with OpenCASCADE data exchange.
#pragma once

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace nurbs::cad {

// "STEP", "IGES" or "BREP" from the extension; throws InputError naming the file otherwise.
std::string_view model_format(const std::filesystem::path& path);

// Runs `body`; an OpenCASCADE failure (Standard_Failure) or a signal inside it (a crash on a
// malformed file, caught with OCC_CATCH_SIGNALS) becomes the returned message. Empty: it ran.
std::string run_guarded(const std::function<void()>& body);

// The file as read by OpenCASCADE. Throws InputError naming the file when it is missing,
// unreadable, malformed or holds no face.
TopoDS_Shape read_model(const std::filesystem::path& path);

// Every face of `shape` as TopExp_Explorer visits them (the importer's face-<k> is entry k).
std::vector<TopoDS_Face> model_faces(const TopoDS_Shape& shape);

// The faces of `shape` (model_faces order) after BRepBuilderAPI_NurbsConvert of the shape as
// read: B-spline surfaces stay, analytic ones become exact NURBS, and the p-curves follow the
// new parameters. Where converting the whole shape fails, each face is converted alone; a face
// that cannot be converted is null, with its reason in `errors`.
struct ConvertedFaces {
  std::vector<TopoDS_Face> faces;
  std::vector<std::string> errors;
};
ConvertedFaces convert_faces(const TopoDS_Shape& shape);

}  // namespace nurbs::cad
