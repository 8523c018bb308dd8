#include "harness/uv_file.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unordered_map>

#include "harness/cli/parsing.h"
#include "reference/error_text.h"
#include "reference/validation.h"

namespace nurbs {

namespace {

using cli::trim_blanks;

class UvReader {
 public:
  UvReader(std::istream& in, std::string_view origin, const Scene& scene)
      : in_(*in.rdbuf()), origin_(printable(origin)), scene_(scene) {
    // A name two surfaces share means the first (emplace keeps it); the index reaches either.
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
      by_name_.emplace(scene.surfaces[i].name, i);
  }

  Sampling read() {
    Sampling sampling;
    sampling.mode = SamplingMode::explicit_list;
    sampling.explicit_uv.resize(scene_.surfaces.size());
    bool header_allowed = true;
    std::size_t count = 0;
    while (next_line()) {
      if (!line_.empty() && line_.back() == '\r') line_.pop_back();  // CRLF files
      const std::string_view line = trim_blanks(line_);
      if (line.empty() || line.front() == '#') continue;
      const bool may_be_header = header_allowed;
      header_allowed = false;

      std::string_view fields[3];
      std::size_t start = 0;
      for (int f = 0; f < 3; ++f) {
        const std::size_t comma = line.find(',', start);
        if ((comma == std::string_view::npos) != (f == 2))
          fail("(line)", line, "expected surface,u,v (three fields)");
        fields[f] = trim_blanks(line.substr(start, comma - start));
        start = comma + 1;
      }
      if (may_be_header && fields[0] == "surface" && fields[1] == "u" && fields[2] == "v") continue;

      const std::size_t surface = surface_index(fields[0]);
      const Surface& s = scene_.surfaces[surface];
      const double u = parameter("u", fields[1], s.u_min(), s.u_max());
      const double v = parameter("v", fields[2], s.v_min(), s.v_max());
      if (++count > kMaxSamplesPerRequest)
        fail("(line)", line,
             fmt::format("more than the limit of {} samples per request", kMaxSamplesPerRequest));
      sampling.explicit_uv[surface].push_back({u, v});
    }
    if (count == 0) throw InputError(fmt::format("{}: no (u,v) samples in file", origin_));
    return sampling;
  }

 private:
  [[noreturn]] void fail(std::string_view field, std::string_view value,
                         std::string_view rule) const {
    throw InputError(fmt::format("{}: line {}: {} = '{}': {}", origin_, line_number_, field,
                                 printable(value, kQuotedValueBytes), rule));
  }

  // The next line into line_, without its '\n'; false at the end. A line past kMaxUvLineBytes is
  // refused after reading one byte more than the bound, never read whole.
  bool next_line() {
    try {
      return next_line_unchecked();
    } catch (const std::ios_base::failure& e) {  // libstdc++'s filebuf throws on a read error
      throw InputError(fmt::format("{}: read error after line {}: {}", origin_, line_number_,
                                   printable(e.what())));
    }
  }

  bool next_line_unchecked() {
    line_.clear();
    int c = in_.sbumpc();
    if (c == std::char_traits<char>::eof()) return false;
    ++line_number_;
    while (c != std::char_traits<char>::eof() && c != '\n') {
      if (line_.size() == kMaxUvLineBytes)
        fail("(line)", line_, fmt::format("longer than {} bytes", kMaxUvLineBytes));
      line_ += static_cast<char>(c);
      c = in_.sbumpc();
    }
    return true;
  }

  std::size_t surface_index(std::string_view field) const {
    if (const auto named = by_name_.find(std::string(field)); named != by_name_.end())
      return named->second;
    std::size_t index = 0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), index);
    if (field.empty() || error != std::errc() || end != field.data() + field.size() ||
        index >= scene_.surfaces.size())
      fail("surface", field,
           fmt::format("not a surface name or an index in 0..{}", scene_.surfaces.size() - 1));
    return index;
  }

  // from_chars, not strtod: no locale, no hex floats, no leading blanks or '+' -- the decimal
  // form a CSV writer produces; nan and inf are read, then refused as not finite.
  double parameter(std::string_view field, std::string_view text, double lo, double hi) const {
    double value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    const std::string range = fmt::format("[{}, {}]", format_number(lo), format_number(hi));
    if (text.empty() || end != text.data() + text.size() ||
        (error != std::errc() && error != std::errc::result_out_of_range))
      fail(field, text, "must be a decimal number in " + range);
    if (error == std::errc::result_out_of_range)
      fail(field, text, "beyond the range of a double; must be in " + range);
    if (!std::isfinite(value) || value < lo || value > hi)
      fail(field, text, "must be a finite number in " + range);
    return value + 0.0;  // -0 is the domain's 0: evaluated there and written back as 0
  }

  std::streambuf& in_;
  std::string origin_;  // a path may hold control bytes too
  const Scene& scene_;
  std::unordered_map<std::string, std::size_t> by_name_;
  std::string line_;
  std::size_t line_number_ = 0;
};

}  // namespace

Sampling read_uv_stream(std::istream& in, std::string_view origin, const Scene& scene) {
  return UvReader(in, origin, scene).read();
}

Sampling read_uv_file(const std::string& path, const Scene& scene) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored))
    throw InputError(fmt::format("{}: is a directory, not a (u,v) file", printable(path)));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open (u,v) file", printable(path)));
  return read_uv_stream(in, path, scene);
}

}  // namespace nurbs
