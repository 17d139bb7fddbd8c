// wrinkles/offline/wrinkle_builder.cpp: see wrinkle_builder.h.
#include "wrinkles/offline/wrinkle_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "wrinkles/offline/bezier.h"
#include "wrinkles/runtime/profiles.h"

namespace mimetic {
namespace {

double Dot3(float3 a, float3 b) {
  return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z;
}
double Len3(float3 a) { return std::sqrt(Dot3(a, a)); }
double Cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

double TriangleArea3(float3 a, float3 b, float3 c) { return 0.5 * Len3(Cross(b - a, c - a)); }
double TriangleArea2(float2 a, float2 b, float2 c) {
  return 0.5 * std::fabs(Cross2(double(b.x) - a.x, double(b.y) - a.y, double(c.x) - a.x,
                                double(c.y) - a.y));
}

}  // namespace

std::vector<float> ComputeTriangleAreas(span<const float3> points, span<const uint32_t> triangles) {
  const size_t tri_count = triangles.size() / 3;
  std::vector<float> areas(tri_count, 0.f);
  for (size_t t = 0; t < tri_count; ++t) {
    const uint32_t a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
    if (a >= points.size() || b >= points.size() || c >= points.size()) continue;
    // The run-time expression (TriangleAreaRatioJob), so that the rest pose gives r = 1
    // exactly and an unposed face comes back bit for bit.
    areas[t] = 0.5f * Length(Cross(points[b] - points[a], points[c] - points[a]));
  }
  return areas;
}

void ComputeCompressionWeights(span<const float3> rest_points, span<const uint32_t> row_points,
                               span<const float3> row_directions, span<const uint32_t> offsets,
                               span<const uint32_t> neighbors, std::vector<float>* rest_lengths,
                               std::vector<float>* weights) {
  rest_lengths->assign(neighbors.size(), 0.f);
  weights->assign(neighbors.size(), 0.f);
  const size_t rows = std::min({row_points.size(), row_directions.size(),
                                offsets.empty() ? size_t(0) : offsets.size() - 1});
  for (size_t i = 0; i < rows; ++i) {
    if (row_points[i] >= rest_points.size()) continue;
    const float3 xi = rest_points[row_points[i]];
    for (uint32_t k = offsets[i]; k < offsets[i + 1] && k < neighbors.size(); ++k) {
      if (neighbors[k] >= rest_points.size()) continue;
      const float3 e = rest_points[neighbors[k]] - xi;
      const double len = Len3(e);
      // The run-time expression (EdgeCompressionJob), so that eps = 0 exactly at rest.
      (*rest_lengths)[k] = Length(xi - rest_points[neighbors[k]]);
      if (len > 0.0) {
        (*weights)[k] = static_cast<float>(std::fabs(Dot3(e, row_directions[i]) / len));
      }
    }
  }
}

// ----------------------------------------------------------------------------------------------
MuscleWrinkleSample SampleMuscleWrinkleRegion(const MuscleWrinkleSpec& spec,
                                              const WrinkleMuscleGeometry& muscle, float3 x) {
  MuscleWrinkleSample out;
  const bool linear = muscle.kind == WrinkleMuscleKind::kLinear;
  const double R = linear ? muscle.radius : muscle.length;  // 001: R -> Ls for sheets
  const double lambda_w = spec.lambda_w;
  const double u = (1.0 - lambda_w) * R / (2.0 * spec.count);  // 001 eq. 6
  out.half_cycle = static_cast<float>(u);
  const float3 origin = linear ? muscle.attachment
                               : (muscle.attachment_line[0] + muscle.attachment_line[1]) * 0.5f;
  const float3 tip = linear ? muscle.insertion
                            : (muscle.insertion_line[0] + muscle.insertion_line[1]) * 0.5f;
  const float3 axis = NormalizeOr(tip - origin, {1.f, 0.f, 0.f});
  const float3 v = x - origin;
  const double l = Dot3(v, axis);  // linear: |x - mA| cos(phi_i) (eq. 1); sheet: along fiber
  const double lambda = l / R;
  if (!(lambda >= lambda_w && lambda <= 1.0)) {  // outside S_w along the axis (eq. 3): the
    // rest is not needed (the rig builder's refinement field asks this of every sample)
    out.direction = linear ? NormalizeOr(origin - x, axis * -1.f) : axis;
    return out;
  }
  double gamma, q;
  if (linear) {
    const double dist = Len3(v);
    const double c = dist > 0.0 ? std::clamp(l / dist, -1.0, 1.0) : 1.0;
    const double phi_i = std::acos(c);
    gamma = phi_i / muscle.zone_angle;                                    // eq. 2
    q = (phi_i - spec.phi_c) / (double(muscle.zone_angle) - spec.phi_c);  // eq. 12
    out.direction = NormalizeOr(origin - x, axis * -1.f);                 // x_i -> mA
  } else {
    const float3 across = v - axis * static_cast<float>(l);
    const double h = Len3(across);                          // distance to the fiber
    gamma = 2.0 * h / muscle.width;                         // eq. 13
    q = (h - spec.h_c) / (0.5 * muscle.width - spec.h_c);  // eq. 15
    out.direction = axis;
  }
  out.inside = gamma >= 0.0 && gamma <= 1.0;  // eq. 3 (lambda checked above)
  if (!out.inside) return out;
  double w = std::fmod(l - lambda_w * R, 2.0 * u);  // eq. 7
  if (w < 0.0) w = 0.0;
  out.phase = static_cast<float>(w);
  out.attenuation = static_cast<float>(Attenuation(q));
  return out;
}

bool BuildMuscleWrinkleTable(const MuscleWrinkleSpec& spec, const WrinkleMuscleGeometry& muscle,
                             span<const float3> rest_points, const CsrTable& neighbors,
                             const std::string& where, MuscleWrinkleTable* out, Diagnostics* diag) {
  *out = MuscleWrinkleTable{};
  if (!ValidateMuscleWrinkleSpec(spec, muscle, where, diag)) return false;
  if (neighbors.offsets.size() != rest_points.size() + 1 ||
      neighbors.offsets.back() > neighbors.items.size()) {
    diag->Error(where, "point adjacency has " + std::to_string(neighbors.offsets.size()) +
                           " offsets, expected #points + 1 = " +
                           std::to_string(rest_points.size() + 1));
    return false;
  }
  out->furrow_depth = spec.depth;
  out->shape = spec.shape;
  out->half_cycle = SampleMuscleWrinkleRegion(spec, muscle, {}).half_cycle;
  for (size_t p = 0; p < rest_points.size(); ++p) {
    const MuscleWrinkleSample sample = SampleMuscleWrinkleRegion(spec, muscle, rest_points[p]);
    if (!sample.inside) continue;
    out->points.push_back(static_cast<uint32_t>(p));
    out->phase.push_back(sample.phase);
    out->attenuation.push_back(sample.attenuation);
    out->directions.push_back(sample.direction);
  }
  if (out->points.empty()) {
    diag->Warning(where, "no mesh point lies in the wrinkling region (lambda_w = " +
                             std::to_string(spec.lambda_w) +
                             "); expected some points between lambda_w R and R from the "
                             "attachment, inside the zone");
  }
  // Neighbour entries of each region point (the compression of eq. 9-10).
  out->edge_offsets.push_back(0);
  for (uint32_t p : out->points) {
    for (uint32_t k = neighbors.offsets[p]; k < neighbors.offsets[p + 1]; ++k) {
      out->edge_neighbors.push_back(neighbors.items[k]);
    }
    out->edge_offsets.push_back(static_cast<uint32_t>(out->edge_neighbors.size()));
  }
  ComputeCompressionWeights(rest_points, out->points, out->directions, out->edge_offsets,
                            out->edge_neighbors, &out->edge_rest_lengths, &out->edge_weights);
  return true;
}

// ----------------------------------------------------------------------------------------------
ShrinkageProbe BuildShrinkageProbe(uint32_t point, float2 dp, span<const float3> rest_points,
                                   span<const uint32_t> triangles, span<const float2> corner_uvs,
                                   const CsrTable& point_triangles) {
  ShrinkageProbe probe;
  probe.point = point;
  if (point + 1 >= point_triangles.offsets.size() || point >= rest_points.size()) return probe;
  for (int sign = 1; sign >= -1; sign -= 2) {
    const double dx = sign * double(dp.x), dy = sign * double(dp.y);
    for (uint32_t k = point_triangles.offsets[point]; k < point_triangles.offsets[point + 1];
         ++k) {
      const uint32_t t = point_triangles.items[k];
      if (3 * size_t(t) + 2 >= triangles.size() || 3 * size_t(t) + 2 >= corner_uvs.size()) continue;
      int c1 = -1;
      for (int c = 0; c < 3; ++c) {
        if (triangles[3 * t + c] == point) c1 = c;
      }
      if (c1 < 0) continue;
      const int c2 = (c1 + 1) % 3, c3 = (c1 + 2) % 3;
      const uint32_t v2 = triangles[3 * t + c2], v3 = triangles[3 * t + c3];
      if (v2 >= rest_points.size() || v3 >= rest_points.size()) continue;
      const float2 u1 = corner_uvs[3 * t + c1], u2 = corner_uvs[3 * t + c2],
                   u3 = corner_uvs[3 * t + c3];
      const double e2x = double(u2.x) - u1.x, e2y = double(u2.y) - u1.y;
      const double e3x = double(u3.x) - u1.x, e3y = double(u3.y) - u1.y;
      const double det = Cross2(e2x, e2y, e3x, e3y);
      const double scale = (std::fabs(e2x) + std::fabs(e2y)) * (std::fabs(e3x) + std::fabs(e3y));
      if (!(std::fabs(det) > 1e-12 * scale) || !(scale > 0.0)) continue;
      // dp = alpha e2 + beta' e3 (texture space); the ray hits v2v3 when both are >= 0.
      const double alpha = Cross2(dx, dy, e3x, e3y) / det;
      const double betap = Cross2(e2x, e2y, dx, dy) / det;
      const double tol = 1e-9 * (std::fabs(alpha) + std::fabs(betap));
      if (alpha < -tol || betap < -tol || !(alpha + betap > 0.0)) continue;
      ShrinkageSide side;
      side.v2 = v2;
      side.v3 = v3;
      side.beta = static_cast<float>(std::clamp(betap / (alpha + betap), 0.0, 1.0));
      side.rest_length2 = Length(rest_points[v2] - rest_points[point]);  // as at run time
      side.rest_length3 = Length(rest_points[v3] - rest_points[point]);
      if (!(side.rest_length2 > 0.f) || !(side.rest_length3 > 0.f)) continue;
      probe.sides[probe.side_count++] = side;
      break;
    }
  }
  return probe;
}

float CurveWrinkleSupport(const CurveWrinkleSpec& spec) {
  switch (spec.profile) {
    case CurveWrinkleProfile::kBando:
      // **choice**: 8 w. Beyond it |S| < 7 e^-8 d = 0.0023 d and the tail holds 8 e^-8 d w,
      // 0.73% of the volume d w / e on that side (docs/model.md §7); 12 w (1e-4) cost 50% more
      // points per frame.
      return 8.f * spec.width;
    case CurveWrinkleProfile::kYangZhang:
      return static_cast<float>(YangZhangWidth(std::hypot(double(spec.width), double(spec.depth))));
    case CurveWrinkleProfile::kYangZhangExact:
      // h = 0 once a = S a0 reaches the flank length C, so A <= 20/3 C.
      return static_cast<float>(YangZhangWidth(
          YangZhangSpanLength(spec.width, spec.depth, YangZhangSpan::kFlank)));
  }
  return 0.f;
}

bool BuildCurveWrinkleTable(span<const CurveWrinkleSpec> specs, span<const float3> rest_points,
                            span<const uint32_t> triangles, span<const float2> corner_uvs,
                            const std::string& where, CurveWrinkleTable* out, Diagnostics* diag) {
  *out = CurveWrinkleTable{};
  const size_t before = diag->ErrorCount();
  for (size_t w = 0; w < specs.size(); ++w) {
    ValidateCurveWrinkleSpec(specs[w], where + "[" + std::to_string(w) + "]", diag);
  }
  if (triangles.size() % 3 != 0 || corner_uvs.size() != triangles.size()) {
    diag->Error(where, "expected 3 texture coordinates per triangle corner (" +
                           std::to_string(triangles.size()) + "), got " +
                           std::to_string(corner_uvs.size()));
  }
  if (diag->ErrorCount() != before) return false;
  const size_t n = rest_points.size();
  const CsrTable point_tris = BuildPointTriangles(triangles, n);

  for (const CurveWrinkleSpec& s : specs) {
    CurveWrinkleParams p;
    p.profile = s.profile;
    p.modulation = s.modulation;
    p.depth = s.depth;
    p.width = s.width;
    p.rest_amplitude = s.rest_amplitude;
    p.rest_length = static_cast<float>(YangZhangSpanLength(s.width, s.depth, YangZhangSpan::kFlank));
    out->wrinkles.push_back(p);
  }
  // Per-wrinkle texture-space bounding box of the control polygon (contains the curve).
  struct Box {
    double x0, y0, x1, y1, support;
  };
  std::vector<Box> boxes;
  for (const CurveWrinkleSpec& s : specs) {
    Box b{s.control[0].x, s.control[0].y, s.control[0].x, s.control[0].y, CurveWrinkleSupport(s)};
    for (int k = 1; k < 4; ++k) {
      b.x0 = std::min(b.x0, double(s.control[k].x));
      b.y0 = std::min(b.y0, double(s.control[k].y));
      b.x1 = std::max(b.x1, double(s.control[k].x));
      b.y1 = std::max(b.y1, double(s.control[k].y));
    }
    boxes.push_back(b);
  }

  out->offsets.push_back(0);
  size_t unscaled = 0;
  for (size_t p = 0; p < n; ++p) {
    const uint32_t first = point_tris.offsets[p], last = point_tris.offsets[p + 1];
    if (first == last) continue;
    double area3 = 0.0, area2 = 0.0;
    for (uint32_t k = first; k < last; ++k) {
      const uint32_t t = point_tris.items[k];
      const uint32_t a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
      if (a >= n || b >= n || c >= n) continue;
      area3 += TriangleArea3(rest_points[a], rest_points[b], rest_points[c]);
      area2 += TriangleArea2(corner_uvs[3 * t], corner_uvs[3 * t + 1], corner_uvs[3 * t + 2]);
    }
    if (!(area2 > 0.0) || !(area3 > 0.0)) {
      ++unscaled;
      continue;
    }
    const double scale = std::sqrt(area3 / area2);  // mesh units per texture unit
    bool any = false;
    for (size_t w = 0; w < specs.size(); ++w) {
      const Box& box = boxes[w];
      const double reach = box.support / scale;  // texture units
      double best = std::numeric_limits<double>::infinity();
      float2 tangent{1.f, 0.f};
      float2 seen[8];  // a point's corners share one uv except at seams: query each once
      int seen_count = 0;
      for (uint32_t k = first; k < last; ++k) {
        const uint32_t t = point_tris.items[k];
        for (int c = 0; c < 3; ++c) {
          if (triangles[3 * t + c] != p) continue;
          const float2 uv = corner_uvs[3 * t + c];
          bool repeat = false;
          for (int i = 0; i < seen_count; ++i) repeat |= seen[i].x == uv.x && seen[i].y == uv.y;
          if (repeat) continue;
          if (seen_count < 8) seen[seen_count++] = uv;
          if (uv.x < box.x0 - reach || uv.x > box.x1 + reach || uv.y < box.y0 - reach ||
              uv.y > box.y1 + reach) {
            continue;
          }
          // Beyond the reach it cannot give an entry, nor beat a corner within it.
          if (ClassifyBezierReach(specs[w].control, uv, reach) == BezierReach::kBeyond) continue;
          const BezierClosest hit = ClosestPointOnBezier(specs[w].control, uv);
          if (hit.distance < best) {
            best = hit.distance;
            tangent = hit.tangent;
          }
        }
      }
      const double l = best * scale;
      if (!(l <= box.support)) continue;
      CurveWrinkleEntry entry{static_cast<uint32_t>(w), static_cast<float>(l)};
      if (specs[w].profile == CurveWrinkleProfile::kBando) {
        entry.profile = CurveProfile(entry.distance, specs[w].depth, specs[w].width);
        entry.has_profile = 1;
      }
      out->entries.push_back(entry);
      // Shrinkage is measured across the furrow: dp is perpendicular to its tangent (000 §7).
      const float2 dp{-tangent.y, tangent.x};
      out->probes.push_back(BuildShrinkageProbe(static_cast<uint32_t>(p), dp, rest_points,
                                                triangles, corner_uvs, point_tris));
      any = true;
    }
    if (any) {
      out->points.push_back(static_cast<uint32_t>(p));
      out->offsets.push_back(static_cast<uint32_t>(out->entries.size()));
    }
  }
  if (unscaled > 0 && !specs.empty()) {
    diag->Warning(where, std::to_string(unscaled) +
                             " points have zero texture or rest area around them and get no "
                             "curve wrinkle; expected a non-degenerate texture mapping");
  }
  return true;
}

// ----------------------------------------------------------------------------------------------
bool SampleThicknessMap(span<const uint8_t> gray, int width, int height, float max_thickness,
                        span<const float2> point_uvs, const std::string& where,
                        std::vector<float>* out, Diagnostics* diag) {
  out->clear();
  bool ok = true;
  if (width <= 0 || height <= 0 || gray.size() < size_t(width) * size_t(height)) {
    diag->Error(where, "thickness map of " + std::to_string(width) + " x " +
                           std::to_string(height) + " with " + std::to_string(gray.size()) +
                           " bytes: expected a non-empty 8-bit grayscale image (width * height "
                           "bytes)");
    ok = false;
  }
  if (!(max_thickness >= 0.f) || !std::isfinite(max_thickness)) {
    diag->Error(where, "maximum thickness " + std::to_string(max_thickness) +
                           ": expected a finite number >= 0 (mesh units)");
    ok = false;
  }
  if (!ok) return false;
  out->resize(point_uvs.size(), 0.f);
  for (size_t p = 0; p < point_uvs.size(); ++p) {
    double x = double(point_uvs[p].x) * width - 0.5, y = double(point_uvs[p].y) * height - 0.5;
    if (!std::isfinite(x)) x = 0.0;
    if (!std::isfinite(y)) y = 0.0;
    x = std::clamp(x, 0.0, double(width - 1));
    y = std::clamp(y, 0.0, double(height - 1));
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int xi, int yi) { return gray[size_t(yi) * width + xi] / 255.0; };
    const double v = (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) +
                     (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
    (*out)[p] = static_cast<float>(v * max_thickness);
  }
  return true;
}

}  // namespace mimetic
