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

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
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

// ------------------------------------------------------------ `run --images DIR` and the report
// The same PNG output for two more kinds of picture: what a strategy drew (render()), and the
// trim masks of a strategy that classifies. Files are "<strategy>__<scene>.png" and
// "<strategy>__<scene>__mask<surface index>.png", each replaced atomically.

// Throws InputError naming `option` and `directory` when it is not a writable directory (created
// when missing) or when the build has no OpenImageIO.
void prepare_image_directory(std::string_view option, const std::filesystem::path& directory);

// `name` with every character but letters, digits, '.', '-' and '_' replaced by '_' (a scene
// named by a path, a strategy option in a label): one file, in the directory it was meant for.
std::string safe_file_name(std::string name);

std::filesystem::path render_image_path(const std::filesystem::path& directory,
                                        std::string_view strategy, std::string_view scene);
std::filesystem::path trim_mask_path(const std::filesystem::path& directory,
                                     std::string_view strategy, std::string_view scene,
                                     std::size_t surface);

// Writes `image` (RGBA8, rows top to bottom) as a PNG. Throws std::runtime_error naming the path
// when the image's size does not match its pixels or it cannot be written.
void write_render_image(const std::filesystem::path& path, const RenderedImage& image,
                        const std::string& title);

// A trim mask: each sample of a trimmed surface as the strategy classified it, against the
// reference. In the band (the reference's distance to the trim boundary below band x the domain
// diagonal, as metrics.h scores it) the classification is not scored, so it is shaded, not judged.
enum class TrimMaskClass : std::uint8_t {
  inside,         // strategy and reference: inside
  outside,        // strategy and reference: outside
  band_inside,    // in the band, the strategy said inside
  band_outside,   // in the band, the strategy said outside
  misclassified,  // outside the band, the strategy disagrees with the reference
};
// RGB of each class, in the order above: light and dark for inside and outside, the same tinted
// orange in the band, and magenta (which neither grey nor orange approaches) for misclassified.
inline constexpr std::array<std::array<std::uint8_t, 3>, 5> kTrimMaskColours = {
    {{235, 235, 235}, {70, 70, 70}, {250, 200, 120}, {150, 95, 30}, {255, 0, 255}}};

struct TrimMask {
  std::size_t surface = 0;  // index in the scene
  std::string name;
  int width = 0, height = 0;         // u samples, v samples
  std::vector<TrimMaskClass> pixel;  // index y * width + x, y = v index (as ErrorGrid)
  std::size_t misclassified = 0;
};

// One mask per trimmed surface for which the strategy returned an inside mask, on a tensor
// sampling (other samplings have no image layout: none). `band` as TrimScoring::band.
std::vector<TrimMask> trim_masks(const Scene& scene, const EvalResult& result,
                                 const std::vector<ReferenceSurface>& reference, double band);

// The PNG: each sample a square of max(1, 256 / max(width, height)) pixels, v upwards; the legend
// is in the ImageDescription.
void write_trim_mask(const std::filesystem::path& path, const TrimMask& mask,
                     const std::string& title);

// run --images: every mask of trim_masks, named by trim_mask_path; returns the paths.
std::vector<std::filesystem::path> write_trim_masks(const std::filesystem::path& directory,
                                                    std::string_view strategy, const Scene& scene,
                                                    const std::vector<TrimMask>& masks);

}  // namespace nurbs
