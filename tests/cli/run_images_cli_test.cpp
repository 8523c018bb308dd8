// `run --images DIR` as a user runs it: bad directories are exit 2 with one line naming them, and
// the isolated run (the picture written by the measuring child, the masks by the parent) writes
// the same files, pixel for pixel, as --isolation none.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "harness/error_image.h"
#include "reference/sampling.h"
#include "run_cli.h"
#include "scenes/trimmed_plate.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> pixels_of(const fs::path& path, int& width, int& height) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) throw std::runtime_error(path.string() + ": " + OIIO::geterror());
  width = in->spec().width;
  height = in->spec().height;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height * in->spec().nchannels);
  in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::UINT8, pixels.data());
  return pixels;
}

std::vector<std::string> run_args(const TempDir& tmp, const std::string& isolation,
                                  const std::string& images) {
  return {"run",
          "--scenes",
          "trimmed-plate",
          "--strategies",
          "glsl-deboor,cpu-coxdeboor",
          "--samples",
          "16x16",
          "--repetitions",
          "1",
          "--isolation",
          isolation,
          "--images",
          images,
          "--out",
          tmp / ("out-" + isolation)};
}

TEST(CliRunImages, IsolatedRunWritesWhatAnInProcessRunWrites) {
  TempDir tmp;
  for (const std::string isolation : {"process", "none"}) {
    const CliResult r = run_cli(run_args(tmp, isolation, tmp / isolation));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string mask = "cpu-coxdeboor__trimmed-plate__mask0.png";
  int w = 0, h = 0, w2 = 0, h2 = 0;
  EXPECT_EQ(pixels_of(tmp.path() / "process" / mask, w, h),
            pixels_of(tmp.path() / "none" / mask, w2, h2));
  EXPECT_EQ(w, 16 * (256 / 16));
  // glsl-deboor draws where EGL (llvmpipe or a GPU) is available; its record says so otherwise.
  const std::string picture = "glsl-deboor__trimmed-plate.png";
  const std::string results = read_text(tmp.path() / "out-process" / "results.json");
  if (results.find("\"render\"") == std::string::npos) GTEST_SKIP() << "glsl-deboor did not draw";
  const auto drawn = pixels_of(tmp.path() / "process" / picture, w, h);
  EXPECT_EQ(drawn, pixels_of(tmp.path() / "none" / picture, w2, h2));
  EXPECT_GT(w, 0);
  EXPECT_EQ(w, w2);
  EXPECT_EQ(h, h2);
  // Something was drawn: the plate covers pixels (alpha 255) on a clear (alpha 0) background.
  std::size_t covered = 0, clear = 0;
  for (std::size_t p = 3; p < drawn.size(); p += 4) (drawn[p] == 255 ? covered : clear) += 1;
  EXPECT_GT(covered, drawn.size() / 4 / 10);
  EXPECT_GT(clear, 0u);
  // Nothing but the pictures: no temporaries left behind by the atomic writes.
  for (const auto& entry : fs::directory_iterator(tmp.path() / "process"))
    EXPECT_EQ(entry.path().extension(), ".png") << entry.path();
}

TEST(CliRunImages, BadDirectoryIsExitTwoWithOneLineNamingIt) {
  TempDir tmp;
  const std::string file = tmp / "a-file";
  std::ofstream(file) << "x";
  for (const std::string& bad : {file, file + "/below"}) {
    const CliResult r = run_cli(run_args(tmp, "none", bad));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--images = " + bad), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(tmp.path() / "out-none")) << "nothing measured, nothing written";
  }
  std::vector<std::string> deforming = run_args(tmp, "none", tmp / "images");
  deforming.insert(deforming.end(), {"--deforming", "2"});
  const CliResult r = run_cli(deforming);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--images"), std::string::npos) << r.err;
}

TEST(CliReportTrimMasks, EmbedsTheMaskOfAClassifyingStrategyWithTheClosedFormsInside) {
  TempDir tmp;
  const std::string results = tmp / "results";
  ASSERT_EQ(run_cli({"run", "--scenes", "trimmed-plate,sphere", "--strategies",
                     "cpu-coxdeboor,cpu-horner", "--samples", "24x24", "--repetitions", "1",
                     "--out", results})
                .exit_code,
            0);
  const CliResult r =
      run_cli({"report", "--results", results, "--out", tmp / "report", "--error-images", "0",
               "--trim-masks", "2", "--python", "/bin/false"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string report = read_text(tmp.path() / "report" / "REPORT.md");
  // Only the strategy that classified, on the only trimmed scene.
  const std::string name = "trim-mask-cpu-coxdeboor-trimmed-plate-0.png";
  EXPECT_NE(report.find("![" + name + "](" + name + ")"), std::string::npos) << report;
  EXPECT_EQ(report.find("trim-mask-cpu-horner"), std::string::npos);
  EXPECT_EQ(report.find("trim-mask-cpu-coxdeboor-sphere"), std::string::npos);

  int w = 0, h = 0;
  const auto pixels = pixels_of(tmp.path() / "report" / name, w, h);
  const int scale = 256 / 24;
  ASSERT_EQ(w, 24 * scale);
  std::size_t inside_pixels = 0;
  for (std::size_t p = 0; p < pixels.size(); p += 3)
    inside_pixels += pixels[p] == kTrimMaskColours[0][0] &&
                     pixels[p + 1] == kTrimMaskColours[0][1] &&
                     pixels[p + 2] == kTrimMaskColours[0][2];
  Sampling grid;
  grid.grid_u = grid.grid_v = 24;
  const SurfaceSamples samples = sample_parameters(trimmed_plate_scene(), grid)[0];
  std::size_t inside = 0;
  for (std::size_t k = 0; k < samples.count(); ++k)
    inside += trimmed_plate_signed_distance({}, samples.u_of(k), samples.v_of(k)) < 0;
  EXPECT_EQ(inside_pixels, inside * scale * scale);

  const CliResult bad =
      run_cli({"report", "--results", results, "--out", tmp / "bad", "--trim-masks", "51"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--trim-masks = 51"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(tmp.path() / "bad"));
}

}  // namespace
}  // namespace nurbs::test
