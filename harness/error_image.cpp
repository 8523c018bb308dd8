#include "harness/error_image.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <limits>

#include "harness/image_file.h"
#include "harness/metrics.h"
#include "reference/trim_classify.h"
#include "reference/validation.h"

namespace nurbs {

namespace fs = std::filesystem;

namespace {

// Pixels per sample side: small grids are enlarged to about 256 pixels, by whole pixels so that
// every sample stays a square of the same size.
int sample_scale(int width, int height) {
  return std::max(1, 256 / std::max(width, height));
}

void require_oiio(std::string_view option, const fs::path& path) {
  if (!image_files_built())
    throw InputError(
        fmt::format("{} = {}: this build has no OpenImageIO (install "
                    "libopenimageio-dev, see scripts/setup.sh, and reconfigure)",
                    option, path.string()));
}

// Calls f(k, pixel) for every sample of a width x height tensor grid: k in SurfaceSamples order
// (u-major), pixel = v index * width + u index.
template <class F>
void for_each_sample_pixel(int width, int height, F&& f) {
  for (int a = 0; a < width; ++a)
    for (int b = 0; b < height; ++b)
      f(static_cast<std::size_t>(a) * height + b, static_cast<std::size_t>(b) * width + a);
}

}  // namespace

std::vector<ErrorGrid> error_grids(const Scene& scene, const EvalResult& result,
                                   const std::vector<ReferenceSurface>& reference) {
  const double ulp_scale =
      FLT_EPSILON * (scene.largest_coordinate() > 0 ? scene.largest_coordinate() : 1.0);
  std::vector<ErrorGrid> grids;
  for (std::size_t i = 0; i < result.surfaces.size(); ++i) {
    const SurfaceResult& r = result.surfaces[i];
    if (!r.samples.tensor)
      throw InputError(
          "--error-image: needs a grid (--samples) or span grid (--span-samples); an explicit "
          "(u,v) list (--uv) has no image layout");
    ErrorGrid g;
    g.surface = i < scene.surfaces.size() ? scene.surfaces[i].name : std::to_string(i);
    g.width = static_cast<int>(r.samples.u.size());
    g.height = static_cast<int>(r.samples.v.size());
    g.ulp_scale = ulp_scale;
    g.error.resize(r.samples.count());
    const std::vector<std::uint8_t>& inside = reference.at(i).inside;
    if (!inside.empty()) g.inside.resize(r.samples.count());
    for_each_sample_pixel(g.width, g.height, [&](std::size_t k, std::size_t pixel) {
      const auto p = r.positions[k];
      const Point3& q = reference.at(i).positions.at(k);
      const double e = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
      g.error[pixel] =
          std::isfinite(e) ? static_cast<float>(e) : std::numeric_limits<float>::infinity();
      if (!inside.empty()) g.inside[pixel] = inside.at(k);
    });
    grids.push_back(std::move(g));
  }
  return grids;
}

std::vector<fs::path> error_image_paths(const fs::path& requested, std::size_t surfaces) {
  if (surfaces == 1) return {requested};
  std::vector<fs::path> paths;
  for (std::size_t i = 0; i < surfaces; ++i)
    paths.push_back(requested.parent_path() / fmt::format("{}-{}{}", requested.stem().string(), i,
                                                          requested.extension().string()));
  return paths;
}

std::pair<int, int> error_png_size(int width, int height) {
  const int scale = sample_scale(width, height);
  return {width * scale + kLegendWidth, std::max(height * scale, 256)};
}

ErrorImageFormat error_image_format(const fs::path& path) {
  const std::string ext = path.extension().string();
  ErrorImageFormat format;
  if (ext == ".exr")
    format = ErrorImageFormat::exr;
  else if (ext == ".png")
    format = ErrorImageFormat::png;
  else
    throw InputError(fmt::format(
        "--error-image = {}: extension '{}': must be .exr (raw float error) or .png (colour map)",
        path.string(), ext));
  require_oiio("--error-image", path);
  return format;
}

namespace {

// Viridis at five stops, linearly interpolated: perceptually ordered, readable in grey.
std::array<float, 3> colour(double t) {
  static constexpr std::array<std::array<float, 3>, 5> stops = {{{0.267f, 0.005f, 0.329f},
                                                                 {0.230f, 0.322f, 0.546f},
                                                                 {0.128f, 0.567f, 0.551f},
                                                                 {0.369f, 0.789f, 0.383f},
                                                                 {0.993f, 0.906f, 0.144f}}};
  t = std::clamp(t, 0.0, 1.0) * 4;
  const int k = std::min(3, static_cast<int>(t));
  const float f = static_cast<float>(t - k);
  return {stops[k][0] + f * (stops[k + 1][0] - stops[k][0]),
          stops[k][1] + f * (stops[k + 1][1] - stops[k][1]),
          stops[k][2] + f * (stops[k + 1][2] - stops[k][2])};
}

// Samples outside a trimmed face: a grey that viridis never produces (its ends are purple and
// yellow), so it cannot be read as an error level.
constexpr std::array<float, 3> kOutsideGrey = {0.6f, 0.6f, 0.6f};

// A width x height RGB image in floats (0..1, stored as 8 bits), filled with `background`.
ImageFile rgb8_image(int width, int height, std::array<float, 3> background) {
  ImageFile image;
  image.width = width;
  image.height = height;
  image.channels = 3;
  image.uint8 = true;
  image.pixels.resize(static_cast<std::size_t>(width) * height * 3);
  for (std::size_t i = 0; i < image.pixels.size(); i += 3)
    std::copy(background.begin(), background.end(), image.pixels.begin() + i);
  return image;
}

void set_pixel(ImageFile& image, int x, int y, const std::array<float, 3>& c) {
  std::copy(c.begin(), c.end(),
            image.pixels.begin() + (static_cast<std::size_t>(y) * image.width + x) * 3);
}

// Each sample of a width x height grid as a scale x scale square of colour_of(pixel index); row 0
// of the file is the top, so v grows upwards as on a plot.
template <class ColourOf>
void paint_samples(ImageFile& image, int width, int height, int scale, ColourOf&& colour_of) {
  for (int y = 0; y < height * scale; ++y)
    for (int x = 0; x < width * scale; ++x) {
      const std::size_t pixel = static_cast<std::size_t>(y / scale) * width + x / scale;
      set_pixel(image, x, height * scale - 1 - y, colour_of(pixel));
    }
}

ImageFile exr_image(const ErrorGrid& g, const std::string& title) {
  const bool trimmed = !g.inside.empty();
  ImageFile image;
  image.width = g.width;
  image.height = g.height;
  image.channels = trimmed ? 2 : 1;
  image.channel_names = {"error"};
  if (trimmed) image.channel_names.push_back("inside");
  image.text_attributes = {{"ImageDescription", title},
                           {"nurbsbench:surface", g.surface},
                           {"nurbsbench:units", "model units (distance from the reference)"}};
  image.float_attributes = {{"nurbsbench:ulp_scale", static_cast<float>(g.ulp_scale)}};
  image.pixels.reserve(g.error.size() * image.channels);
  for (std::size_t pixel = 0; pixel < g.error.size(); ++pixel) {
    image.pixels.push_back(g.error[pixel]);
    if (trimmed) image.pixels.push_back(static_cast<float>(g.inside[pixel]));
  }
  return image;
}

ImageFile png_image(const ErrorGrid& g, const std::string& title) {
  const auto [w, h] = error_png_size(g.width, g.height);
  const int scale = sample_scale(g.width, g.height);
  // Log scale over the decades the errors span, in ulps; zero and below the range = darkest.
  auto outside = [&](std::size_t pixel) { return !g.inside.empty() && g.inside[pixel] == 0; };
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (std::size_t pixel = 0; pixel < g.error.size(); ++pixel) {
    if (outside(pixel)) continue;  // not part of the face: not on the scale
    const double ulp = g.error[pixel] / g.ulp_scale;
    if (std::isfinite(ulp) && ulp > 0) {
      lo = std::min(lo, ulp);
      hi = std::max(hi, ulp);
    }
  }
  double lo_exp = std::isfinite(lo) ? std::floor(std::log10(lo)) : -1;
  double hi_exp = hi > 0 ? std::ceil(std::log10(hi)) : 0;
  if (hi_exp <= lo_exp) hi_exp = lo_exp + 1;
  auto t_of = [&](double ulp) {
    if (!std::isfinite(ulp)) return 1.0;
    return ulp > 0 ? (std::log10(ulp) - lo_exp) / (hi_exp - lo_exp) : 0.0;
  };
  ImageFile image = rgb8_image(w, h, {1, 1, 1});
  image.text_attributes = {
      {"ImageDescription",
       fmt::format("{}; error in f32 ulps of the largest coordinate, log scale 1e{} .. 1e{}", title,
                   lo_exp, hi_exp)}};
  paint_samples(image, g.width, g.height, scale, [&](std::size_t pixel) {
    return outside(pixel) ? kOutsideGrey : colour(t_of(g.error[pixel] / g.ulp_scale));
  });
  // Legend: a colour bar from the lowest decade (bottom) to the highest (top), labelled.
  const int bar_x = g.width * scale + 10, bar_top = 20, bar_bottom = h - 20;
  for (int y = bar_top; y <= bar_bottom; ++y) {
    const auto c = colour(1.0 - static_cast<double>(y - bar_top) / (bar_bottom - bar_top));
    for (int x = bar_x; x < bar_x + 16; ++x) set_pixel(image, x, y, c);
  }
  constexpr std::array<float, 3> black = {0, 0, 0};
  // DejaVu Sans (fonts-dejavu-core, see scripts/setup.sh); OIIO's own default font is not
  // packaged on Debian. Without a font the bar is still drawn and the range is in the metadata.
  image.font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  for (double e = lo_exp; e <= hi_exp; e += 1) {
    const int y =
        bar_bottom - static_cast<int>((e - lo_exp) / (hi_exp - lo_exp) * (bar_bottom - bar_top));
    for (int x = bar_x + 16; x < bar_x + 22; ++x) set_pixel(image, x, y, black);
    image.texts.push_back({bar_x + 24, y + 4, fmt::format("1e{}", e), 12, black});
  }
  image.texts.push_back({bar_x - 4, 14, "ulp", 12, black});
  if (!g.inside.empty()) {
    // The swatch sits in the bottom margin, under the bar.
    for (int y = h - 14; y < h - 2; ++y)
      for (int x = bar_x; x < bar_x + 16; ++x) set_pixel(image, x, y, kOutsideGrey);
    image.texts.push_back({bar_x + 20, h - 3, "outside", 12, black});
  }
  return image;
}

}  // namespace

std::vector<fs::path> write_error_images(const fs::path& requested,
                                         const std::vector<ErrorGrid>& grids,
                                         const std::string& title) {
  const ErrorImageFormat format = error_image_format(requested);
  const std::vector<fs::path> paths = error_image_paths(requested, grids.size());
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const std::string surface_title =
        fmt::format("{}, surface {} ({})", title, i, grids[i].surface);
    write_image_file(paths[i], format == ErrorImageFormat::exr
                                   ? exr_image(grids[i], surface_title)
                                   : png_image(grids[i], surface_title));
  }
  return paths;
}

void prepare_image_directory(std::string_view option, const fs::path& directory) {
  require_oiio(option, directory);
  std::error_code error;
  if (fs::exists(directory, error) && !fs::is_directory(directory, error))
    throw InputError(
        fmt::format("{} = {}: exists and is not a directory", option, directory.string()));
  fs::create_directories(directory, error);
  if (error)
    throw InputError(
        fmt::format("{} = {}: cannot create: {}", option, directory.string(), error.message()));
  // Refused now rather than by every measurement's write later.
  if (::access(directory.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("{} = {}: not writable", option, directory.string()));
}

std::string safe_file_name(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return name;
}

fs::path render_image_path(const fs::path& directory, std::string_view strategy,
                           std::string_view scene) {
  return directory / safe_file_name(fmt::format("{}__{}.png", strategy, scene));
}

fs::path trim_mask_path(const fs::path& directory, std::string_view strategy,
                        std::string_view scene, std::size_t surface) {
  return directory / safe_file_name(fmt::format("{}__{}__mask{}.png", strategy, scene, surface));
}

std::vector<TrimMask> trim_masks(const Scene& scene, const EvalResult& result,
                                 const std::vector<ReferenceSurface>& reference, double band) {
  std::vector<TrimMask> masks;
  for (std::size_t i = 0; i < result.surfaces.size() && i < scene.surfaces.size(); ++i) {
    const SurfaceResult& r = result.surfaces[i];
    const ReferenceSurface& ref = reference.at(i);
    const std::size_t n = r.samples.count();
    if (!scene.surfaces[i].trim || !r.samples.tensor || r.inside.size() != n ||
        ref.inside.size() != n || ref.trim_distance.size() != n)
      continue;
    TrimMask m;
    m.surface = i;
    m.name = scene.surfaces[i].name;
    m.width = static_cast<int>(r.samples.u.size());
    m.height = static_cast<int>(r.samples.v.size());
    m.pixel.resize(n);
    const double band_units = band * domain_diagonal(scene.surfaces[i]);
    for_each_sample_pixel(m.width, m.height, [&](std::size_t k, std::size_t pixel) {
      const bool inside = r.inside[k] != 0;
      TrimMaskClass c;
      if (in_trim_band(ref.trim_distance[k], band_units))
        c = inside ? TrimMaskClass::band_inside : TrimMaskClass::band_outside;
      else if (inside != (ref.inside[k] != 0))
        c = TrimMaskClass::misclassified;
      else
        c = inside ? TrimMaskClass::inside : TrimMaskClass::outside;
      m.misclassified += c == TrimMaskClass::misclassified;
      m.pixel[pixel] = c;
    });
    masks.push_back(std::move(m));
  }
  return masks;
}

void write_render_image(const fs::path& path, const RenderedImage& picture,
                        const std::string& title) {
  if (picture.width <= 0 || picture.height <= 0 ||
      picture.rgba.size() != static_cast<std::size_t>(picture.width) * picture.height * 4)
    throw std::runtime_error(fmt::format("{}: the strategy's picture is {}x{} with {} bytes",
                                         path.string(), picture.width, picture.height,
                                         picture.rgba.size()));
  ImageFile image;
  image.width = picture.width;
  image.height = picture.height;
  image.channels = 4;
  image.uint8 = true;
  image.bytes = picture.rgba;
  image.text_attributes = {{"ImageDescription", title}};
  // The strategy's bytes as they are: without this OIIO takes them for premultiplied alpha and
  // divides the colour by it on the way to PNG.
  image.int_attributes = {{"oiio:UnassociatedAlpha", 1}};
  write_image_file(path, image);
}

void write_trim_mask(const fs::path& path, const TrimMask& mask, const std::string& title) {
  const int scale = sample_scale(mask.width, mask.height);
  ImageFile image = rgb8_image(mask.width * scale, mask.height * scale, {0, 0, 0});
  image.text_attributes = {
      {"ImageDescription",
       fmt::format("{}; one square per sample, v upwards: light = inside, dark = outside, orange = "
                   "in the trim band (light: said inside), magenta = misclassified ({} samples)",
                   title, mask.misclassified)}};
  paint_samples(image, mask.width, mask.height, scale, [&](std::size_t pixel) {
    const auto& c = kTrimMaskColours[static_cast<std::size_t>(mask.pixel[pixel])];
    // Exactly the 8-bit value back after OIIO's float -> uint8 conversion.
    return std::array<float, 3>{c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
  });
  write_image_file(path, image);
}

std::vector<fs::path> write_trim_masks(const fs::path& directory, std::string_view strategy,
                                       const Scene& scene, const std::vector<TrimMask>& masks) {
  std::vector<fs::path> paths;
  for (const TrimMask& m : masks) {
    paths.push_back(trim_mask_path(directory, strategy, scene.name, m.surface));
    write_trim_mask(paths.back(), m,
                    fmt::format("trim mask of {} on {}, surface {} ({}), {}x{} samples", strategy,
                                scene.name, m.surface, m.name, m.width, m.height));
  }
  return paths;
}

}  // namespace nurbs
