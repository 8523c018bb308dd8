// The --uv reader (harness/uv_file.h) on the inputs issue 14 names: giant lines, many lines, NUL
// bytes, nan/inf/hex floats, -0, whitespace, CRLF, names that read as indices, samples outside a
// surface's domain. Each refusal is one clean line naming the origin, the line, the field and the
// value.
#include "harness/uv_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <streambuf>
#include <string>

#include "reference/error_text.h"
#include "reference/validation.h"
#include "tests/fuzz/uv_test_scene.h"

namespace nurbs {
namespace {

const Scene& two_surfaces() {
  return fuzz::uv_test_scene();
}

Sampling read(const std::string& text) {
  std::istringstream in(text);
  return read_uv_stream(in, "uv.csv", two_surfaces());
}

std::string error_of(const std::string& text) {
  try {
    read(text);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return {};
}

void expect_clean_line(const std::string& message) {
  for (const unsigned char c : message) EXPECT_FALSE(is_control_byte(c)) << message;
}

// Yields `size` bytes of `fill` (then `tail`) without ever holding them, counting what was read.
class GeneratedBuf : public std::streambuf {
 public:
  GeneratedBuf(std::size_t size, char fill, std::string tail = {})
      : remaining_(size), fill_(fill), tail_(std::move(tail)) {}
  std::size_t consumed() const { return consumed_ - static_cast<std::size_t>(egptr() - gptr()); }

 protected:
  int_type underflow() override {
    if (remaining_ > 0) {
      const std::size_t n = std::min(remaining_, sizeof buffer_);
      std::fill_n(buffer_, n, fill_);
      remaining_ -= n;
      consumed_ += n;
      setg(buffer_, buffer_, buffer_ + n);
    } else if (!tail_sent_ && !tail_.empty()) {
      tail_sent_ = true;
      consumed_ += tail_.size();
      setg(tail_.data(), tail_.data(), tail_.data() + tail_.size());
    } else {
      return traits_type::eof();
    }
    return traits_type::to_int_type(*gptr());
  }

 private:
  std::size_t remaining_, consumed_ = 0;
  char fill_;
  std::string tail_;
  bool tail_sent_ = false;
  char buffer_[1 << 16];
};

TEST(UvFile, ReadsNamesIndicesCommentsHeaderCrlfAndBlanks) {
  const Sampling s = read(
      "surface,u,v\r\n# comment\r\n\r\n  patch , 0.25 ,\t1\r\n1,-2,1.5\n0,3.5,2\n  # indented\n"
      "patch,0.1,0.30000000000000004");
  ASSERT_EQ(s.mode, SamplingMode::explicit_list);
  ASSERT_EQ(s.explicit_uv.size(), 2u);
  // "0" is surface 1's name: a name wins over an index.
  ASSERT_EQ(s.explicit_uv[0].size(), 2u);
  ASSERT_EQ(s.explicit_uv[1].size(), 2u);
  EXPECT_EQ(s.explicit_uv[0][0][0], 0.25);
  EXPECT_EQ(s.explicit_uv[0][0][1], 1.0);
  EXPECT_EQ(s.explicit_uv[0][1][1], 0.30000000000000004);
  EXPECT_EQ(s.explicit_uv[1][0][0], -2.0);
  EXPECT_EQ(s.explicit_uv[1][1][0], 3.5);
}

TEST(UvFile, NegativeZeroIsReadAsZero) {
  const Sampling s = read("patch,-0,-0.0\n");
  EXPECT_EQ(s.explicit_uv[0][0][0], 0.0);
  EXPECT_FALSE(std::signbit(s.explicit_uv[0][0][0]));
  EXPECT_FALSE(std::signbit(s.explicit_uv[0][0][1]));
}

TEST(UvFile, SubnormalIsANumberButUnderflowIsRefused) {
  EXPECT_EQ(read("patch,1e-310,0\n").explicit_uv[0][0][0], 1e-310);
  const std::string e = error_of("patch,1e-400,0\n");
  EXPECT_NE(e.find("u = '1e-400': beyond the range of a double"), std::string::npos) << e;
}

TEST(UvFile, HeaderIsOnlyTheFirstDataLineAndOnlyExact) {
  // A surface named like the header's first field is data, not a header.
  EXPECT_NE(error_of("surface1,0.5,0.5\n").find("line 1: surface = 'surface1'"), std::string::npos);
  EXPECT_NE(error_of("patch,0.5,0.5\nsurface,u,v\n").find("line 2: surface = 'surface'"),
            std::string::npos);
}

TEST(UvFile, RefusalsNameLineFieldValueAndRule) {
  struct Case {
    std::string text, expect;
  };
  const Case cases[] = {
      {"patch,nan,0.5\n", "uv.csv: line 1: u = 'nan': must be a finite number in [0, 1]"},
      {"patch,0.5,inf\n", "uv.csv: line 1: v = 'inf': must be a finite number in [0, 1]"},
      {"patch,-inf,0\n", "u = '-inf': must be a finite number"},
      {"patch,0x1p-3,0.5\n", "u = '0x1p-3': must be a decimal number in [0, 1]"},
      {"patch,+0.5,0.5\n", "u = '+0.5': must be a decimal number"},
      {"patch,1e999,0.5\n", "u = '1e999': beyond the range of a double"},
      {"patch,,0.5\n", "u = '': must be a decimal number"},
      {"1,3.6,1.5\n", "line 1: u = '3.6': must be a finite number in [-2, 3.5]"},
      {"1,0,0.5\n", "line 1: v = '0.5': must be a finite number in [1, 2]"},
      {"2,0.5,0.5\n", "surface = '2': not a surface name or an index in 0..1"},
      {"-1,0.5,0.5\n", "surface = '-1'"},
      {"1.0,0.5,0.5\n", "surface = '1.0'"},
      {"18446744073709551617,0.5,0.5\n", "surface = '18446744073709551617'"},
      {"\n\n# c\npatch,0.5\n", "line 4: (line) = 'patch,0.5': expected surface,u,v"},
      {"patch,0.5,0.5,0.5\n", "expected surface,u,v (three fields)"},
      {"# only a comment\n", "uv.csv: no (u,v) samples in file"},
      {"surface,u,v\n", "uv.csv: no (u,v) samples in file"},
      {"", "uv.csv: no (u,v) samples in file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string e = error_of(c.text);
    EXPECT_NE(e.find(c.expect), std::string::npos) << e;
    expect_clean_line(e);
  }
}

TEST(UvFile, ControlBytesAreEscapedInTheMessage) {
  static constexpr char kText[] = "patch,0.5,0\0x\x1b[2J\r\n";
  const std::string e = error_of(std::string(kText, sizeof kText - 1));
  EXPECT_NE(e.find("v = '0\\x00x\\x1b[2J'"), std::string::npos) << e;
  expect_clean_line(e);
}

TEST(UvFile, QuotedValuesAreCut) {
  const std::string e = error_of("patch,0.5," + std::string(1000, '7') + "\n");
  EXPECT_NE(e.find("v = '" + std::string(64, '7') + "...'"), std::string::npos) << e;
  EXPECT_LT(e.size(), 200u);
}

TEST(UvFile, GiantLineIsRefusedWithoutReadingIt) {
  // 1 GiB without a line break: refused after the bound, the rest never read.
  GeneratedBuf buf(std::size_t{1} << 30, '5');
  std::istream in(&buf);
  try {
    read_uv_stream(in, "giant.csv", two_surfaces());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("giant.csv: line 1: (line) = '5555"), std::string::npos) << message;
    EXPECT_NE(message.find("longer than 4096 bytes"), std::string::npos) << message;
    EXPECT_LT(message.size(), 200u);
  }
  EXPECT_LE(buf.consumed(), kMaxUvLineBytes + 1);
}

TEST(UvFile, LineOfExactlyTheBoundIsRead) {
  std::string line = "patch,0.5,0.";
  line += std::string(kMaxUvLineBytes - line.size(), '5');
  ASSERT_EQ(line.size(), kMaxUvLineBytes);
  EXPECT_EQ(read(line + "\n").explicit_uv[0].size(), 1u);
  EXPECT_NE(error_of(line + "5\n").find("longer than 4096 bytes"), std::string::npos);
}

TEST(UvFile, LineNumbersCountPastAMillionLines) {
  // A million comment lines, then a bad sample: streamed, and the line number is exact.
  GeneratedBuf buf(1'000'000, '\n', "patch,2,0\n");
  std::istream in(&buf);
  try {
    read_uv_stream(in, "long.csv", two_surfaces());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("long.csv: line 1000001: u = '2'"), std::string::npos)
        << e.what();
  }
}

TEST(UvFile, ControlBytesOfThePathAreEscapedToo) {
  std::istringstream in("patch,2,0\n");
  try {
    read_uv_stream(in, "evil\nname.csv", two_surfaces());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("evil\\x0aname.csv: line 1: u = '2'"), 0u) << e.what();
  }
}

TEST(UvFile, FileErrorsNameThePath) {
  const Scene scene = two_surfaces();
  for (const auto& [path, expect] :
       {std::pair<std::string, std::string>{"/nonexistent/uv.csv", "cannot open"},
        {"/tmp", "is a directory"}}) {
    try {
      read_uv_file(path, scene);
      ADD_FAILURE() << path;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find(path + ": "), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace nurbs
