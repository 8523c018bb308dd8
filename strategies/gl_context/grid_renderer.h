// Drawing evaluated grids as triangles into an offscreen framebuffer (RGBA8 + depth), shared by
// the GL strategies that draw (glsl-deboor, gl-pingpong): either straight from a strategy's output
// texture by vertex texture fetch (002 §4.2, no read-back; the index buffer is static, built once
// per grid size), or the traditional way from host points (002 §4.1). A trimmed surface's
// fragments outside its trim are discarded by a trim-texture lookup (000 §4).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "strategies/gl_context/gl_program.h"

namespace nurbs::gl {

// Where a grid of nu x nv evaluated points lies in a float texture (xyz in .rgb): sample (a, b)
// at texel origin + (a, b) when u runs along x, else origin + (b, a).
struct GridPoints {
  const Texture* texture = nullptr;
  int nu = 0, nv = 0;
  int origin_x = 0, origin_y = 0;
  bool u_along_x = true;
};

// A trimmed surface's trim texture (R8, 0 = trimmed away; u along x) and its sample table (RG32F,
// row 0 the u samples, row 1 the v samples, .g = the sample in trim-texture coordinates [0, 1]);
// the grid's first sample is (first_u, first_v) of the table (tiles of a larger grid).
struct GridTrim {
  const Texture* trim = nullptr;
  const Texture* parameters = nullptr;
  int first_u = 0, first_v = 0;
};

// Two triangles per grid cell of an nu x nv grid whose vertex k is b * nu + a: (nu - 1)(nv - 1)
// cells, 6 indices each.
std::vector<GLuint> grid_triangle_indices(int nu, int nv);

// Column-major orthographic view looking down -z at the scene's control-point bounding box,
// scaled so the box fits in 90% of clip space in every axis (so nothing is clipped).
std::array<float, 16> orthographic_view(const Scene& scene);

class GridRenderer {
 public:
  GridRenderer(Context& context, int width, int height);
  ~GridRenderer();
  GridRenderer(const GridRenderer&) = delete;
  GridRenderer& operator=(const GridRenderer&) = delete;

  // Binds the framebuffer, clears colour (transparent black) and depth.
  void begin_frame();
  // 002 §4.2: positions fetched from the output texture. `trim` null: the whole grid.
  void draw(const GridPoints& grid, const float mvp[16], const GridTrim* trim);
  // 002 §4.1: positions read back to the host, in SurfaceSamples order (sample (a, b) at
  // xyz[(a * nv + b) * 3]), re-uploaded as a vertex buffer.
  void draw(const float* xyz, int nu, int nv, const float mvp[16], const GridTrim* trim);
  // 000 §3.2: the evaluated points copied on the device into `vertex_buffer` (RGBA32F texels, the
  // grid's sample (a, b) at texel a * nv + b: a u x v output texture read row by row into a
  // pixel-pack buffer), drawn as a vertex buffer without passing through the host. `trim` null:
  // the whole grid. Returns the triangles drawn (before any fragment is discarded).
  std::uint64_t draw_device_points(GLuint vertex_buffer, int nu, int nv, const float mvp[16],
                                   const GridTrim* trim);
  void end_frame(std::string_view where);

  // The steps of a draw from host points that Krishnamurthy's LOD repeats at every change of
  // resolution (002 §2, Fig 15's baseline), callable without drawing: the points (SurfaceSamples
  // order) uploaded as the vertex buffer, and the nu x nv index buffer generated on the host and
  // uploaded again (a cached one is replaced). The latter returns the element count GL holds.
  void upload_vertices(const float* xyz, int nu, int nv);
  GLsizei rebuild_index_buffer(int nu, int nv);

  // The image, RGBA8, rows bottom-up as GL gives them.
  std::vector<unsigned char> image();
  // The same, rows top to bottom (Strategy::last_render).
  RenderedImage picture();
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  struct Variant {
    std::unique_ptr<Program> program;
    GLint mvp, nu, v_major, trimmed, first_sample;
  };
  Variant variant(bool fetch);
  void set_common(const Variant& v, const float mvp[16], int nu, const GridTrim* trim,
                  bool v_major = false);
  GLsizei index_buffer(int nu, int nv);  // built once per size, then reused; binds it

  Context& context_;
  int width_, height_;
  GLuint framebuffer_ = 0, color_ = 0, depth_ = 0, vertex_array_ = 0, vertex_buffer_ = 0;
  Variant fetch_, traditional_;
  GLint origin_ = -1, u_along_x_ = -1;
  std::map<std::pair<int, int>, std::pair<GLuint, GLsizei>> index_buffers_;
  std::vector<float> vertices_;
};

// Strategy::last_render() of a GL strategy whose renderer, created at its first draw, is
// `renderer` (null: nothing drawn yet).
std::optional<RenderedImage> last_picture(Context& context, GridRenderer* renderer);

}  // namespace nurbs::gl
