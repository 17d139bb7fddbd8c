// viewer/core/overlays.h: the overlay colour maps (per-vertex scalar fields of one frame), their
// legends and the value under the cursor.
//
// Fields (docs/viewer.md "Overlays"), per output vertex, from one EvaluateJob frame:
//   area-ratio     r of its point (docs/model.md §4): < 1 compressed, > 1 stretched; neutral 1
//   shrinkage      s of its point's directional curve-wrinkle entries (docs/model.md §5, the mean
//                  of its entries' probes measured on X1, the pose before the skin layers);
//                  0 for a point without any; neutral 0
//   compression    eps (docs/model.md §5): the largest of its point's wrinkled-muscle rows; 0
//                  without rows; neutral 0
//   wrinkle        the wrinkle layers' displacement along the output normal, mesh units: the
//                  frame with every layer minus the frame without the two wrinkle layers
//   thickness      the skin thickness h of its point (docs/model.md §4), mesh units
//   displacement   |posed - rest|, mesh units
// Signed fields (r, s, eps, wrinkle) use the diverging map around their neutral value over a
// range symmetric about it; thickness and displacement the sequential map over [0, max].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/span.h"

namespace mimetic::viewer {

enum class Overlay : uint8_t {
  kNone = 0,
  kAreaRatio,
  kShrinkage,
  kCompression,
  kWrinkle,
  kThickness,
  kDisplacement,
};
inline constexpr int kOverlayCount = 7;

// The command-line names ("none", "area-ratio", "shrinkage", "compression", "wrinkle",
// "thickness", "displacement") and the labels the legend shows.
const char* OverlayName(Overlay overlay);
const char* OverlayLabel(Overlay overlay);
bool ParseOverlay(const std::string& text, Overlay* out);
// "none, area-ratio, ..." for messages.
std::string OverlayNames();

enum class ColorMap : uint8_t {
  kSequential,  // dark blue (0) -> teal -> yellow (1), monotonic in lightness
  kDiverging,   // blue (0) -> white (0.5) -> red (1)
};

// The map's colour at t (clamped to [0, 1]; NaN -> 0), each channel in [0, 1]. Piecewise
// linear through the control points kSequentialStops / kDivergingStops at t = i / (n - 1).
float3 MapColor(ColorMap map, float t);
inline constexpr float3 kSequentialStops[5] = {
    {0.05f, 0.03f, 0.35f}, {0.15f, 0.30f, 0.60f}, {0.10f, 0.60f, 0.55f},
    {0.55f, 0.80f, 0.30f}, {0.99f, 0.91f, 0.15f}};
inline constexpr float3 kDivergingStops[3] = {
    {0.13f, 0.30f, 0.85f}, {0.97f, 0.97f, 0.97f}, {0.85f, 0.15f, 0.12f}};

// One frame's field with the range its colours span.
struct OverlayField {
  Overlay overlay = Overlay::kNone;
  std::vector<float> values;  // per output vertex
  float lo = 0.f, hi = 1.f;   // the colour range: values map to t = (v - lo) / (hi - lo)
  ColorMap map = ColorMap::kSequential;
  // The data's own extremes (the legend prints them).
  float min_value = 0.f, max_value = 0.f;
};

// Fills field->lo/hi/map/min_value/max_value from field->values and field->overlay: signed
// fields [n - a, n + a] with n the neutral value and a = max |v - n| (at least kMinHalfRange);
// the others [0, max(max v, kMinHalfRange)]. Non-finite values are ignored.
void FitOverlayRange(OverlayField* field);
inline constexpr float kMinHalfRange = 1e-4f;
float OverlayNeutral(Overlay overlay);

// t of value v in the field's range, in [0, 1].
float OverlayT(const OverlayField& field, float v);
// Per-vertex colours (3 floats each) of the field into `out` (resized).
void OverlayColors(const OverlayField& field, std::vector<float3>* out);

// The legend: `count` (>= 2) evenly spaced values from lo to hi with their colours.
struct LegendEntry {
  float value = 0.f;
  float3 color{};
};
std::vector<LegendEntry> OverlayLegend(const OverlayField& field, int count);

// Inputs of ComputeOverlayValues, per output vertex unless told (spans may be empty where the
// overlay does not read them).
struct OverlayInputs {
  span<const uint32_t> vertex_points;  // #V: vertex -> point
  span<const float3> rest_positions;   // #V (displacement)
  span<const float3> positions;        // #V, this frame (displacement, wrinkle)
  span<const float3> normals;          // #V, this frame (wrinkle)
  span<const float3> unwrinkled;       // #V, this frame without the wrinkle layers (wrinkle)
  span<const float> tension;           // 2 per vertex: r, eps (area-ratio, compression)
  span<const float> point_thickness;   // #P (thickness)
  span<const float> point_shrinkage;   // #P (shrinkage; PointShrinkage)
};

// The field's values (field->values resized to #V = vertex_points.size()); then FitOverlayRange.
// False (field untouched) when a span the overlay reads is too small.
bool ComputeOverlayValues(Overlay overlay, const OverlayInputs& in, OverlayField* field);

// Per point: the mean shrinkage s of its curve-wrinkle entries (rows `row_points`, entries
// [row_offsets[r], row_offsets[r + 1]) of `entry_shrinkage`), 0 for points without rows.
// out resized to point_count.
void PointShrinkage(uint32_t point_count, span<const uint32_t> row_points,
                    span<const uint32_t> row_offsets, span<const float> entry_shrinkage,
                    std::vector<float>* out);

// The value at a point of triangle (a, b, c) with barycentric weights (1 - u - w, u, w).
float InterpolateValue(const OverlayField& field, uint32_t a, uint32_t b, uint32_t c, float u,
                       float w);

}  // namespace mimetic::viewer
