// The OpenImageIO module: the only code that touches OpenImageIO, built as a shared module that
// image_file.cpp loads on the first image written (see image_file.h for why).
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "harness/image_file.h"

extern "C" __attribute__((visibility("default"))) void nurbsbench_write_image_file(
    const nurbs::ImageFile& image, const char* path, std::string& error) {
  try {
    const OIIO::TypeDesc stored = image.uint8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    OIIO::ImageSpec spec(image.width, image.height, image.channels, stored);
    if (!image.channel_names.empty()) spec.channelnames = image.channel_names;
    for (const auto& [name, value] : image.text_attributes) spec.attribute(name, value);
    for (const auto& [name, value] : image.float_attributes) spec.attribute(name, value);
    for (const auto& [name, value] : image.int_attributes) spec.attribute(name, value);
    OIIO::ImageBuf buffer(spec);
    const OIIO::ROI all(0, image.width, 0, image.height, 0, 1, 0, image.channels);
    const bool set = image.pixels.empty()
                         ? buffer.set_pixels(all, OIIO::TypeDesc::UINT8, image.bytes.data())
                         : buffer.set_pixels(all, OIIO::TypeDesc::FLOAT, image.pixels.data());
    if (!set) {
      error = "cannot set the pixels: " + buffer.geterror();
      return;
    }
    for (const nurbs::ImageText& t : image.texts)
      OIIO::ImageBufAlgo::render_text(buffer, t.x, t.y, t.text, t.size, image.font,
                                      OIIO::cspan<float>(t.colour.data(), t.colour.size()));
    if (!buffer.write(path)) error = "cannot write image: " + buffer.geterror();
  } catch (const std::exception& e) {
    error = e.what();
  }
}
