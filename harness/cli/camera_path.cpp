// `nurbsbench camera-path`: 000 §3.2's continuous LOD along a fly-in, on gl-pingpong. Per frame
// each surface's grid is chosen from its size on screen (strategies/gl_pingpong/camera_lod.h),
// evaluated, copied on the device into a vertex buffer and drawn (lod_renderer.h); beside it the
// same fly-in re-evaluated every frame at one fixed grid. Writes DIR/camera_path.json
// (nurbsbench-camera-path/1) and, with --images, the first and last frame of each as PNG.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "harness/error_image.h"
#include "harness/machine.h"
#include "harness/side_files.h"
#include "harness/timing.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_pingpong/camera_lod.h"
#include "strategies/gl_pingpong/lod_renderer.h"

namespace nurbs::cli {

namespace {

using gl_pingpong::Camera;
using gl_pingpong::LodCounts;
using gl_pingpong::LodRenderer;

Sampling one_grid(std::string_view option, const std::string& text, int low, int high) {
  const std::vector<Sampling> grids = parse_grid_list(option, text);
  if (grids.size() != 1)
    throw InputError(fmt::format("{} = '{}': one WxH, not a list", option, text));
  const Sampling& g = grids.front();
  if (g.grid_u < low || g.grid_u > high || g.grid_v < low || g.grid_v > high)
    throw InputError(
        fmt::format("{} = '{}': each side must be in {}..{}", option, text, low, high));
  return g;
}

std::array<double, 3> point_of(const Point3& p) {
  return {p[0], p[1], p[2]};
}

CameraCounts counts_of(const LodCounts& after, const LodCounts& before) {
  return {after.draws - before.draws, after.passes - before.passes,
          after.host_read_backs - before.host_read_backs,
          after.device_copies - before.device_copies};
}

struct Frame {
  std::uint64_t samples = 0, triangles = 0;
  double seconds = 0;
  std::vector<std::pair<int, int>> grids;
};

}  // namespace

int camera_path_command(const CameraPathOptions& options) {
  // Everything is checked before the output directory is touched.
  const int threads = apply_thread_setting(options.threads);
  if (options.frames < 2 || options.frames > 10000)
    throw InputError(fmt::format("--frames = {}: must be in 2..10000", options.frames));
  const Sampling viewport = one_grid("--viewport", options.viewport, 16, 8192);
  if (!(options.pixels_per_sample >= 0.25 && options.pixels_per_sample <= 1024))
    throw InputError(
        fmt::format("--pixels-per-sample = {}: must be in 0.25..1024", options.pixels_per_sample));
  if (options.min_samples < 2 || options.min_samples > options.max_samples ||
      options.max_samples > 4096)
    throw InputError(
        fmt::format("--min-samples = {}, --max-samples = {}: must be 2 <= min <= max <= 4096",
                    options.min_samples, options.max_samples));
  const Sampling fixed = one_grid("--fixed-samples", options.fixed_samples, 2, 4096);
  std::vector<Scene> scenes;
  for (const std::string& name : scene_list(options.scenes)) {
    Scene scene = load_scene(name);
    for (const Surface& s : scene.surfaces) {
      if (s.is_tspline())
        throw InputError(
            fmt::format("--scenes: '{}' surface '{}' is a T-spline; gl-pingpong evaluates NURBS",
                        name, s.name));
    }
    scenes.push_back(std::move(scene));
  }
  if (!options.images.empty()) prepare_image_directory("--images", options.images);

  const gl_pingpong::LodRule rule{options.pixels_per_sample, options.min_samples,
                                  options.max_samples};
  const int width = viewport.grid_u, height = viewport.grid_v;
  const StrategyOptions strategy_options{threads, backend_extra(options.gl, "")};
  CameraPathFile file;
  std::string text;
  for (const Scene& scene : scenes) {
    const std::unique_ptr<LodRenderer> renderer =
        gl_pingpong::make_lod_renderer(scene, width, height, strategy_options);
    const gl_pingpong::FlyIn path = gl_pingpong::fly_in_of(scene);
    auto camera = [&](int f) {
      return gl_pingpong::camera_at(path, f, options.frames, width, height);
    };
    auto picture = [&](const std::string& kind, int f) {
      if (options.images.empty()) return;
      write_render_image(
          std::filesystem::path(options.images) /
              safe_file_name(fmt::format("camera_path__{}__{}__f{}.png", scene.name, kind, f)),
          renderer->picture(),
          fmt::format("gl-pingpong {} frame {} of {} ({}x{})", kind, f, scene.name, width, height));
    };

    // The baseline: one grid for every surface, evaluated again every frame.
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
      renderer->set_grid(i, fixed.grid_u, fixed.grid_v);
    renderer->draw_frame(gl_pingpong::view_projection(camera(0)));  // warm-up
    const LodCounts fixed_before = renderer->counts();
    std::vector<Frame> fixed_frames(static_cast<std::size_t>(options.frames));
    for (int f = 0; f < options.frames; ++f) {
      Frame& frame = fixed_frames[static_cast<std::size_t>(f)];
      Stopwatch watch;
      frame.triangles = renderer->draw_frame(gl_pingpong::view_projection(camera(f)));
      frame.seconds = watch.seconds();
      if (f == 0 || f + 1 == options.frames) picture("fixed", f);
    }
    const LodCounts fixed_after = renderer->counts();

    // 000 §3.2: each surface's grid from its size on screen, chosen and set inside the timed frame
    // (the CPU's share of the LOD is part of its cost). The warm-up starts from the first frame's
    // grids, as an interactive session arriving at that view would.
    auto lod_frame = [&](int f, Frame& frame) {
      const Camera c = camera(f);
      frame.grids.clear();
      frame.samples = 0;
      for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
        const gl_pingpong::LodResolution r =
            gl_pingpong::lod_resolution(scene.surfaces[i], c, rule);
        renderer->set_grid(i, r.nu, r.nv);
        frame.grids.emplace_back(r.nu, r.nv);
        frame.samples += static_cast<std::uint64_t>(r.nu) * r.nv;
      }
      frame.triangles = renderer->draw_frame(gl_pingpong::view_projection(c));
    };
    Frame warm;
    lod_frame(0, warm);
    const LodCounts lod_before = renderer->counts();
    std::vector<Frame> lod_frames(static_cast<std::size_t>(options.frames));
    for (int f = 0; f < options.frames; ++f) {
      Frame& frame = lod_frames[static_cast<std::size_t>(f)];
      Stopwatch watch;
      lod_frame(f, frame);
      frame.seconds = watch.seconds();
      if (f == 0 || f + 1 == options.frames) picture("lod", f);
    }
    const LodCounts lod_after = renderer->counts();

    const DeviceInfo device = renderer->device();
    const std::uint64_t fixed_samples =
        static_cast<std::uint64_t>(fixed.grid_u) * fixed.grid_v * scene.surfaces.size();
    std::vector<CameraFrame> frames;
    std::vector<double> lod_seconds, fixed_seconds;
    std::string table =
        fmt::format("{:>5} {:>10} {:>12} {:>12} {:>12} {:>12} {:>12}\n", "frame", "distance",
                    "LOD samples", "LOD tris", "LOD frame", "fixed tris", "fixed frame");
    const int every = std::max(1, options.frames / 12);
    for (int f = 0; f < options.frames; ++f) {
      const Frame& lod = lod_frames[static_cast<std::size_t>(f)];
      const Frame& fix = fixed_frames[static_cast<std::size_t>(f)];
      const Camera c = camera(f);
      std::vector<std::array<int, 2>> grids;
      for (const auto& [nu, nv] : lod.grids) grids.push_back({nu, nv});
      const double distance = gl_pingpong::distance_at(path, f, options.frames);
      frames.push_back({f, distance, point_of(c.eye), std::move(grids), lod.samples, lod.triangles,
                        lod.seconds, fixed_samples, fix.triangles, fix.seconds});
      lod_seconds.push_back(lod.seconds);
      fixed_seconds.push_back(fix.seconds);
      if (f % every == 0 || f + 1 == options.frames)
        table += fmt::format("{:>5} {:>10.4g} {:>12} {:>12} {:>9.3f} ms {:>12} {:>9.3f} ms\n", f,
                             distance, lod.samples, lod.triangles, lod.seconds * 1e3, fix.triangles,
                             fix.seconds * 1e3);
    }
    const double lod_median = PhaseStats::of(lod_seconds).median_s;
    const double fixed_median = PhaseStats::of(fixed_seconds).median_s;
    const Camera first = camera(0);
    file.rows.push_back({scene.name,
                         scene.surfaces.size(),
                         {device.name, device.kind},
                         point_of(path.centre),
                         point_of(first.target),
                         point_of(first.up),
                         path.radius,
                         lod_median,
                         fixed_median,
                         counts_of(lod_after, lod_before),
                         counts_of(fixed_after, fixed_before),
                         std::move(frames)});
    const std::string kind =
        device.kind == "cpu" ? " (a software rasterizer: CPU figures, not a GPU's)" : "";
    text += fmt::format(
        "000 §3.2 continuous LOD on {} ({} surfaces), gl-pingpong on {} ({}){}:\n{}"
        "median frame: LOD {:.3f} ms, fixed {}x{} {:.3f} ms; host read-backs in the timed frames: "
        "{} (LOD), {} (fixed); device copies {} / {}\n\n",
        scene.name, scene.surfaces.size(), device.name, device.kind, kind, table, lod_median * 1e3,
        fixed.grid_u, fixed.grid_v, fixed_median * 1e3,
        lod_after.host_read_backs - lod_before.host_read_backs,
        fixed_after.host_read_backs - fixed_before.host_read_backs,
        lod_after.device_copies - lod_before.device_copies,
        fixed_after.device_copies - fixed_before.device_copies);
  }
  const Camera sample_camera;
  const gl_pingpong::FlyIn sample_path;
  file.machine = machine_record(threads);
  file.settings = {{"scenes", options.scenes},
                   {"frames", options.frames},
                   {"viewport", fmt::format("{}x{}", width, height)},
                   {"pixels_per_sample", options.pixels_per_sample},
                   {"min_samples", options.min_samples},
                   {"max_samples", options.max_samples},
                   {"fixed_samples", fmt::format("{}x{}", fixed.grid_u, fixed.grid_v)},
                   {"fov_y_degrees", sample_camera.fov_y_degrees},
                   {"direction", point_of(sample_path.direction)},
                   {"far_distance_radii", sample_path.far_distance},
                   {"near_distance_radii", sample_path.near_distance},
                   {"gl", options.gl.empty() ? "egl" : options.gl}};
  const nlohmann::json document = file;
  std::filesystem::create_directories(options.out);
  write_file_atomically(std::filesystem::path(options.out) / "camera_path.json",
                        document.dump(1) + "\n");
  std::cout << text
            << fmt::format(
                   "(LOD: each surface's grid from its projected control polygon, {} pixels per "
                   "sample, {}..{} samples per side; fixed: every surface {}x{}, evaluated again "
                   "every frame; frame = set grids + evaluate + device copy + draw + finish, "
                   "host clock)\n{}/camera_path.json\n",
                   options.pixels_per_sample, options.min_samples, options.max_samples,
                   fixed.grid_u, fixed.grid_v, options.out);
  return 0;
}

}  // namespace nurbs::cli
