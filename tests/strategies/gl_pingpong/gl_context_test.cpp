// The shared GL plumbing: both platforms in one process (interleaved, each call reaching its own
// driver through its own function table), draws counted one by one, renderer strings, shader errors
// carrying the compiler log and becoming a `failed` record, and a missing EGL display becoming
// `unavailable: reason`.
#include "strategies/gl_context/gl_context.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/gl_program.h"
#include "strategies/registry.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

namespace embedded_shaders {
constexpr const char* kVertex = "#version 330 core\nvoid main() { gl_Position = vec4(0.0); }\n";
constexpr const char* kFragment =
    "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";
constexpr const char* kBrokenFragment =
    "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(undeclared_name); }\n";
}  // namespace embedded_shaders

bool both_available() {
  return gl::Context::probe(gl::Platform::osmesa).available &&
         gl::Context::probe(gl::Platform::egl).available;
}

TEST(GlContext, OsmesaAndEglInOneProcessInterleaved) {
  if (!both_available()) GTEST_SKIP() << "needs both OSMesa and EGL";
  auto osmesa = gl::Context::create(gl::Platform::osmesa);
  auto egl = gl::Context::create(gl::Platform::egl);
  EXPECT_EQ(osmesa->description(), "osmesa");
  EXPECT_NE(egl->description().find("egl"), std::string::npos);
  for (gl::Context* c : {osmesa.get(), egl.get(), osmesa.get(), egl.get()}) {
    c->make_current();
    EXPECT_FALSE(c->renderer().empty());
    EXPECT_FALSE(c->version().empty());
    EXPECT_GE(c->max_texture_size(), 1024);
    // A float render target written and read back through this context's own table.
    gl::Texture t(*c, GL_RGBA32F, 3, 2, true);
    t.bind_target();
    c->gl().ClearColor(0.25f, 0.5f, 0.75f, 1.0f);
    c->gl().Clear(GL_COLOR_BUFFER_BIT);
    float texels[3 * 2 * 4] = {};
    c->read_pixels(0, 0, 3, 2, GL_RGBA, GL_FLOAT, texels);
    c->check("clear and read back");
    EXPECT_EQ(texels[0], 0.25f);
    EXPECT_EQ(texels[23], 1.0f);
  }
}

// Context::draw_arrays / draw_arrays_instanced / draw_elements are the only way to draw (Functions
// has no glDraw*), so the pass counts strategies record are counted. The counter must advance by
// exactly one per draw, an instanced draw of 4 instances included -- checked after every draw
// here, and in total against GL's own count of the triangles it was given
// (GL_PRIMITIVES_GENERATED; one triangle per draw or instance) -- and a pass is a framebuffer
// binding drawn into: a binding without a draw is none.
TEST(GlContext, DrawCountsAreTheDrawsIssued) {
  for (gl::Platform platform : {gl::Platform::osmesa, gl::Platform::egl}) {
    if (!gl::Context::probe(platform).available) continue;
    SCOPED_TRACE(std::string(gl::to_string(platform)));
    auto c = gl::Context::create(platform);
    c->make_current();
    const gl::Functions& gl = c->gl();
    gl::Program program(*c, embedded::gl_fullscreen_triangle_vert, embedded_shaders::kFragment, "",
                        "draw count");
    gl::Texture a(*c, GL_RGBA32F, 4, 4, true), b(*c, GL_RGBA32F, 4, 4, true);
    GLuint vertex_array = 0, indices = 0, query = 0;
    gl.GenVertexArrays(1, &vertex_array);
    gl.BindVertexArray(vertex_array);
    gl.GenBuffers(1, &indices);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
    const GLuint triangle[] = {0, 1, 2};
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof triangle, triangle, GL_STATIC_DRAW);
    gl.UseProgram(program.id());
    gl.GenQueries(1, &query);

    const gl::DrawCounts start = c->draw_counts();
    std::uint64_t issued = 0, triangles = 0;
    auto draw = [&](bool elements, int instances = 0) {
      if (elements)
        c->draw_elements(GL_TRIANGLES, 3, GL_UNSIGNED_INT, nullptr);
      else if (instances > 0)
        c->draw_arrays_instanced(GL_TRIANGLES, 0, 3, instances);
      else
        c->draw_arrays(GL_TRIANGLES, 0, 3);
      ++issued;
      triangles += instances > 0 ? instances : 1;
      EXPECT_EQ((c->draw_counts() - start).draws, issued);
    };
    gl.BeginQuery(GL_PRIMITIVES_GENERATED, query);
    a.bind_target();  // pass 1: three draws into a
    draw(false);
    draw(true);
    draw(false);
    b.bind_target();  // pass 2
    draw(true);
    a.bind_target();  // bound, never drawn into: no pass
    b.bind_target();  // pass 3: the same target bound again is another pass
    draw(false);
    draw(false, 4);
    gl.EndQuery(GL_PRIMITIVES_GENERATED);
    c->finish("draw count");
    GLuint64 primitives = 0;
    gl.GetQueryObjectui64v(query, GL_QUERY_RESULT, &primitives);
    c->check("draw count");

    const gl::DrawCounts counted = c->draw_counts() - start;
    EXPECT_EQ(counted.draws, 6u);
    EXPECT_EQ(primitives, triangles);
    EXPECT_EQ(triangles, 9u);
    EXPECT_EQ(counted.passes, 3u);
    gl.DeleteQueries(1, &query);
    gl.DeleteBuffers(1, &indices);
    gl.DeleteVertexArrays(1, &vertex_array);
  }
}

TEST(GlContext, PlatformOptionParsing) {
  EXPECT_EQ(gl::platform_option(StrategyOptions{}), gl::Platform::egl);
  StrategyOptions o;
  o.extra["gl"] = "osmesa";
  EXPECT_EQ(gl::platform_option(o), gl::Platform::osmesa);
  o.extra["gl"] = "glx";
  EXPECT_THROW(gl::platform_option(o), std::invalid_argument);
}

TEST(GlContext, ShaderErrorCarriesTheCompilerLog) {
  if (!gl::Context::probe(gl::Platform::osmesa).available) GTEST_SKIP();
  auto context = gl::Context::create(gl::Platform::osmesa);
  try {
    gl::Program p(*context, embedded_shaders::kVertex, embedded_shaders::kBrokenFragment, "",
                  "broken.frag");
    FAIL() << "a broken shader compiled";
  } catch (const gl::ShaderError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("broken.frag"), std::string::npos) << what;
    EXPECT_NE(what.find("undeclared_name"), std::string::npos) << what;  // the driver's log
  }
}

// The runner turns a shader error into `failed: <log>` and goes on: a strategy entry whose
// factory compiles a broken program, measured like any other.
TEST(GlContext, ShaderErrorIsAFailedRecordNotACrash) {
  if (!gl::Context::probe(gl::Platform::osmesa).available) GTEST_SKIP();
  StrategyEntry broken = *find_strategy("gl-pingpong");
  broken.create = [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
    auto context = gl::Context::create(gl::Platform::osmesa);
    gl::Program p(*context, embedded_shaders::kVertex, embedded_shaders::kBrokenFragment, "",
                  "broken.frag");
    return nullptr;
  };
  ReferenceCache references;
  Sampling grid;
  grid.grid_u = grid.grid_v = 4;
  const Record r = measure(broken, StrategyOptions{}, *make_builtin_scene("patch144"),
                           EvalRequest{grid, Precision::f32, false}, 1, references);
  EXPECT_EQ(r.status, Status::failed);
  EXPECT_NE(r.reason.find("undeclared_name"), std::string::npos) << r.reason;
}

// No EGL vendor at all (glvnd finds no ICD): creating an EGL context says why, the probe says
// unavailable, and nothing crashes. Runs in its own process (gtest_discover_tests), so the
// environment variable is read by libEGL's first use here.
TEST(GlContextNoEglDisplay, UnavailableWithReason) {
  setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/vendor.json", 1);
  setenv("__EGL_VENDOR_LIBRARY_DIRS", "/nonexistent", 1);
  try {
    gl::Context::create(gl::Platform::egl);
    FAIL() << "an EGL context without any EGL vendor";
  } catch (const gl::UnavailableError& e) {
    EXPECT_NE(std::string(e.what()).find("EGL"), std::string::npos) << e.what();
  }
  const Availability a = gl::Context::probe(gl::Platform::egl);
  EXPECT_FALSE(a.available);
  EXPECT_FALSE(a.reason.empty());
  // The strategy asked for EGL reports it as a failed record naming the cause.
  ReferenceCache references;
  Sampling grid;
  grid.grid_u = grid.grid_v = 4;
  StrategyOptions egl;
  egl.extra["gl"] = "egl";
  const Record r = measure(*find_strategy("gl-pingpong"), egl, *make_builtin_scene("patch144"),
                           EvalRequest{grid, Precision::f32, false}, 1, references);
  EXPECT_NE(r.status, Status::ok);
  EXPECT_NE(r.reason.find("unavailable"), std::string::npos) << r.reason;
}

}  // namespace
}  // namespace nurbs
