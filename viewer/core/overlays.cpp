// viewer/core/overlays.cpp: see overlays.h.
#include "viewer/core/overlays.h"

#include <algorithm>
#include <cmath>

namespace mimetic::viewer {
namespace {

struct OverlayRow {
  Overlay overlay;
  const char* name;
  const char* label;
};
constexpr OverlayRow kRows[kOverlayCount] = {
    {Overlay::kNone, "none", "none (skin shading)"},
    {Overlay::kAreaRatio, "area-ratio", "area ratio r"},
    {Overlay::kShrinkage, "shrinkage", "shrinkage s"},
    {Overlay::kCompression, "compression", "compression eps"},
    {Overlay::kWrinkle, "wrinkle", "wrinkle displacement (mesh units)"},
    {Overlay::kThickness, "thickness", "skin thickness h (mesh units)"},
    {Overlay::kDisplacement, "displacement", "displacement |x - X| (mesh units)"},
};

bool Signed(Overlay o) {
  return o == Overlay::kAreaRatio || o == Overlay::kShrinkage || o == Overlay::kCompression ||
         o == Overlay::kWrinkle;
}

template <size_t N>
float3 Ramp(const float3 (&stops)[N], float t) {
  const float x = t * float(N - 1);
  const size_t i = std::min(size_t(x), N - 2);
  const float f = x - float(i);
  return stops[i] * (1.f - f) + stops[i + 1] * f;
}

}  // namespace

const char* OverlayName(Overlay overlay) { return kRows[int(overlay)].name; }
const char* OverlayLabel(Overlay overlay) { return kRows[int(overlay)].label; }

bool ParseOverlay(const std::string& text, Overlay* out) {
  for (const OverlayRow& row : kRows) {
    if (text == row.name) {
      *out = row.overlay;
      return true;
    }
  }
  return false;
}

std::string OverlayNames() {
  std::string s;
  for (const OverlayRow& row : kRows) s += (s.empty() ? "" : ", ") + std::string(row.name);
  return s;
}

float3 MapColor(ColorMap map, float t) {
  t = std::isfinite(t) ? std::clamp(t, 0.f, 1.f) : 0.f;
  return map == ColorMap::kDiverging ? Ramp(kDivergingStops, t) : Ramp(kSequentialStops, t);
}

float OverlayNeutral(Overlay overlay) { return overlay == Overlay::kAreaRatio ? 1.f : 0.f; }

void FitOverlayRange(OverlayField* field) {
  float lo = INFINITY, hi = -INFINITY;
  for (float v : field->values) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  const float n = OverlayNeutral(field->overlay);
  if (!(lo <= hi)) lo = hi = n;  // no finite value
  field->min_value = lo;
  field->max_value = hi;
  if (Signed(field->overlay)) {
    const float a = std::max({std::fabs(lo - n), std::fabs(hi - n), kMinHalfRange});
    field->lo = n - a;
    field->hi = n + a;
    field->map = ColorMap::kDiverging;
  } else {
    field->lo = 0.f;
    field->hi = std::max(hi, kMinHalfRange);
    field->map = ColorMap::kSequential;
  }
}

float OverlayT(const OverlayField& field, float v) {
  const float span = field.hi - field.lo;
  if (!(span > 0.f) || !std::isfinite(v)) return 0.f;
  return std::clamp((v - field.lo) / span, 0.f, 1.f);
}

void OverlayColors(const OverlayField& field, std::vector<float3>* out) {
  out->resize(field.values.size());
  for (size_t i = 0; i < field.values.size(); ++i)
    (*out)[i] = MapColor(field.map, OverlayT(field, field.values[i]));
}

std::vector<LegendEntry> OverlayLegend(const OverlayField& field, int count) {
  count = std::max(count, 2);
  std::vector<LegendEntry> legend(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const float f = float(i) / float(count - 1);
    legend[size_t(i)].value = field.lo + f * (field.hi - field.lo);
    legend[size_t(i)].color = MapColor(field.map, f);
  }
  return legend;
}

bool ComputeOverlayValues(Overlay overlay, const OverlayInputs& in, OverlayField* field) {
  const size_t nv = in.vertex_points.size();
  auto point_ok = [&](span<const float> per_point) {
    for (uint32_t p : in.vertex_points)
      if (p >= per_point.size()) return false;
    return true;
  };
  switch (overlay) {
    case Overlay::kNone: break;
    case Overlay::kAreaRatio:
    case Overlay::kCompression:
      if (in.tension.size() < 2 * nv) return false;
      break;
    case Overlay::kShrinkage:
      if (!point_ok(in.point_shrinkage)) return false;
      break;
    case Overlay::kThickness:
      if (!point_ok(in.point_thickness)) return false;
      break;
    case Overlay::kWrinkle:
      if (in.positions.size() < nv || in.normals.size() < nv || in.unwrinkled.size() < nv)
        return false;
      break;
    case Overlay::kDisplacement:
      if (in.positions.size() < nv || in.rest_positions.size() < nv) return false;
      break;
  }
  field->overlay = overlay;
  field->values.assign(nv, 0.f);
  for (size_t v = 0; v < nv; ++v) {
    float& out = field->values[v];
    switch (overlay) {
      case Overlay::kNone: break;
      case Overlay::kAreaRatio: out = in.tension[2 * v]; break;
      case Overlay::kCompression: out = in.tension[2 * v + 1]; break;
      case Overlay::kShrinkage: out = in.point_shrinkage[in.vertex_points[v]]; break;
      case Overlay::kThickness: out = in.point_thickness[in.vertex_points[v]]; break;
      case Overlay::kWrinkle: out = Dot(in.positions[v] - in.unwrinkled[v], in.normals[v]); break;
      case Overlay::kDisplacement: out = Length(in.positions[v] - in.rest_positions[v]); break;
    }
  }
  FitOverlayRange(field);
  return true;
}

void PointShrinkage(uint32_t point_count, span<const uint32_t> row_points,
                    span<const uint32_t> row_offsets, span<const float> entry_shrinkage,
                    std::vector<float>* out) {
  out->assign(point_count, 0.f);
  std::vector<uint32_t> counts(point_count, 0);
  for (size_t r = 0; r < row_points.size() && r + 1 < row_offsets.size(); ++r) {
    const uint32_t p = row_points[r];
    if (p >= point_count) continue;
    for (uint32_t e = row_offsets[r]; e < row_offsets[r + 1] && e < entry_shrinkage.size(); ++e) {
      (*out)[p] += entry_shrinkage[e];
      ++counts[p];
    }
  }
  for (uint32_t p = 0; p < point_count; ++p)
    if (counts[p]) (*out)[p] /= float(counts[p]);
}

float InterpolateValue(const OverlayField& field, uint32_t a, uint32_t b, uint32_t c, float u,
                       float w) {
  const size_t n = field.values.size();
  if (a >= n || b >= n || c >= n) return 0.f;
  return (1.f - u - w) * field.values[a] + u * field.values[b] + w * field.values[c];
}

}  // namespace mimetic::viewer
