// 000 §4 (Krishnamurthy et al. 2007): the trim texture, shared by the GL strategies that trim
// (gl-pingpong, gl-pingpong-packed, glsl-deboor). Per trimmed surface, at prepare: the trim loops
// tessellated to polygons (trim_polygons.h), each polygon drawn as a triangle fan into an R x R
// texture over the surface's (u, v) domain with odd/even blending, so a texel ends 1 where its
// centre lies inside an odd number of loops. classify(): one pass per surface looks up every
// evaluated sample's texel and writes a mask, which read_mask() returns (SurfaceResult::inside).
// The renderer discards fragments by the same texture (gl::GridTrim).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "strategies/gl_context/grid_renderer.h"
#include "strategies/trim_texture/trim_polygons.h"

namespace nurbs::trim_texture {

class TrimTextures {
 public:
  // Throws RefusedError when the context cannot hold an R x R texture.
  TrimTextures(gl::Context& context, const Options& options, std::string strategy);
  ~TrimTextures();
  TrimTextures(const TrimTextures&) = delete;
  TrimTextures& operator=(const TrimTextures&) = delete;

  // Builds the textures of every trimmed surface of `scene`, sampled at `samples` (tensor
  // grids); drops any previous classification. Throws RefusedError when a grid side exceeds
  // GL_MAX_TEXTURE_SIZE (the mask is one texture per surface).
  void prepare(const Scene& scene, const std::vector<SurfaceSamples>& samples);
  // 000 §3.2 with §4: surface `surface` sampled at a new grid; its sample table and mask are made
  // anew, the trim texture (which depends only on the loops) stays. Nothing for an untrimmed
  // surface; the same limits as prepare().
  void resample(std::size_t surface, const SurfaceSamples& grid);
  // The lookup pass of every trimmed surface (Strategy::classify()); returns true when the device
  // is done.
  bool classify();
  // 1 inside, 0 outside per sample in SurfaceSamples order; empty for an untrimmed surface or
  // before classify().
  std::vector<std::uint8_t> read_mask(std::size_t surface);
  // What the renderer needs to discard the outside of `surface` (null when untrimmed); the grid
  // drawn starts at sample (first_u, first_v).
  std::optional<gl::GridTrim> grid_trim(std::size_t surface, int first_u = 0,
                                        int first_v = 0) const;
  // trim_resolution, trim_tolerance, trim_polygon_vertices, trim_subpixel_bits.
  void add_details(DeviceInfo& device) const;

  const Options& options() const { return options_; }
  int subpixel_bits() const { return subpixel_bits_; }

 private:
  struct Surface;
  void draw_trim(const std::vector<std::vector<Point2>>& polygons, const nurbs::Surface& surface,
                 const gl::Texture& target);
  void make_sample_table(Surface& s, const SurfaceSamples& grid);

  gl::Context& context_;
  Options options_;
  std::string strategy_;
  int subpixel_bits_ = 0;
  std::unique_ptr<gl::Program> fan_, lookup_;
  GLuint vertex_array_ = 0, vertex_buffer_ = 0;
  std::vector<std::unique_ptr<Surface>> surfaces_;  // null for an untrimmed surface
  std::size_t polygon_vertices_ = 0;
  bool classified_ = false;
};

}  // namespace nurbs::trim_texture
