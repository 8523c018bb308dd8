// `run --images DIR` through the runner in one process (the CLI tests drive the isolated path):
// the picture of a strategy that drew, read back with OpenImageIO against the one the strategy
// returned, and the trim masks of a strategy that classifies, whose pixels are counted against the
// trimmed plate's closed form (tests/scenes/trimmed_plate_closed_form.h), never against the
// classifier that produced them.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>

#include "../cli/run_cli.h"
#include "harness/error_image.h"
#include "harness/runner.h"
#include "scenes/trimmed_plate.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs {
namespace {

namespace fs = std::filesystem;

using ScratchDir = test::TempDir;

// cpu-coxdeboor that, optionally, "draws" (render() true, last_render() a fixed picture) and has
// its read back altered.
class FakeStrategy final : public Strategy {
 public:
  FakeStrategy(std::optional<RenderedImage> picture, std::function<void(EvalResult&)> alter)
      : inner_(find_strategy("cpu-coxdeboor")->create({})),
        picture_(std::move(picture)),
        alter_(std::move(alter)) {}
  std::string_view name() const override { return "fake"; }
  Capabilities capabilities() const override { return inner_->capabilities(); }
  DeviceInfo device() const override { return inner_->device(); }
  void prepare_checked(const Scene& s, const EvalRequest& r) override { inner_->prepare(s, r); }
  void evaluate() override { inner_->evaluate(); }
  bool classify() override { return inner_->classify(); }
  EvalResult read_back() override {
    EvalResult result = inner_->read_back();
    if (alter_) alter_(result);
    return result;
  }
  bool render() override {
    drawn_ = picture_.has_value();
    return drawn_;
  }
  std::optional<RenderedImage> last_render() override { return drawn_ ? picture_ : std::nullopt; }

 private:
  std::unique_ptr<Strategy> inner_;
  std::optional<RenderedImage> picture_;
  std::function<void(EvalResult&)> alter_;
  bool drawn_ = false;
};

StrategyEntry fake_entry(std::string name, std::optional<RenderedImage> picture,
                         std::function<void(EvalResult&)> alter = {}) {
  StrategyEntry entry = *find_strategy("cpu-coxdeboor");
  entry.name = std::move(name);
  entry.create = [picture, alter](const StrategyOptions&) -> std::unique_ptr<Strategy> {
    return std::make_unique<FakeStrategy>(picture, alter);
  };
  return entry;
}

EvalRequest grid(int n) {
  Sampling s;
  s.grid_u = s.grid_v = n;
  return EvalRequest{s, Precision::f64, false};
}

struct Png {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> pixels;
};

Png read_png(const fs::path& path) {
  // The file's bytes, not premultiplied by its alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) throw std::runtime_error(path.string() + ": " + OIIO::geterror());
  Png png{in->spec().width, in->spec().height, in->spec().nchannels, {}};
  png.pixels.resize(static_cast<std::size_t>(png.width) * png.height * png.channels);
  if (!in->read_image(0, 0, 0, png.channels, OIIO::TypeDesc::UINT8, png.pixels.data()))
    throw std::runtime_error(path.string() + ": " + in->geterror());
  return png;
}

// Pixels of each kTrimMaskColours entry (index 5: any other colour).
std::array<std::size_t, 6> colour_counts(const Png& png) {
  std::array<std::size_t, 6> counts{};
  for (std::size_t p = 0; p < png.pixels.size(); p += 3) {
    std::size_t k = 0;
    while (k < kTrimMaskColours.size() && !(png.pixels[p] == kTrimMaskColours[k][0] &&
                                            png.pixels[p + 1] == kTrimMaskColours[k][1] &&
                                            png.pixels[p + 2] == kTrimMaskColours[k][2]))
      ++k;
    ++counts[k];
  }
  return counts;
}

TEST(RunImages, PictureOfAStrategyThatDrewIsWrittenAsItReturnedIt) {
  RenderedImage picture{3, 2, {}};
  for (int k = 0; k < 3 * 2 * 4; ++k) picture.rgba.push_back(static_cast<std::uint8_t>(11 * k));
  const StrategyEntry drawing = fake_entry("drawing-fake", picture);
  const StrategyEntry silent = fake_entry("silent-fake", std::nullopt);
  const Scene scene = trimmed_plate_scene();
  ScratchDir dir;
  ReferenceCache references;
  EXPECT_EQ(
      measure(drawing, {}, scene, grid(5), 1, references, kDefaultTrimBand, dir.path()).status,
      Status::ok);
  EXPECT_EQ(measure(silent, {}, scene, grid(5), 1, references, kDefaultTrimBand, dir.path()).status,
            Status::ok);

  const Png png = read_png(dir.path() / "drawing-fake__trimmed-plate.png");
  EXPECT_EQ(png.width, 3);
  EXPECT_EQ(png.height, 2);
  ASSERT_EQ(png.channels, 4);
  EXPECT_EQ(png.pixels, picture.rgba);  // rows top to bottom, as given
  EXPECT_FALSE(fs::exists(dir.path() / "silent-fake__trimmed-plate.png"));
}

TEST(RunImages, NoDirectoryNoFiles) {
  const StrategyEntry drawing = fake_entry("drawing-fake", RenderedImage{1, 1, {1, 2, 3, 4}});
  ScratchDir dir;
  const fs::path was = fs::current_path();
  fs::current_path(dir.path());  // where a relative name would land
  ReferenceCache references;
  measure(drawing, {}, trimmed_plate_scene(), grid(5), 1, references);
  fs::current_path(was);
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(RunImages, PictureOfTheWrongSizeFailsTheMeasurementAndWritesNothing) {
  const StrategyEntry drawing = fake_entry("drawing-fake", RenderedImage{4, 4, {1, 2, 3}});
  ScratchDir dir;
  ReferenceCache references;
  const Record r = measure(drawing, {}, trimmed_plate_scene(), grid(5), 1, references,
                           kDefaultTrimBand, dir.path());
  EXPECT_EQ(r.status, Status::failed);
  EXPECT_NE(r.reason.find("4x4 with 3 bytes"), std::string::npos) << r.reason;
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// The trimmed plate's samples, counted from the closed form: inside, outside, and (for a band)
// those surely inside the band and those possibly in it (the reference's distance is exact to 1%).
struct ClosedFormCounts {
  std::size_t inside = 0, outside = 0, surely_band = 0, maybe_band = 0, nearest = 0;
  double nearest_distance = INFINITY;
};

ClosedFormCounts closed_form_counts(const Scene& scene, const EvalRequest& request,
                                    double band_units) {
  const TrimmedPlateShape shape;
  const SurfaceSamples samples = sample_parameters(scene, request.sampling)[0];
  ClosedFormCounts c;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    const double d = test::trimmed_plate_signed_distance(shape, samples.u_of(k), samples.v_of(k));
    (d < 0 ? c.inside : c.outside) += 1;
    c.nearest_distance = std::min(c.nearest_distance, std::abs(d));
    if (std::abs(d) < 0.98 * band_units) ++c.surely_band;
    if (std::abs(d) < 1.02 * band_units) ++c.maybe_band;
  }
  return c;
}

TEST(RunImages, TrimMaskPixelsCountTheClosedFormsInsideAndOutside) {
  const Scene scene = trimmed_plate_scene();
  const EvalRequest request = grid(24);
  const ClosedFormCounts expected = closed_form_counts(scene, request, 0);
  // The premise: no sample of this grid is within rounding of the boundary, so the exact answer
  // is the closed form's.
  ASSERT_GT(expected.nearest_distance, 1e-6);
  ASSERT_GT(expected.inside, 100u);
  ASSERT_GT(expected.outside, 100u);

  ScratchDir dir;
  ReferenceCache references;
  const Record r = measure(*find_strategy("cpu-coxdeboor"), {}, scene, request, 1, references,
                           kDefaultTrimBand, dir.path());
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  const Png png = read_png(dir.path() / "cpu-coxdeboor__trimmed-plate__mask0.png");
  const int scale = 256 / 24;  // error_image.h: whole pixels per sample, about 256 in all
  ASSERT_EQ(png.width, 24 * scale);
  ASSERT_EQ(png.height, 24 * scale);
  ASSERT_EQ(png.channels, 3);
  const auto counts = colour_counts(png);
  const std::size_t per_sample = static_cast<std::size_t>(scale) * scale;
  EXPECT_EQ(counts[0], expected.inside * per_sample);
  EXPECT_EQ(counts[1], expected.outside * per_sample);
  for (std::size_t k = 2; k < counts.size(); ++k) EXPECT_EQ(counts[k], 0u) << "colour " << k;
  // v upwards: the bottom-left pixel is sample (u_min, v_min), outside the rounded rectangle.
  const std::size_t bottom_left = static_cast<std::size_t>(png.height - 1) * png.width * 3;
  EXPECT_EQ(png.pixels[bottom_left], kTrimMaskColours[1][0]);
}

TEST(RunImages, TrimMaskShowsMisclassifiedSamplesAndShadesTheBand) {
  const Scene scene = trimmed_plate_scene();
  const EvalRequest request = grid(24);
  const double band = 0.02;  // of the domain diagonal, sqrt(2) for [0, 1]^2
  const ClosedFormCounts expected = closed_form_counts(scene, request, band * std::sqrt(2.0));
  ASSERT_GT(expected.surely_band, 20u);

  // The strategy's mask with samples 0..N-1 (u = 0, the domain's edge: far outside the face,
  // never in the band) flipped to inside.
  constexpr std::size_t kFlipped = 7;
  const StrategyEntry flipping = fake_entry("flipping-fake", std::nullopt, [](EvalResult& r) {
    for (std::size_t k = 0; k < kFlipped; ++k) r.surfaces[0].inside[k] = 1;
  });
  ScratchDir dir;
  ReferenceCache references;
  const Record r = measure(flipping, {}, scene, request, 1, references, band, dir.path());
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  ASSERT_TRUE(r.accuracy && r.accuracy->trim && r.accuracy->trim->misclassified);
  EXPECT_EQ(*r.accuracy->trim->misclassified, kFlipped);

  const Png png = read_png(dir.path() / "flipping-fake__trimmed-plate__mask0.png");
  const std::size_t per_sample = (256 / 24) * (256 / 24);
  const auto counts = colour_counts(png);
  EXPECT_EQ(counts[4], kFlipped * per_sample);
  const std::size_t band_samples = (counts[2] + counts[3]) / per_sample;
  EXPECT_GE(band_samples, expected.surely_band);
  EXPECT_LE(band_samples, expected.maybe_band);
  EXPECT_EQ((counts[0] + counts[1] + counts[2] + counts[3] + counts[4]) / per_sample, 24u * 24u);
  EXPECT_EQ(counts[5], 0u);
}

}  // namespace
}  // namespace nurbs
