// core/image.h: 8-bit images in memory (decoding and encoding live in io/image.h).
#pragma once

#include <cstdint>
#include <vector>

namespace mimetic {

// 8-bit RGB, rows top to bottom, 3 bytes per pixel (width * height * 3 bytes).
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

// 8-bit grey levels, rows top to bottom (width * height bytes).
// 16-bit grey levels (the fine-scale height maps, docs/model.md §22): 0 black, 65535 white.
struct Gray16Image {
  int width = 0, height = 0;
  std::vector<uint16_t> pixels;
  bool empty() const { return pixels.empty(); }
};

struct GrayImage {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;
  bool empty() const { return pixels.empty(); }
};

}  // namespace mimetic
