// `eval --uv FILE`: an explicit list of (u, v) samples, CSV lines "surface,u,v" (surface = name
// or index; '#' comments, blank lines and a "surface,u,v" header allowed; fields may be padded
// with spaces; CRLF files read). Every error is one line naming the file, the line number, the
// field and the value; the file is read line by line with each line bounded, so a giant or binary
// file is refused without being read into memory.
#pragma once

#include <istream>
#include <string>
#include <string_view>

#include "reference/sampling.h"
#include "reference/surface.h"

namespace nurbs {

// Far longer than any "surface,u,v" line (two 17-digit numbers and a name), short enough that a
// file with no line breaks costs nothing to refuse.
inline constexpr std::size_t kMaxUvLineBytes = 4096;

// The samples of `path` for `scene`: u and v finite decimal numbers (no hex, nan or inf) within
// the surface's domain, -0 read as 0; at least one sample, at most kMaxSamplesPerRequest.
Sampling read_uv_file(const std::string& path, const Scene& scene);
// The same from a stream; `origin` names it in errors.
Sampling read_uv_stream(std::istream& in, std::string_view origin, const Scene& scene);

}  // namespace nurbs
