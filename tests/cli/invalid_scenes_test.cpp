// Every file in scenes/invalid/ is fed to the CLI as a user would: `eval`, `run` and `scene` must
// each refuse it with exit code 2 and one stderr line naming the file and everything its
// .expect file lists (field, index, value, surface), and must leave no output behind. Adding a
// case is adding a <case>.json with its <case>.expect (one required substring per line).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "run_cli.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;

const fs::path kInvalidDir = fs::path(NURBSBENCH_SOURCE_DIR) / "scenes" / "invalid";

std::vector<std::string> invalid_cases() {
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(kInvalidDir))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> expected_substrings(const std::string& name) {
  std::vector<std::string> out;
  for (const std::string& line : split_lines(read_text(kInvalidDir / (name + ".expect"))))
    if (!line.empty()) out.push_back(line);
  return out;
}

// The assertions shared by every verb and every bad input: exit 2, one line, the file named and
// every expected substring present.
void expect_rejection(const CliResult& r, const std::string& file,
                      const std::vector<std::string>& substrings) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(is_one_error_line(r.err)) << "stderr:\n" << r.err;
  EXPECT_TRUE(r.err.starts_with("nurbsbench: error: ")) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << "the file is not named: " << r.err;
  for (const std::string& s : substrings)
    EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(InvalidScenesFolder, EveryCaseHasItsExpectation) {
  for (const fs::directory_entry& e : fs::directory_iterator(kInvalidDir)) {
    const fs::path p = e.path();
    if (p.filename() == "README.md") continue;
    ASSERT_TRUE(p.extension() == ".json" || p.extension() == ".expect") << p;
    const fs::path sibling =
        fs::path(p).replace_extension(p.extension() == ".json" ? ".expect" : ".json");
    EXPECT_TRUE(fs::exists(sibling)) << p << " has no " << sibling.filename();
    if (p.extension() == ".json") {
      EXPECT_FALSE(expected_substrings(p.stem().string()).empty()) << p;
    }
  }
  // One case per validation rule (DESIGN.md "Data model") plus the malformed-JSON cases.
  EXPECT_GE(invalid_cases().size(), 40u);
}

class InvalidScene : public ::testing::TestWithParam<std::string> {
 protected:
  std::string file() const { return (kInvalidDir / (GetParam() + ".json")).string(); }
  TempDir tmp_;
};

TEST_P(InvalidScene, EvalRefusesWithOneLineAndWritesNothing) {
  const std::string out = tmp_ / "out.csv";
  const CliResult r =
      run_cli({"eval", "--scene", file(), "--strategy", "cpu-coxdeboor", "--out", out},
              {kRejectionMemoryLimit});
  expect_rejection(r, file(), expected_substrings(GetParam()));
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::is_empty(tmp_.path())) << "no temporary or partial file may be left";
}

TEST_P(InvalidScene, RunRefusesBeforeCreatingTheOutputDirectory) {
  const std::string out = tmp_ / "r";
  const CliResult r =
      run_cli({"run", "--scenes", "patch144," + file(), "--strategies", "cpu-coxdeboor",
               "--samples", "4x4", "--repetitions", "1", "--out", out},
              {kRejectionMemoryLimit});
  expect_rejection(r, file(), expected_substrings(GetParam()));
  EXPECT_FALSE(fs::exists(out));
}

TEST_P(InvalidScene, SceneVerbRefusesAndWritesNothing) {
  const std::string out = tmp_ / "copy.json";
  const CliResult r = run_cli({"scene", file(), "--out", out}, {kRejectionMemoryLimit});
  expect_rejection(r, file(), expected_substrings(GetParam()));
  EXPECT_FALSE(fs::exists(out));
}

INSTANTIATE_TEST_SUITE_P(Files, InvalidScene, ::testing::ValuesIn(invalid_cases()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// 4e9 control points: refused from the counts alone, before the loader allocates anything. The
// folder test above runs it under the same limit; this one states the point on its own.
TEST(InvalidScene, AbsurdCountIsRefusedUnderAMemoryLimit) {
  if (!memory_limit_supported()) GTEST_SKIP() << "no address-space limit under ASan";
  TempDir tmp;
  const std::string file = (kInvalidDir / "count-absurd-product.json").string();
  const CliResult r =
      run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--out", tmp / "o.csv"},
              {kRejectionMemoryLimit});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("count_u * count_v = 4294967296 exceeds"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
}

// Bytes that are not JSON text at all (binary headers, invalid UTF-8, NUL). Generated here
// rather than committed as binary files.
TEST(InvalidScene, NonJsonBytesAreRefused) {
  TempDir tmp;
  const std::vector<std::pair<std::string, std::string>> inputs = {
      {"elf.json", std::string("\x7f"
                               "ELF\x02\x01\x01\x00\x00\xff\xfe\n\r",
                               13)},
      {"invalid-utf8.json", std::string("{\"format\": \"nurbs\xff\xfe\"}")},
      {"nul.json", std::string("\0\0\0\0", 4)},
      {"png.json", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)},
      {"text.json", "this is not a scene\n"},
  };
  for (const auto& [name, bytes] : inputs) {
    SCOPED_TRACE(name);
    const std::string file = tmp / name;
    write_text(file, bytes);
    const std::string out = tmp / "out.csv";
    const CliResult r =
        run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--out", out},
                {kRejectionMemoryLimit});
    expect_rejection(r, file, {"not valid JSON"});
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(InvalidScene, MissingFileIsNamed) {
  TempDir tmp;
  const std::string file = tmp / "no-such-dir/scene.json";
  const CliResult r = run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor"});
  // Not a file, so it is looked up as a built-in name: the message lists the valid ones.
  expect_rejection(r, file, {"neither a file nor a built-in scene", "patch144", "many-N"});
}

}  // namespace
}  // namespace nurbs::test
