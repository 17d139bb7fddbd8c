// io/image.h: image files read through stb (Debian's libstb: PNG, JPEG, TGA, BMP) and libspng
// (16-bit greyscale PNG); every PNG written through libspng.
#pragma once

#include <string>

#include "core/diagnostics.h"
#include "core/image.h"

namespace mimetic {

// Reads any image stb_image reads (PNG, JPEG, TGA, BMP, ...) as 8-bit grey levels. On failure
// records `where: cannot read <what> '<path>': <reason> (expected a PNG, JPEG, TGA or BMP
// image)` and returns false. The file must be a regular file of at most 256 MiB (ReadFile) and
// at most 256 Mpixels; the reason is stb_image's, in words ("truncated image data (the file
// ends early) (stb_image: outofdata)").
bool LoadGrayImage(const std::string& path, const std::string& where, const std::string& what,
                   GrayImage* out, Diagnostics* diag);

// The decoding part of LoadGrayImage, on bytes in memory (the fuzz target); false with the
// reason (the <reason> above) when they are not an image stb_image reads.
bool DecodeGrayImage(const std::string& bytes, GrayImage* out, std::string* reason);

// Writes `image` as an 8-bit RGB PNG atomically (libspng into memory, then WriteFileAtomic).
bool SavePng(const std::string& path, const Image& image, Diagnostics* diag);

// Writes a 16-bit greyscale PNG atomically (the same way).
bool SavePng16(const std::string& path, const Gray16Image& image, Diagnostics* diag);
// Reads a PNG as 16-bit grey levels (libspng; an 8-bit or colour PNG is converted: its
// luminance, 8 bits scaled by 257). Errors as LoadGrayImage's.
bool LoadGray16Png(const std::string& path, const std::string& where, const std::string& what,
                   Gray16Image* out, Diagnostics* diag);
// The decoding part of LoadGray16Png on bytes in memory.
bool DecodeGray16Png(const std::string& bytes, Gray16Image* out, std::string* reason);

}  // namespace mimetic
