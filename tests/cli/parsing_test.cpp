// The CLI's value parsers (harness/cli/parsing.h) on what issue 14 names: empty items, blanks,
// repeats, integer overflow, sizes whose product passes the sample limit, control bytes; and
// sample_parameters refusing an absurd request from the sizes alone.
#include "harness/cli/parsing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "harness/metrics.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"

namespace nurbs::cli {
namespace {

template <typename F>
std::string error_of(F&& parse) {
  try {
    parse();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

std::vector<std::string> labels(const std::vector<Sampling>& list) {
  std::vector<std::string> out;
  for (const Sampling& s : list) out.push_back(s.label());
  return out;
}

TEST(ParseList, TrimsBlanksAndRefusesEmptyItems) {
  EXPECT_EQ(parse_list("--x", " a ,\tb,c "), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(parse_list("--x", "").empty());
  EXPECT_TRUE(parse_list("--x", " \t ").empty());
  EXPECT_EQ(error_of([] { parse_list("--x", "a,,b"); }),
            "--x = 'a,,b': item 2 is empty (items are separated by single commas)");
  EXPECT_NE(error_of([] { parse_list("--x", "a,"); }).find("item 2 is empty"), std::string::npos);
  EXPECT_NE(error_of([] { parse_list("--x", ",a"); }).find("item 1 is empty"), std::string::npos);
  EXPECT_NE(error_of([] { parse_list("--x", "a, ,b"); }).find("item 2 is empty"),
            std::string::npos);
}

TEST(ParseList, BoundsTheItemCount) {
  std::string text = "a0";
  for (std::size_t k = 1; k < kMaxListItems; ++k) text += ",a" + std::to_string(k);
  EXPECT_EQ(parse_list("--x", text).size(), kMaxListItems);
  EXPECT_NE(error_of([&] { parse_list("--x", text + ",z"); }).find("more than 1024 items"),
            std::string::npos);
}

TEST(ParseGridList, ReadsGridsAndSquares) {
  EXPECT_EQ(labels(parse_grid_list("--samples", "64x32, 16 ,2x65536")),
            (std::vector<std::string>{"64x32", "16x16", "2x65536"}));
}

TEST(ParseGridList, RefusesEmptyItemsRepeatsAndOverflow) {
  struct Case {
    std::string text, expect;
  };
  const Case cases[] = {
      {"64x64,,", "--samples = '64x64,,': item 2 is empty"},
      {"64x64,", "item 2 is empty"},
      {"", "--samples = '': give at least one grid such as 64x64"},
      {"64x64,64", "--samples = '64x64,64': 64x64 is given twice"},
      {"8x4,8x4", "8x4 is given twice"},
      {"4294967298x2", "'4294967298' must be an integer in 2..65536"},
      {"2x99999999999999999999", "'99999999999999999999' must be an integer in 2..65536"},
      {"65537x2", "'65537' must be an integer in 2..65536"},
      {"-2x2", "'-2' must be an integer"},
      {"+8x8", "'+8' must be an integer"},
      {"8 x8", "'8 ' must be an integer"},
      {"0x10", "'0' must be an integer"},
      {"8X8", "'8X8' must be an integer"},
      {"8x8x8", "'8x8' must be an integer"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string e = error_of([&] { parse_grid_list("--samples", c.text); });
    EXPECT_NE(e.find(c.expect), std::string::npos) << e;
  }
}

TEST(ParseSpanList, RefusesEmptyItemsRepeatsAndOverflow) {
  EXPECT_EQ(labels(parse_span_list("--span-samples", " 4,16 ,4096")),
            (std::vector<std::string>{"span4", "span16", "span4096"}));
  EXPECT_NE(error_of([] { parse_span_list("--span-samples", "4,4"); }).find("span4 is given twice"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_span_list("--span-samples", "4,,8"); }).find("item 2 is empty"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              parse_span_list("--span-samples", "4097");
            }).find("'4097' must be an integer in 1..4096"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              parse_span_list("--span-samples", "2147483648");
            }).find("'2147483648' must be an integer in 1..4096"),
            std::string::npos);
}

TEST(ParseValues, ControlBytesAreEscapedAndLongValuesCut) {
  const std::string e = error_of([] { parse_grid_list("--samples", "8x8\n\x1b[31m"); });
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_NE(e.find("--samples = '8x8\\x0a\\x1b[31m'"), std::string::npos) << e;
  const std::string longer = error_of([] { parse_precision(std::string(5000, 'f')); });
  EXPECT_EQ(longer, "--precision = '" + std::string(64, 'f') + "...': must be f32 or f64");
}

TEST(ParseTrimBand, DecimalsInZeroToOneOnly) {
  EXPECT_EQ(parse_trim_band(std::nullopt), kDefaultTrimBand);
  EXPECT_EQ(parse_trim_band("0.25"), 0.25);
  EXPECT_EQ(parse_trim_band("1e-7"), 1e-7);
  EXPECT_FALSE(std::signbit(parse_trim_band("-0")));
  for (const std::string bad :
       {"0x1p-3", " 0.1", "0.1 ", "+0.1", "1", "-0.1", "nan", "1e-400", ""}) {
    SCOPED_TRACE(bad);
    EXPECT_NE(error_of([&] {
                parse_trim_band(bad);
              }).find("--trim-band = '" + bad + "': must be a number in [0, 1)"),
              std::string::npos);
  }
}

TEST(SceneList, RefusesRepeatsAndEmptyItems) {
  EXPECT_EQ(scene_list(" patch144 , teapot"), (std::vector<std::string>{"patch144", "teapot"}));
  EXPECT_NE(error_of([] {
              scene_list("patch144,teapot,patch144");
            }).find("--scenes = 'patch144,teapot,patch144': 'patch144' is given twice"),
            std::string::npos);
  EXPECT_NE(error_of([] { scene_list(","); }).find("--scenes = ',': item 1 is empty"),
            std::string::npos);
  EXPECT_TRUE(scene_list("").empty());  // the verbs say "--scenes: empty list"
  const std::vector<std::string> all = scene_list("all"), def = scene_list("default");
  EXPECT_EQ(all.size(), def.size() + 2);  // default leaves out many-4096 and many-ducks-64
}

TEST(BackendExtra, RefusesARepeatedKey) {
  EXPECT_EQ(backend_extra("", "3", {"vk-mode=adaptive", "vk-mu=2"}),
            (std::map<std::string, std::string>{
                {"device", "3"}, {"vk-mode", "adaptive"}, {"vk-mu", "2"}}));
  EXPECT_EQ(error_of([] {
              backend_extra("", "", {"vk-mu=1", "vk-mu=2"});
            }),
            "--strategy-option = 'vk-mu=2': vk-mu is given twice");
  EXPECT_NE(error_of([] { backend_extra("", "", {"=2"}); }).find("must be KEY=VALUE"),
            std::string::npos);
  EXPECT_NE(error_of([] { backend_extra("", "1024", {}); }).find("--device = '1024'"),
            std::string::npos);
}

// Each side within bounds, the product not: refused from the sizes, before any list is built.
TEST(SampleParameters, RefusesAbsurdRequestsFromTheSizes) {
  const Scene many = *make_builtin_scene("many-4096");
  const std::string grid = error_of(
      [&] { sample_parameters(many, parse_grid_list("--samples", "65536x65536").front()); });
  EXPECT_NE(grid.find("17592186044416 samples over 4096 surfaces: more than the limit of "
                      "134217728 per request"),
            std::string::npos)
      << grid;

  // 2^20 - 1 non-empty spans along u, 4097 samples each, times 4097 along v: the u list alone
  // would be 34 GB; the count itself passes 2^64 when squared, which must not wrap.
  Surface wide;
  wide.degree_u = wide.degree_v = 1;
  wide.count_u = 1 << 20;
  wide.count_v = 2;
  for (int k = 0; k <= wide.count_u + 1; ++k)
    wide.knots_u.push_back(std::clamp(k - 1, 0, wide.count_u - 1));
  wide.knots_v = {0, 0, 1, 1};
  Scene scene;
  scene.surfaces = {wide};
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = kMaxSpanSteps;
  const std::string spans = error_of([&] { sample_parameters(scene, span); });
  EXPECT_NE(spans.find("17600760242175 samples over 1 surfaces: more than the limit"),
            std::string::npos)
      << spans;

  // Within the limit: built.
  const std::vector<SurfaceSamples> ok =
      sample_parameters(many, parse_grid_list("--samples", "128x256").front());
  ASSERT_EQ(ok.size(), 4096u);
  EXPECT_EQ(ok[0].u.size(), 128u);
  EXPECT_EQ(total_samples(ok), 4096u * 128 * 256);
}

}  // namespace
}  // namespace nurbs::cli
