// Built without OpenCASCADE data exchange: every model path is refused with the reason.
#include <fmt/format.h>

#include "reference/validation.h"
#include "scenes/cad_import/cad_import.h"

namespace nurbs {

CadImport import_cad_model(const std::filesystem::path& path, const CadImportOptions&) {
  throw InputError(fmt::format(
      "{}: not built with OpenCASCADE data exchange (install libocct-data-exchange-dev)",
      path.string()));
}

}  // namespace nurbs
