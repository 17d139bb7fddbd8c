// tools/render/close_up.cpp: close-ups and panels.
#include "tools/render/close_up.h"

#include <algorithm>
#include <cmath>

namespace mimetic {

Image RenderCloseUp(const MeshData& mesh, RenderOptions options, int size, double zoom,
                    double focus_x, double focus_y) {
  const int full = static_cast<int>(std::lround(std::min(8192.0, size * std::max(1.0, zoom))));
  options.width = options.height = full;
  Image image = RenderMesh(mesh, options);
  if (full <= size) return image;
  const int x0 = std::clamp(static_cast<int>(std::lround(focus_x * full)) - size / 2, 0, full - size);
  const int y0 = std::clamp(static_cast<int>(std::lround(focus_y * full)) - size / 2, 0, full - size);
  Image crop;
  crop.width = crop.height = size;
  crop.rgb.resize(static_cast<size_t>(size) * size * 3);
  for (int y = 0; y < size; ++y)
    std::copy_n(&image.rgb[(static_cast<size_t>(y0 + y) * full + x0) * 3],
                static_cast<size_t>(size) * 3, &crop.rgb[static_cast<size_t>(y) * size * 3]);
  return crop;
}

Image SideBySide(const std::vector<Image>& images, int gap, float3 background) {
  Image out;
  if (images.empty()) return out;
  for (const Image& i : images) {
    out.width += i.width;
    out.height = std::max(out.height, i.height);
  }
  out.width += gap * int(images.size() - 1);
  out.rgb.resize(static_cast<size_t>(out.width) * out.height * 3);
  const uint8_t bg[3] = {uint8_t(std::lround(255 * background.x)),
                         uint8_t(std::lround(255 * background.y)),
                         uint8_t(std::lround(255 * background.z))};
  for (size_t p = 0; p < out.rgb.size(); p += 3) std::copy_n(bg, 3, &out.rgb[p]);
  int x = 0;
  for (const Image& i : images) {
    const int y0 = (out.height - i.height) / 2;
    for (int y = 0; y < i.height; ++y)
      std::copy_n(&i.rgb[static_cast<size_t>(y) * i.width * 3], static_cast<size_t>(i.width) * 3,
                  &out.rgb[(static_cast<size_t>(y0 + y) * out.width + x) * 3]);
    x += i.width + gap;
  }
  return out;
}

}  // namespace mimetic
