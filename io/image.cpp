// io/image.cpp: image files through stb.
#include "io/image.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>  // Debian's libstb.so holds the implementation (-lstb)

#include <cstdint>
#include <limits>

#include "core/file_util.h"

namespace mimetic {
namespace {

constexpr uint64_t kMaxImagePixels = uint64_t{1} << 28;  // 256 Mpixels

void WriteToString(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<size_t>(size));
}

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
  std::string bytes;
  const int ok = stbi_write_png_to_func(WriteToString, &bytes, image.width, image.height, 3,
                                        image.rgb.data(), image.width * 3);
  if (!ok || bytes.empty()) {
    d->Error(path, "PNG encoding failed (stb_image_write)");
    return false;
  }
  return WriteFileAtomic(path, bytes, d);
}

}  // namespace mimetic
