// 000 §3.2 continuous LOD on gl-pingpong: each surface evaluated on a grid of its own, changed
// between frames, and drawn from the evaluation output copied on the device into a vertex buffer
// (glReadPixels into a pixel-pack buffer, then bound as the array buffer: no host read-back). A
// GL-free interface: `nurbsbench camera-path` uses it in every build, and without OpenGL
// make_lod_renderer throws the reason.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs::gl_pingpong {

// Since the renderer was made (gl::DrawCounts of its context).
struct LodCounts {
  std::uint64_t draws = 0, passes = 0, host_read_backs = 0, device_copies = 0;
};

class LodRenderer {
 public:
  virtual ~LodRenderer() = default;
  virtual DeviceInfo device() const = 0;
  // Surface `surface` is evaluated on an nu x nv grid over its domain from the next frame on: its
  // parameters and first-span indices (000 §3.1 step 1, on the CPU) and basis targets are made
  // anew; the control points stay on the device. The same size again does nothing.
  virtual void set_grid(std::size_t surface, int nu, int nv) = 0;
  // One frame: every surface evaluated (basis and accumulation passes), its output copied into
  // its vertex buffer on the device, drawn with `mvp` (column-major) into the width x height
  // image, and the device waited for. Returns the triangles drawn.
  virtual std::uint64_t draw_frame(const std::array<float, 16>& mvp) = 0;
  virtual LodCounts counts() const = 0;
  // For tests, outside the frames: each surface's vertex buffer read back to the host (xyz per
  // sample, in SurfaceSamples order) with the samples it was evaluated at.
  virtual std::vector<SurfaceResult> read_vertex_buffers() = 0;
  // The last frame's image.
  virtual RenderedImage picture() = 0;
};

// Every surface starts on a 2x2 grid; a trimmed surface is drawn with its outside discarded by
// gl-pingpong's trim texture (000 §4, built once here; options trim-resolution/trim-tolerance),
// whose sample table follows each new grid. Throws std::runtime_error("unavailable: ...") without
// a GL context, RefusedError for a scene gl-pingpong cannot evaluate (T-splines, degree or net
// beyond its limits).
std::unique_ptr<LodRenderer> make_lod_renderer(const Scene& scene, int width, int height,
                                               const StrategyOptions& options);

}  // namespace nurbs::gl_pingpong
