// io/image.cpp: images read through stb (and 16-bit greyscale PNG through libspng), PNG
// written through libspng.
#include "io/image.h"

#include <spng.h>

#include <cmath>
#include <cstdlib>

#include <stb/stb_image.h>

#include <cstdint>
#include <limits>

#include "core/file_util.h"

namespace mimetic {
namespace {

constexpr uint64_t kMaxImagePixels = uint64_t{1} << 28;  // 256 Mpixels

// stb_image's terse failure reasons, in words; its own word is kept in parentheses.
std::string FailureText(const char* reason) {
  const std::string r = reason ? reason : "";
  struct Entry {
    const char* stb;
    const char* text;
  };
  static const Entry kTable[] = {
      {"outofdata", "truncated image data (the file ends early)"},
      {"unknown image type", "not an image format stb_image reads"},
      {"first not IHDR", "corrupt PNG: the first chunk is not IHDR"},
      {"bad png sig", "corrupt PNG signature"},
      {"bad IHDR len", "corrupt PNG header"},
      {"too large", "the image is too large"},
      {"outofmem", "out of memory decoding the image"},
      {"bad zlib header", "corrupt PNG: bad compressed data"},
      {"bad huffman code", "corrupt compressed image data"},
      {"no IDAT", "corrupt PNG: no image data chunk"},
      {"not enough pixels", "truncated PNG: not enough pixel data"},
  };
  for (const Entry& e : kTable)
    if (r == e.stb) return std::string(e.text) + " (stb_image: " + r + ")";
  if (r.empty()) return "corrupt or truncated image data (stb_image gave no reason)";
  return "stb_image: " + r;
}

}  // namespace

bool LoadGrayImage(const std::string& path, const std::string& where, const std::string& what,
                   GrayImage* out, Diagnostics* diag) {
  auto fail = [&](const std::string& reason) {
    diag->Error(where, "cannot read " + what + " '" + path + "': " + reason +
                           " (expected a PNG, JPEG, TGA or BMP image)");
    return false;
  };
  std::string bytes;
  Diagnostics read;
  if (!ReadFile(path, &bytes, &read, kMaxImageFileBytes, "image file"))
    return fail(read.items().empty() ? "cannot open" : read.items()[0].what);
  std::string reason;
  if (!DecodeGrayImage(bytes, out, &reason)) return fail(reason);
  return true;
}

bool DecodeGrayImage(const std::string& bytes, GrayImage* out, std::string* reason) {
  auto fail = [&](const std::string& why) {
    *reason = why;
    return false;
  };
  if (bytes.empty()) return fail("the file is empty");
  if (bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    return fail("the file is too large for stb_image");
  const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int length = static_cast<int>(bytes.size());
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(data_in, length, &width, &height, &channels))
    return fail(FailureText(stbi_failure_reason()));
  if (width <= 0 || height <= 0 ||
      static_cast<uint64_t>(width) * static_cast<uint64_t>(height) > kMaxImagePixels)
    return fail("the image is " + std::to_string(width) + "x" + std::to_string(height) +
                " pixels; expected at most " + std::to_string(kMaxImagePixels >> 20) +
                " Mpixels");
  unsigned char* data = stbi_load_from_memory(data_in, length, &width, &height, &channels, 1);
  if (!data) return fail(FailureText(stbi_failure_reason()));
  out->width = width;
  out->height = height;
  out->pixels.assign(data, data + size_t(width) * size_t(height));
  stbi_image_free(data);
  return true;
}

namespace {

// One PNG through libspng, saved atomically: 8-bit RGB or 16-bit greyscale (host-endian
// samples: SPNG_FMT_PNG is the PNG's own layout and libspng swaps). zlib level 3 instead of
// libspng's default 6: `mimetic texture --size 2048` writes its maps in about 1 s less, the
// files 4-5% larger (docs/performance.md); stb_image_write's deflate, used before for 8-bit
// images, was slower still.
bool EncodePng(const std::string& path, int width, int height, uint8_t bit_depth,
               uint8_t color_type, const void* pixels, size_t bytes_in, Diagnostics* d) {
  spng_ctx* ctx = spng_ctx_new(SPNG_CTX_ENCODER);
  if (!ctx) {
    d->Error(path, "PNG encoding failed (libspng: out of memory)");
    return false;
  }
  spng_set_option(ctx, SPNG_ENCODE_TO_BUFFER, 1);
  spng_set_option(ctx, SPNG_IMG_COMPRESSION_LEVEL, 3);
  spng_ihdr ihdr{};
  ihdr.width = uint32_t(width);
  ihdr.height = uint32_t(height);
  ihdr.bit_depth = bit_depth;
  ihdr.color_type = color_type;
  int err = spng_set_ihdr(ctx, &ihdr);
  if (!err)
    err = spng_encode_image(ctx, pixels, bytes_in, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  size_t len = 0;
  void* buffer = err ? nullptr : spng_get_png_buffer(ctx, &len, &err);
  spng_ctx_free(ctx);
  if (err || !buffer) {
    d->Error(path, std::string("PNG encoding failed (libspng: ") + spng_strerror(err) + ")");
    free(buffer);
    return false;
  }
  std::string bytes(static_cast<const char*>(buffer), len);
  free(buffer);
  return WriteFileAtomic(path, bytes, d);
}

}  // namespace

bool SavePng(const std::string& path, const Image& image, Diagnostics* diag) {
  Diagnostics local;
  Diagnostics* d = diag ? diag : &local;
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3) {
    d->Error(path, "image is " + std::to_string(image.width) + "x" +
                       std::to_string(image.height) + " with " +
                       std::to_string(image.rgb.size()) +
                       " bytes; expected positive size and width*height*3 bytes");
    return false;
  }
  return EncodePng(path, image.width, image.height, 8, SPNG_COLOR_TYPE_TRUECOLOR,
                   image.rgb.data(), image.rgb.size(), d);
}

bool SavePng16(const std::string& path, const Gray16Image& image, Diagnostics* diag) {
  Diagnostics local;
  Diagnostics* d = diag ? diag : &local;
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * size_t(image.height)) {
    d->Error(path, "16-bit image is " + std::to_string(image.width) + "x" +
                       std::to_string(image.height) + " with " +
                       std::to_string(image.pixels.size()) +
                       " pixels; expected positive size and width*height pixels");
    return false;
  }
  return EncodePng(path, image.width, image.height, 16, SPNG_COLOR_TYPE_GRAYSCALE,
                   image.pixels.data(), image.pixels.size() * 2, d);
}

bool DecodeGray16Png(const std::string& bytes, Gray16Image* out, std::string* reason) {
  spng_ctx* ctx = spng_ctx_new(0);
  if (!ctx) {
    *reason = "out of memory (libspng)";
    return false;
  }
  spng_set_png_buffer(ctx, bytes.data(), bytes.size());
  spng_set_image_limits(ctx, 1u << 16, 1u << 16);
  spng_ihdr ihdr{};
  int err = spng_get_ihdr(ctx, &ihdr);
  size_t size = 0;
  if (!err && uint64_t(ihdr.width) * ihdr.height > (uint64_t(1) << 28)) err = SPNG_EWIDTH;
  if (!err) err = spng_decoded_image_size(ctx, SPNG_FMT_RGBA16, &size);
  std::vector<uint16_t> rgba;
  if (!err) {
    rgba.resize(size / 2);
    err = spng_decode_image(ctx, rgba.data(), size, SPNG_FMT_RGBA16, SPNG_DECODE_TRNS);
  }
  spng_ctx_free(ctx);
  if (err) {
    *reason = std::string(spng_strerror(err)) + " (libspng)";
    return false;
  }
  out->width = int(ihdr.width);
  out->height = int(ihdr.height);
  out->pixels.resize(size_t(ihdr.width) * ihdr.height);
  for (size_t i = 0; i < out->pixels.size(); ++i) {
    const uint16_t* p = &rgba[4 * i];
    // Grey PNGs come out with r = g = b; colour ones get their Rec. 709 luminance.
    out->pixels[i] = p[0] == p[1] && p[1] == p[2]
                         ? p[0]
                         : uint16_t(std::lround(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]));
  }
  return true;
}

bool LoadGray16Png(const std::string& path, const std::string& where, const std::string& what,
                   Gray16Image* out, Diagnostics* diag) {
  std::string bytes;
  if (!ReadFile(path, &bytes, diag, size_t(256) << 20, what)) return false;
  std::string reason;
  if (!DecodeGray16Png(bytes, out, &reason)) {
    diag->Error(where, "cannot read " + what + " '" + path + "': " + reason + " (expected a PNG image)");
    return false;
  }
  return true;
}

}  // namespace mimetic
