# cmake -DINPUT=f -DOUTPUT=f.cpp -DSYMBOL=name -P embed_file.cmake
file(READ ${INPUT} hex HEX)
if(PREFIX)
  # PREFIX's bytes, a newline, then INPUT's (nurbsbench_embed_kernel_header).
  file(READ ${PREFIX} prefix_hex HEX)
  set(hex "${prefix_hex}0a${hex}")
endif()
string(LENGTH "${hex}" hex_length)
math(EXPR size "${hex_length} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(REGEX REPLACE "(0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f],0x[0-9a-f][0-9a-f])" "\\1\n" bytes "${bytes}")
file(WRITE ${OUTPUT} "// Generated from ${INPUT} by embed_file.cmake. Do not edit.
#include <string_view>
namespace nurbs::embedded {
namespace {
const unsigned char data[] = {
${bytes}0x00};
}  // namespace
extern const std::string_view ${SYMBOL};
const std::string_view ${SYMBOL}(reinterpret_cast<const char*>(data), ${size});
}  // namespace nurbs::embedded
")
