// Error heat maps (`nurbsbench eval --error-image F.exr|F.png`): per surface, the distance of
// every sample from the reference, laid out over the (u, v) domain. Pixel (x, y) is the sample
// with u-index x and v-index y (row 0 = first v, i.e. v_min; the span grid's repeated span ends
// appear as they were sampled). EXR: one float channel "error", the raw distance in model units
// (through OpenImageIO; +inf where the result was not finite). PNG: a colour map of the error in
// f32 ulps of the scene's largest coordinate (the max_ulp scale), log scale, with a legend bar.
// On a trimmed surface the samples the reference classifies outside the face are marked: grey in
// the PNG (a grey "outside" swatch in the legend; the colour scale spans the inside samples only),
// and in the EXR a second channel "inside" (1 inside, 0 outside) beside "error", which keeps its
// meaning for every sample.
// Scenes with several surfaces: one file per surface, "<stem>-<index><ext>" (index as in the eval
// CSV's surface column); a one-surface scene writes exactly the requested file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "reference/reference_evaluator.h"
#include "strategies/strategy.h"

namespace nurbs {

struct ErrorGrid {
  std::string surface;
  int width = 0, height = 0;  // u samples, v samples
  std::vector<float> error;   // model units, index y * width + x
  // Trimmed surfaces: the reference's classification, same index (1 inside); empty otherwise.
  std::vector<std::uint8_t> inside;
  double ulp_scale = 1;  // model units of one f32 ulp of the scene's largest coordinate
};

enum class ErrorImageFormat { exr, png };

// Throws InputError unless `path` ends in .exr or .png, or when the build has no OpenImageIO.
ErrorImageFormat error_image_format(const std::filesystem::path& path);

// Throws InputError when the sampling has no image layout (an explicit list).
std::vector<ErrorGrid> error_grids(const Scene& scene, const EvalResult& result,
                                   const std::vector<ReferenceSurface>& reference);

std::vector<std::filesystem::path> error_image_paths(const std::filesystem::path& requested,
                                                     std::size_t surfaces);

// The PNG's size for a map of width x height samples: each sample drawn as a square of
// max(1, 256 / max(width, height)) pixels, then a legend strip of kLegendWidth pixels at the
// right; at least 256 pixels high.
inline constexpr int kLegendWidth = 100;
std::pair<int, int> error_png_size(int width, int height);

// Writes one file per grid (paths from error_image_paths), each replaced atomically; returns
// them. `title` goes into the image metadata (ImageDescription).
std::vector<std::filesystem::path> write_error_images(const std::filesystem::path& requested,
                                                      const std::vector<ErrorGrid>& grids,
                                                      const std::string& title);

}  // namespace nurbs
