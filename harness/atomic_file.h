// Files are replaced atomically (write a sibling temporary, then rename), so a reader, or a run
// that is interrupted, never sees a half-written file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace nurbs {

// Throws std::runtime_error naming the path when it cannot write.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);
// The whole file as bytes (what write_file_atomically wrote, or a child's answer); throws
// std::runtime_error naming the path when it cannot read.
std::string read_whole_file(const std::filesystem::path& path);

}  // namespace nurbs
