// vk-ksquad trims: trim_classify.comp (the single-source direct-trimming classifier as GLSL)
// against the reference classifier on trimmed-plate and the hammer, grid and span grid.
#include "tests/strategies/trim_direct/strategy_trim_check.h"

namespace nurbs {
namespace {

using test::trim_grid;

TEST(vk_ksquad_trim, TrimmedPlateExact) {
  test::expect_trimmed_plate_exact("vk-ksquad");
}
TEST(vk_ksquad_trim, HammerExact) {
  test::expect_hammer_exact("vk-ksquad");
}
// On a span grid the tessellator's own parameters (16.16 fixed point, not the requested lattice,
// and not always a tensor grid) are what is evaluated and scored, so they are what is
// classified: classifying the requested lattice misclassified a sample of the hammer at span16.
TEST(vk_ksquad_trim, HammerSpanGridClassifiesTheTessellatorsSamples) {
  test::expect_strategy_trims_exactly("vk-ksquad", "hammer", test::trim_span_grid(16),
                                      Precision::f32);
}
TEST(vk_ksquad_trim, OptionsRefused) {
  test::expect_strategy_refuses_trim_options("vk-ksquad");
}

TEST(vk_ksquad_trim, AdaptiveModeRefusesTrimmedScenes) {
  StrategyOptions o;
  o.extra["vk-mode"] = "adaptive";
  auto s = find_strategy("vk-ksquad")->create(o);
  EXPECT_THROW(s->prepare(*make_builtin_scene("trimmed-plate"), EvalRequest{trim_grid(8)}),
               RefusedError);
}

// render() discards fragments outside the trim (ksquad.frag): seen from above, the centre of the
// image is trimmed-plate's hole centre, where the background shows through; the same plate
// untrimmed covers it. A pixel over the frame (u about 0.18, v = 0.5) is covered in both.
TEST(vk_ksquad_trim, RenderShowsBackgroundThroughTheHole) {
  StrategyOptions o;
  o.extra = {{"vk-eye", "5,5,30"}, {"vk-center", "5,5,0"}, {"vk-viewport", "256x256"}};
  const auto alpha_at = [](const RenderedImage& image, int x, int y) {
    return image.rgba[4 * (static_cast<std::size_t>(y) * image.width + x) + 3];
  };
  for (const bool trimmed : {true, false}) {
    SCOPED_TRACE(trimmed ? "trimmed" : "untrimmed");
    Scene scene = *make_builtin_scene("trimmed-plate");
    if (!trimmed) scene.surfaces[0].trim.reset();
    auto s = find_strategy("vk-ksquad")->create(o);
    EXPECT_FALSE(s->last_render()) << "nothing drawn yet";
    s->prepare(scene, EvalRequest{test::trim_grid(64)});
    s->evaluate();
    ASSERT_TRUE(s->render());
    const std::optional<RenderedImage> image = s->last_render();
    ASSERT_TRUE(image);
    ASSERT_EQ(image->width, 256);
    ASSERT_EQ(image->height, 256);
    ASSERT_EQ(image->rgba.size(), 256u * 256 * 4);
    // The hole's radius is about 2 units of x at 30 units with a 45 degree field: ~20 pixels.
    EXPECT_EQ(alpha_at(*image, 128, 128), trimmed ? 0 : 255) << "hole centre";
    EXPECT_EQ(alpha_at(*image, 128 - 33, 128), 255) << "frame";
    EXPECT_EQ(alpha_at(*image, 128 + 33, 128), 255) << "frame";
    std::size_t hole = 0;  // background pixels within 10 of the centre
    for (int y = 118; y < 138; ++y)
      for (int x = 118; x < 138; ++x) hole += alpha_at(*image, x, y) == 0;
    EXPECT_EQ(hole, trimmed ? 400u : 0u);
  }
}

}  // namespace
}  // namespace nurbs
