// tools/render/heat_map.cpp: the heat-map colour scale.
#include "tools/render/heat_map.h"

#include <algorithm>
#include <cmath>

namespace mimetic {

float3 HeatColor(float t) {
  static const float3 kStops[5] = {{0.15f, 0.25f, 0.90f}, {0.15f, 0.80f, 0.90f},
                                   {0.30f, 0.85f, 0.30f}, {0.95f, 0.85f, 0.20f},
                                   {0.90f, 0.15f, 0.10f}};
  if (!(t > 0.f)) t = 0.f;  // NaN too
  if (t > 1.f) t = 1.f;
  const float s = t * 4.f;
  const int i = std::min(3, static_cast<int>(s));
  const float f = s - float(i);
  return kStops[i] * (1.f - f) + kStops[i + 1] * f;
}

std::vector<float3> HeatColors(const std::vector<float>& values, float max_value,
                               const std::vector<uint8_t>* measured) {
  std::vector<float3> colors(values.size());
  for (size_t i = 0; i < values.size(); ++i)
    colors[i] = measured && i < measured->size() && !(*measured)[i]
                    ? float3{0.72f, 0.72f, 0.72f}
                    : HeatColor(max_value > 0.f ? values[i] / max_value : 0.f);
  return colors;
}

void DrawHeatLegend(Image* image, int height, int margin) {
  const int w = image->width, h = image->height;
  const int x0 = margin, x1 = w - margin, y1 = h - margin, y0 = std::max(0, y1 - height);
  if (x1 - x0 < 3 || y1 - y0 < 3) return;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const bool border = y == y0 || y == y1 - 1 || x == x0 || x == x1 - 1;
      const float3 c = border ? float3{0.1f, 0.1f, 0.1f}
                              : HeatColor(float(x - x0 - 1) / float(x1 - x0 - 3));
      uint8_t* p = &image->rgb[(static_cast<size_t>(y) * w + x) * 3];
      p[0] = static_cast<uint8_t>(std::lround(255.f * c.x));
      p[1] = static_cast<uint8_t>(std::lround(255.f * c.y));
      p[2] = static_cast<uint8_t>(std::lround(255.f * c.z));
    }
}

}  // namespace mimetic
