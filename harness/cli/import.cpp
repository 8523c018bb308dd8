#include <iostream>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "reference/validation.h"
#include "scenes/cad_import/cad_import.h"
#include "scenes/scene_json.h"

namespace nurbs::cli {

int import_command(const ImportOptions& options) {
  const bool to_stdout = options.out.empty() || options.out == "-";
  // Checked before the model is read: a path that cannot be written is bad input, not a failure
  // after minutes of import.
  const std::string out = to_stdout ? "" : writable_output_file("--out", options.out);
  // The summary goes where the scene does not.
  std::ostream& log = to_stdout ? std::cerr : std::cout;
  const CadImport imported = import_cad_model(
      options.model, {.strict = options.strict, .warn = [](const std::string& warning) {
                        std::cerr << "nurbsbench: warning: " << warning << "\n";
                      }});
  const std::string json = scene_to_json(imported.scene);
  if (to_stdout)
    std::cout << json;
  else
    write_file_atomically(out, json);
  log << imported.report.summary();
  return 0;
}

}  // namespace nurbs::cli
