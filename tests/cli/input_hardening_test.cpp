// Issue 14's input hardening as a user meets it: the real binary, bad --uv files and list values,
// exit code 2 with one clean stderr line naming the file or option, nothing written, and every
// refusal made before anything large is allocated (under a 1 GiB address-space limit).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "reference/error_text.h"
#include "run_cli.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;

void expect_refused(const CliResult& r, const std::vector<std::string>& substrings) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(is_one_error_line(r.err)) << "stderr:\n" << r.err;
  for (const unsigned char c : r.err.substr(0, r.err.size() - 1))
    EXPECT_FALSE(is_control_byte(c)) << "control byte in: " << r.err;
  for (const std::string& s : substrings)
    EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
}

CliResult eval_uv(const std::string& uv, const std::string& out) {
  return run_cli(
      {"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--uv", uv, "--out", out},
      {kRejectionMemoryLimit});
}

TEST(CliInput, UvFileWithoutLineBreaksIsRefusedAtTheLineBound) {
  // /dev/zero: an endless line of NUL bytes. Refused after 4 KiB, the rest never read.
  TempDir tmp;
  const std::string out = tmp / "out.csv";
  expect_refused(eval_uv("/dev/zero", out),
                 {"/dev/zero: line 1: (line) = '\\x00\\x00", "longer than 4096 bytes"});
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliInput, UvFileRefusalsAreOneCleanLine) {
  TempDir tmp;
  const std::string out = tmp / "out.csv";
  struct Case {
    std::string text;
    std::vector<std::string> expect;
  };
  static constexpr char kControlBytes[] = "0,0.5,0.5\n0,0.5\0\r\x1b[1m\n";
  const std::vector<Case> cases = {
      {std::string(kControlBytes, sizeof kControlBytes - 1),
       {"line 2", "'0,0.5\\x00\\x0d\\x1b[1m'"}},
      {"0,0x1p-3,0.5\n", {"line 1", "u = '0x1p-3'", "decimal number"}},
      {"0,inf,0.5\n", {"line 1", "u = 'inf'", "finite"}},
      {"0,0.5," + std::string(100000, '1') + "\n", {"line 1", "longer than 4096 bytes"}},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(k);
    const std::string uv = tmp / ("uv" + std::to_string(k) + ".csv");
    write_text(uv, cases[k].text);
    std::vector<std::string> expect = cases[k].expect;
    expect.push_back(uv + ": ");
    expect_refused(eval_uv(uv, out), expect);
    EXPECT_FALSE(fs::exists(out));
  }
  expect_refused(eval_uv(tmp.path().string(), out), {"is a directory"});
}

TEST(CliInput, UvFileNegativeZeroIsWrittenAsZero) {
  TempDir tmp;
  const std::string uv = tmp / "uv.csv";
  write_text(uv, " 0 , -0 , -0.0 \r\n");
  const CliResult r =
      run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--uv", uv});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_TRUE(lines[1].starts_with("0,0,0,")) << lines[1];
}

TEST(CliInput, ListValuesAreRefusedWithTheOption) {
  TempDir tmp;
  const std::string out = tmp / "r";
  struct Case {
    std::vector<std::string> args, expect;
  };
  const std::vector<Case> cases = {
      {{"--samples", "64x64,,"}, {"--samples = '64x64,,'", "item 2 is empty"}},
      {{"--samples", "8x8,8"}, {"--samples = '8x8,8'", "8x8 is given twice"}},
      {{"--samples", "8x8\nrm -rf"}, {"--samples = '8x8\\x0arm -rf'"}},
      {{"--span-samples", "4,4"}, {"--span-samples = '4,4'", "span4 is given twice"}},
      {{"--samples", "4294967298x2"}, {"'4294967298' must be an integer in 2..65536"}},
      {{"--scenes", "patch144,patch144"}, {"--scenes", "'patch144' is given twice"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.expect.front());
    std::vector<std::string> args = {
        "run", "--strategies", "cpu-coxdeboor", "--repetitions", "1", "--out", out};
    if (c.args.front() != "--scenes") args.insert(args.end(), {"--scenes", "patch144"});
    args.insert(args.end(), c.args.begin(), c.args.end());
    expect_refused(run_cli(args, {kRejectionMemoryLimit}), c.expect);
    EXPECT_FALSE(fs::exists(out));
  }
  const std::string csv = tmp / "out.csv";
  expect_refused(
      run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--samples", "4x4",
               "--strategy-option", "vk-mu=1", "--strategy-option", "vk-mu=2", "--out", csv}),
      {"--strategy-option = 'vk-mu=2'", "vk-mu is given twice"});
  EXPECT_FALSE(fs::exists(csv));
}

TEST(CliInput, AbsurdSamplingsOfManySurfacesAreRefusedBeforeAllocating) {
  // 4096 surfaces: the parameter lists alone would be 4 GiB (grid) or 3 GiB (span grid).
  TempDir tmp;
  const std::string out = tmp / "out.csv";
  for (const std::vector<std::string>& sampling :
       {std::vector<std::string>{"--samples", "65536x65536"}, {"--span-samples", "4096"}}) {
    SCOPED_TRACE(sampling.front());
    std::vector<std::string> args = {"eval",          "--scene", "many-4096", "--strategy",
                                     "cpu-coxdeboor", "--out",   out};
    args.insert(args.end(), sampling.begin(), sampling.end());
    expect_refused(run_cli(args, {kRejectionMemoryLimit}),
                   {"samples over 4096 surfaces: more than the limit of 134217728"});
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
}  // namespace nurbs::test
