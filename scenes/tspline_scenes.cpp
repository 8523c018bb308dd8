#include "scenes/tspline_scenes.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "reference/tspline_refinement.h"
#include "scenes/scene_json.h"
#include "scenes/tsm/tsm_reader.h"

namespace nurbs {
namespace {

struct RefinedMesh {
  TMesh mesh;
  TSplineSurface tspline;
  std::size_t first_new_vertex = 0;
};

// Three face splits, each at the middle of an interior face, far enough apart that no vertex gains
// more than one knot per split and the T-junction extensions never meet (analysis-suitable). Each
// split is a refinement of the previous T-spline (refine_onto), so the surface never changes.
RefinedMesh refined_mesh(const Surface& nurbs) {
  if (nurbs.degree_u != 3 || nurbs.degree_v != 3 || nurbs.count_u < 8 || nurbs.count_v < 8)
    throw std::logic_error("tspline scenes: need a bicubic net of at least 8x8");
  RefinedMesh out;
  out.mesh = tensor_tmesh(nurbs);
  out.first_new_vertex = out.mesh.vertices.size();
  out.tspline = infer_tspline(out.mesh, nurbs.name);
  const int last_column = nurbs.count_u - 1, last_row = nurbs.count_v - 1;
  // (column, row) of the face's lower-left index corner, in the mesh as it is at that split;
  // rightmost first so the earlier columns keep their indices (the third face is columns 3-4 of
  // the original mesh, after the second split put a column at index 3).
  const std::pair<int, int> faces[] = {{last_column - 3, last_row - 4}, {2, 2}, {4, last_row - 2}};
  for (const auto& [column, row] : faces) {
    const double knot = 0.5 * (out.mesh.knots_s[column] + out.mesh.knots_s[column + 1]);
    TMesh finer = with_column_segment(out.mesh, column, knot, row);
    if (const std::string violation = analysis_suitability_violation(finer); !violation.empty())
      throw std::logic_error("tspline scenes: not analysis-suitable: " + violation);
    out.tspline = refine_onto(out.tspline, infer_tspline(finer, nurbs.name));
    out.mesh = std::move(finer);
  }
  return out;
}

Scene one_surface(std::string name, std::string description, TSplineSurface tspline) {
  tspline.name = name;
  Scene scene{std::move(name), std::move(description), {}};
  scene.surfaces.push_back(make_tspline_surface(std::move(tspline)));
  return scene;
}

}  // namespace

Scene tspline_refined_scene(const Surface& nurbs) {
  return one_surface("tspline-refined",
                     "bicubic NURBS refined onto a T-mesh with six T-junctions: the same surface",
                     refined_mesh(nurbs).tspline);
}

Scene tspline_tjunction_scene(const Surface& nurbs, double lift) {
  RefinedMesh refined = refined_mesh(nurbs);
  for (std::size_t k = refined.first_new_vertex; k < refined.tspline.count(); ++k)
    refined.tspline.points[k][2] += lift;
  return one_surface("tspline-tjunction",
                     "a T-mesh with six T-junctions, their control points lifted out of the NURBS "
                     "surface",
                     std::move(refined.tspline));
}

Scene tsm_scene(std::string_view bytes, const std::string& name, const std::string& origin,
                const std::string& file) {
  return one_surface(name, "Rhino T-Splines model " + file,
                     infer_tspline(parse_tsm(bytes, origin), origin));
}

bool is_tsm_path(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".tsm";
}

Scene tsm_file_scene(const std::filesystem::path& path) {
  return tsm_scene(read_input_file(path, "T-spline"), path.stem().string(), path.string(),
                   path.filename().string());
}

}  // namespace nurbs
