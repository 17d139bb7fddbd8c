// tools/render/heat_map.h: colour scale for per-vertex values (`mimetic compare --heatmap`).
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/math.h"

namespace mimetic {

// The colour of t in [0, 1] (clamped; NaN as 0) on a five-stop scale: blue (0), cyan (0.25),
// green (0.5), yellow (0.75), red (1), linear between the stops.
float3 HeatColor(float t);

// Per-vertex colours of `values` scaled by 1 / `max_value` (max_value <= 0: all blue). With
// `measured` (one flag per value), unmeasured vertices are neutral grey (0.72).
std::vector<float3> HeatColors(const std::vector<float>& values, float max_value,
                               const std::vector<uint8_t>* measured = nullptr);

// Draws the colour scale along the bottom `height` rows of `image` (left = 0, right = max),
// inset by `margin` pixels, with a dark border.
void DrawHeatLegend(Image* image, int height, int margin);

}  // namespace mimetic
