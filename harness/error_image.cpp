#include "harness/error_image.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <limits>

#include "harness/metrics.h"
#include "reference/trim_classify.h"
#include "reference/validation.h"

#ifdef NURBSBENCH_HAVE_OIIO
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#endif

namespace nurbs {

namespace fs = std::filesystem;

namespace {

// Pixels per sample side: small grids are enlarged to about 256 pixels, by whole pixels so that
// every sample stays a square of the same size.
int sample_scale(int width, int height) {
  return std::max(1, 256 / std::max(width, height));
}

void require_oiio([[maybe_unused]] std::string_view option, [[maybe_unused]] const fs::path& path) {
#ifndef NURBSBENCH_HAVE_OIIO
  throw InputError(
      fmt::format("{} = {}: this build has no OpenImageIO (install "
                  "libopenimageio-dev, see scripts/setup.sh, and reconfigure)",
                  option, path.string()));
#endif
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

#ifdef NURBSBENCH_HAVE_OIIO
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

void write_atomically(const fs::path& path, const OIIO::ImageBuf& image) {
  const fs::path tmp = path.parent_path() / fmt::format(".{}.tmp{}{}", path.stem().string(),
                                                        ::getpid(), path.extension().string());
  if (!image.write(tmp.string())) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error(
        fmt::format("{}: cannot write image: {}", path.string(), image.geterror()));
  }
  fs::rename(tmp, path);
}

// Each sample of a width x height grid as a scale x scale square of colour_of(pixel index); row 0
// of the file is the top, so v grows upwards as on a plot.
template <class ColourOf>
void paint_samples(OIIO::ImageBuf& image, int width, int height, int scale, ColourOf&& colour_of) {
  for (int y = 0; y < height * scale; ++y)
    for (int x = 0; x < width * scale; ++x) {
      const std::size_t pixel = static_cast<std::size_t>(y / scale) * width + x / scale;
      const std::array<float, 3> c = colour_of(pixel);
      image.setpixel(x, height * scale - 1 - y, c.data());
    }
}

OIIO::ImageBuf exr_image(const ErrorGrid& g, const std::string& title) {
  const bool trimmed = !g.inside.empty();
  OIIO::ImageSpec spec(g.width, g.height, trimmed ? 2 : 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"error"};
  if (trimmed) spec.channelnames.push_back("inside");
  spec.attribute("ImageDescription", title);
  spec.attribute("nurbsbench:surface", g.surface);
  spec.attribute("nurbsbench:units", "model units (distance from the reference)");
  spec.attribute("nurbsbench:ulp_scale", static_cast<float>(g.ulp_scale));
  OIIO::ImageBuf image(spec);
  image.set_pixels(OIIO::ROI(0, g.width, 0, g.height, 0, 1, 0, 1), OIIO::TypeDesc::FLOAT,
                   g.error.data());
  if (trimmed) {
    const std::vector<float> inside(g.inside.begin(), g.inside.end());
    image.set_pixels(OIIO::ROI(0, g.width, 0, g.height, 0, 1, 1, 2), OIIO::TypeDesc::FLOAT,
                     inside.data());
  }
  return image;
}

OIIO::ImageBuf png_image(const ErrorGrid& g, const std::string& title) {
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
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("ImageDescription",
                 fmt::format("{}; error in f32 ulps of the largest coordinate, log scale 1e{} .. "
                             "1e{}",
                             title, lo_exp, hi_exp));
  OIIO::ImageBuf image(spec);
  const float white[3] = {1, 1, 1};
  OIIO::ImageBufAlgo::fill(image, white);
  paint_samples(image, g.width, g.height, scale, [&](std::size_t pixel) {
    return outside(pixel) ? kOutsideGrey : colour(t_of(g.error[pixel] / g.ulp_scale));
  });
  // Legend: a colour bar from the lowest decade (bottom) to the highest (top), labelled.
  const int bar_x = g.width * scale + 10, bar_top = 20, bar_bottom = h - 20;
  for (int y = bar_top; y <= bar_bottom; ++y) {
    const auto c = colour(1.0 - static_cast<double>(y - bar_top) / (bar_bottom - bar_top));
    for (int x = bar_x; x < bar_x + 16; ++x) image.setpixel(x, y, c.data());
  }
  const float black[3] = {0, 0, 0};
  // DejaVu Sans (fonts-dejavu-core, see scripts/setup.sh); OIIO's own default font is not
  // packaged on Debian. Without a font the bar is still drawn and the range is in the metadata.
  const std::string font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  for (double e = lo_exp; e <= hi_exp; e += 1) {
    const int y =
        bar_bottom - static_cast<int>((e - lo_exp) / (hi_exp - lo_exp) * (bar_bottom - bar_top));
    for (int x = bar_x + 16; x < bar_x + 22; ++x) image.setpixel(x, y, black);
    OIIO::ImageBufAlgo::render_text(image, bar_x + 24, y + 4, fmt::format("1e{}", e), 12, font,
                                    black);
  }
  OIIO::ImageBufAlgo::render_text(image, bar_x - 4, 14, "ulp", 12, font, black);
  if (!g.inside.empty()) {
    // The swatch sits in the bottom margin, under the bar.
    for (int y = h - 14; y < h - 2; ++y)
      for (int x = bar_x; x < bar_x + 16; ++x) image.setpixel(x, y, kOutsideGrey.data());
    OIIO::ImageBufAlgo::render_text(image, bar_x + 20, h - 3, "outside", 12, font, black);
  }
  return image;
}

}  // namespace
#endif

std::vector<fs::path> write_error_images(const fs::path& requested,
                                         const std::vector<ErrorGrid>& grids,
                                         const std::string& title) {
  const ErrorImageFormat format = error_image_format(requested);
  const std::vector<fs::path> paths = error_image_paths(requested, grids.size());
#ifdef NURBSBENCH_HAVE_OIIO
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const std::string surface_title =
        fmt::format("{}, surface {} ({})", title, i, grids[i].surface);
    write_atomically(paths[i], format == ErrorImageFormat::exr
                                   ? exr_image(grids[i], surface_title)
                                   : png_image(grids[i], surface_title));
  }
#else
  (void)format;
  (void)title;
#endif
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
#ifdef NURBSBENCH_HAVE_OIIO
  OIIO::ImageSpec spec(picture.width, picture.height, 4, OIIO::TypeDesc::UINT8);
  spec.attribute("ImageDescription", title);
  // The strategy's bytes as they are: without this OIIO takes them for premultiplied alpha and
  // divides the colour by it on the way to PNG.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::ImageBuf image(spec);
  image.set_pixels(OIIO::ROI(0, picture.width, 0, picture.height), OIIO::TypeDesc::UINT8,
                   picture.rgba.data());
  write_atomically(path, image);
#else
  (void)title;
#endif
}

void write_trim_mask(const fs::path& path, const TrimMask& mask, const std::string& title) {
#ifdef NURBSBENCH_HAVE_OIIO
  const int scale = sample_scale(mask.width, mask.height);
  OIIO::ImageSpec spec(mask.width * scale, mask.height * scale, 3, OIIO::TypeDesc::UINT8);
  spec.attribute(
      "ImageDescription",
      fmt::format("{}; one square per sample, v upwards: light = inside, dark = outside, orange = "
                  "in the trim band (light: said inside), magenta = misclassified ({} samples)",
                  title, mask.misclassified));
  OIIO::ImageBuf image(spec);
  paint_samples(image, mask.width, mask.height, scale, [&](std::size_t pixel) {
    const auto& c = kTrimMaskColours[static_cast<std::size_t>(mask.pixel[pixel])];
    // Exactly the 8-bit value back after OIIO's float -> uint8 conversion.
    return std::array<float, 3>{c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
  });
  write_atomically(path, image);
#else
  (void)path;
  (void)mask;
  (void)title;
#endif
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
