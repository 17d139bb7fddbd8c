// fuzz/fuzz_image.cpp: the image decoder (DecodeGrayImage: PNG, JPEG, TGA, BMP through stb) on
// arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mimetic::GrayImage image;
  std::string reason;
  mimetic::DecodeGrayImage(std::string(reinterpret_cast<const char*>(data), size), &image,
                           &reason);
  return 0;
}
