// libFuzzer target: COLMAP's binary model; the input is cameras.bin,
// images.bin and points3D.bin separated by "\n@@\n".
#include "core/io/colmap_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  es::WriteFuzzParts({"cameras.bin", "images.bin", "points3D.bin"}, data,
                     size);
  es::ReadAllowingRefusal([] { es::ReadColmapBinary(es::FuzzDir()); });
  return 0;
}
