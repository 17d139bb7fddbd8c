// io/image.cpp: image files through stb.
#include "io/image.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>  // Debian's libstb.so holds the implementation (-lstb)

#include "core/file_util.h"

namespace mimetic {
namespace {

void WriteToString(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<size_t>(size));
}

}  // namespace

bool LoadGrayImage(const std::string& path, const std::string& where, const std::string& what,
                   GrayImage* out, Diagnostics* diag) {
  int width = 0, height = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 1);
  if (!data) {
    const char* reason = stbi_failure_reason();
    diag->Error(where, "cannot read " + what + " '" + path +
                           "': " + (reason ? reason : "unknown error") +
                           " (expected a PNG, JPEG, TGA or BMP image)");
    return false;
  }
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
