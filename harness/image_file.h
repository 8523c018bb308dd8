// An image as the harness paints it (error heat maps, rendered pictures, trim masks), and the one
// call that writes it to a file, EXR or PNG by the extension.
//
// OpenImageIO writes the file, from a module of its own (image_file_oiio.cpp) that is loaded on the
// first write, not linked into the binary: OpenImageIO pulls in some 260 shared libraries (codecs,
// OpenVDB, DICOM...) whose loading costs about 0.4 s of CPU on every start of any program linking
// it. The CLI starts once per command, per isolated measurement server and, in the tests, hundreds
// of times; only the commands that write an image pay for OpenImageIO now.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace nurbs {

struct ImageText {
  int x = 0, y = 0;  // the baseline's left end, in pixels from the top left
  std::string text;
  int size = 12;  // pixels
  std::array<float, 3> colour{};
};

struct ImageFile {
  int width = 0, height = 0, channels = 0;
  bool uint8 = false;  // the file's pixel type: 8-bit (PNG) or 32-bit float (EXR)
  // width * height * channels values, interleaved, row 0 at the top: either floats (converted to
  // the file's type by OpenImageIO, 0..1 for 8-bit files) or, for an 8-bit file, the bytes as they
  // are. Exactly one of the two is filled.
  std::vector<float> pixels;
  std::vector<std::uint8_t> bytes;
  std::vector<std::string> channel_names;  // empty: OpenImageIO's defaults (R, G, B, A)
  std::vector<std::pair<std::string, std::string>> text_attributes;
  std::vector<std::pair<std::string, float>> float_attributes;
  std::vector<std::pair<std::string, int>> int_attributes;
  std::vector<ImageText> texts;  // drawn over the pixels, in `font`
  std::string font;
};

// Whether this build can write image files at all (the OpenImageIO module was built).
bool image_files_built();

// Writes `image` to `path` (its extension names the format) through a temporary file in the same
// directory and a rename, so a failed write leaves nothing behind. Throws std::runtime_error naming
// the path when the module cannot be loaded or the write fails.
void write_image_file(const std::filesystem::path& path, const ImageFile& image);

}  // namespace nurbs

// The module's entry point (image_file_oiio.cpp), looked up by name after dlopen: writes `image`
// to `path` as it is, or sets `error`.
extern "C" void nurbsbench_write_image_file(const nurbs::ImageFile& image, const char* path,
                                            std::string& error);
