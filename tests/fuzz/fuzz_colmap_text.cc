// libFuzzer target: COLMAP's text model; the input is cameras.txt,
// images.txt and points3D.txt separated by "\n@@\n".
#include "core/io/colmap_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  es::WriteFuzzParts({"cameras.txt", "images.txt", "points3D.txt"}, data,
                     size);
  es::ReadAllowingRefusal([] { es::ReadColmapText(es::FuzzDir()); });
  return 0;
}
