#include "scenes/cad_import/occt_model.h"

#include <fmt/format.h>

#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <OSD.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <iostream>
#include <mutex>
#include <sstream>

#include "reference/validation.h"
#include "scenes/cad_import/cad_import.h"

// Under LeakSanitizer: OpenCASCADE's data exchange keeps objects it never frees (IFSelect_Editor
// and its allocator's blocks, created when a STEP/IGES reader first starts; not built with
// sanitizers, like the GPU drivers). Its leaks are suppressed, ours are not: nothing of ours is
// allocated inside these libraries. Quietly: bad input must still give one line on stderr.
#if defined(__SANITIZE_ADDRESS__)
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libTKXSBase.so\nleak:libTKSTEP\nleak:libTKIGES.so\nleak:libTKernel.so\n";
}
extern "C" const char* __lsan_default_options() {
  return "print_suppressions=0";
}
#endif

namespace nurbs::cad {
namespace {

// Once per process: signal handlers that OCC_CATCH_SIGNALS can turn into exceptions (only where
// none is installed already: a sanitizer's stays), no floating-point traps, and no OpenCASCADE
// trace on stdout, which may be carrying the scene.
void prepare_occt() {
  static std::once_flag once;
  std::call_once(once, [] {
    OSD::SetSignal(OSD_SignalMode_SetUnhandled, Standard_False);
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  });
}

template <class Reader>
TopoDS_Shape read_with(const std::filesystem::path& path, std::string_view format) {
  Reader reader;
  const IFSelect_ReturnStatus status = reader.ReadFile(path.c_str());
  if (status != IFSelect_RetDone)
    throw InputError(fmt::format("{}: not a readable {} file (OpenCASCADE reader status {})",
                                 path.string(), format, static_cast<int>(status)));
  reader.TransferRoots();
  return reader.OneShape();
}

}  // namespace

std::string_view model_format(const std::filesystem::path& path) {
  if (!is_cad_model_path(path))
    throw InputError(fmt::format(
        "{}: unknown model extension '{}' (STEP .stp/.step, IGES .igs/.iges, BREP .brep)",
        path.string(), path.extension().string()));
  std::string extension = path.extension().string();
  const char first = static_cast<char>(std::tolower(static_cast<unsigned char>(extension.at(1))));
  return first == 's' ? "STEP" : first == 'i' ? "IGES" : "BREP";
}

std::string run_guarded(const std::function<void()>& body) {
  prepare_occt();
  try {
    OCC_CATCH_SIGNALS
    body();
  } catch (const Standard_Failure& failure) {
    const char* message = failure.GetMessageString();
    return fmt::format("{}{}{}", failure.DynamicType()->Name(), message && *message ? ": " : "",
                       message ? message : "");
  }
  return {};
}

TopoDS_Shape read_model(const std::filesystem::path& path) {
  const std::string_view format = model_format(path);
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw InputError(fmt::format("{}: no such file", path.string()));
  TopoDS_Shape shape;
  // BRepTools::Read writes its complaints straight to std::cout, which may be carrying a scene.
  std::ostringstream occt_output;
  struct RestoreCout {
    std::streambuf* saved;
    ~RestoreCout() { std::cout.rdbuf(saved); }
  } restore{std::cout.rdbuf(occt_output.rdbuf())};
  const std::string failure = run_guarded([&] {
    if (format == "STEP") {
      shape = read_with<STEPControl_Reader>(path, format);
    } else if (format == "IGES") {
      shape = read_with<IGESControl_Reader>(path, format);
    } else {
      BRep_Builder builder;
      if (!BRepTools::Read(shape, path.c_str(), builder))
        throw InputError(fmt::format("{}: not a readable BREP file", path.string()));
    }
  });
  if (!failure.empty())
    throw InputError(
        fmt::format("{}: OpenCASCADE cannot read it as {}: {}", path.string(), format, failure));
  if (shape.IsNull() || model_faces(shape).empty())
    throw InputError(fmt::format("{}: no faces in the model", path.string()));
  return shape;
}

std::vector<TopoDS_Face> model_faces(const TopoDS_Shape& shape) {
  std::vector<TopoDS_Face> faces;
  for (TopExp_Explorer explorer(shape, TopAbs_FACE); explorer.More(); explorer.Next())
    faces.push_back(TopoDS::Face(explorer.Current()));
  return faces;
}

ConvertedFaces convert_faces(const TopoDS_Shape& shape) {
  const std::vector<TopoDS_Face> faces = model_faces(shape);
  ConvertedFaces out{std::vector<TopoDS_Face>(faces.size()),
                     std::vector<std::string>(faces.size())};
  const std::string whole = run_guarded([&] {
    BRepBuilderAPI_NurbsConvert convert(shape, Standard_True);
    for (std::size_t k = 0; k < faces.size(); ++k)
      // The modification is kept per face (TShape), not per occurrence: the occurrence's
      // orientation is the face's, as read.
      out.faces[k] = TopoDS::Face(convert.ModifiedShape(faces[k]).Oriented(faces[k].Orientation()));
  });
  if (whole.empty()) return out;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    out.faces[k].Nullify();
    out.errors[k] = run_guarded([&] {
      out.faces[k] = TopoDS::Face(BRepBuilderAPI_NurbsConvert(faces[k], Standard_True)
                                      .Shape()
                                      .Oriented(faces[k].Orientation()));
    });
    if (!out.errors[k].empty()) out.faces[k].Nullify();
  }
  return out;
}

}  // namespace nurbs::cad
