#include "strategies/glsl_deboor/renderer.h"

#include "strategies/trim_texture/trim_texture.h"

namespace nurbs::glsl_deboor {
namespace {

std::optional<gl::GridTrim> trim_of(const trim_texture::TrimTextures* trims, std::size_t surface) {
  return trims ? trims->grid_trim(surface) : std::nullopt;
}

}  // namespace

void Renderer::draw_without_read_back(const Evaluator& evaluator, const float mvp[16],
                                      const trim_texture::TrimTextures* trims) {
  grid_.begin_frame();
  for (const Page& page : evaluator.pages())
    for (const SurfaceSlot& s : page.slots) {
      const auto trim = trim_of(trims, s.surface);
      // Sample (a, b) is output texel (b, output_row0 + a).
      grid_.draw(gl::GridPoints{&page.points, s.nu, s.nv, 0, s.output_row0, false}, mvp,
                 trim ? &*trim : nullptr);
    }
  grid_.end_frame("glsl-deboor render (vertex texture fetch)");
}

void Renderer::draw_with_read_back(Evaluator& evaluator, const float mvp[16],
                                   const trim_texture::TrimTextures* trims) {
  evaluator.read_back_into(read_back_);
  grid_.begin_frame();
  for (const Page& page : evaluator.pages())
    for (const SurfaceSlot& s : page.slots) {
      const auto trim = trim_of(trims, s.surface);
      grid_.draw(read_back_.surfaces[s.surface].positions.f32(), s.nu, s.nv, mvp,
                 trim ? &*trim : nullptr);
    }
  grid_.end_frame("glsl-deboor render (read back, vertex buffer)");
}

}  // namespace nurbs::glsl_deboor
