// The parts of the import that need no OpenCASCADE: which paths are models, and the summary.
#include "scenes/cad_import/cad_import.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <numeric>

namespace nurbs {

bool is_cad_model_path(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".stp" || extension == ".step" || extension == ".igs" ||
         extension == ".iges" || extension == ".brep";
}

int CadImportReport::faces_skipped() const {
  return std::accumulate(skipped.begin(), skipped.end(), 0,
                         [](int sum, const auto& reason) { return sum + reason.second; });
}

std::string CadImportReport::summary() const {
  std::string reasons;
  for (const auto& [reason, count] : skipped)
    reasons += fmt::format("{}{}: {}", reasons.empty() ? " (" : ", ", reason, count);
  if (!reasons.empty()) reasons += ")";
  std::string routes;
  for (const auto& [route, count] : placed)
    routes += fmt::format("{}{}: {}", routes.empty() ? "" : ", ", route, count);
  std::string degree_list;
  for (const auto& [degree, count] : degrees)
    degree_list += fmt::format("{}{}: {}", degree_list.empty() ? "" : ", ", degree, count);
  return fmt::format(
      "import {} ({}): faces read {}, converted {}, skipped {}{}\n"
      "  loops {} ({} curves), largest closure gap {:.3g} (u,v), largest change moving p-curves "
      "into the domain {:.3g} (u,v)\n"
      "  p-curves placed exactly (faces): {}\n"
      "  largest surface deviation from OpenCASCADE {:.3g} (of the face's size)\n"
      "  surface degrees (u x v): {}\n"
      "  import time {:.3f} s\n",
      file, format, faces_read, faces_converted, faces_skipped(), reasons, loops, curves,
      largest_closure_gap, largest_domain_excess, routes.empty() ? "as read" : routes,
      largest_surface_deviation, degree_list.empty() ? "none" : degree_list, seconds);
}

}  // namespace nurbs
