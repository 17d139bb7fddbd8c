// geometry/normal_field.cpp: see normal_field.h.
#include "geometry/normal_field.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "geometry/normals.h"

namespace mimetic {

NormalField::NormalField(span<const float3> points, span<const uint32_t> triangles)
    : points_(points.begin(), points.end()), triangles_(triangles.begin(), triangles.end()) {}

const std::vector<double>& NormalField::Areas() {
  Prepare();
  return area_;
}

void NormalField::Prepare() {
  if (prepared_) return;
  prepared_ = true;
  own_ = ComputeVertexNormals(span<const float3>(points_), span<const uint32_t>(triangles_),
                              VertexNormalOptions{.share_by_position = true});
  area_.assign(points_.size(), 0.0);
  const size_t np = points_.size();
  const std::vector<uint32_t>& triangles = triangles_;
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const uint32_t v[3] = {triangles[t], triangles[t + 1], triangles[t + 2]};
    if (v[0] >= np || v[1] >= np || v[2] >= np) continue;
    const double a = TriangleArea(points_[v[0]], points_[v[1]], points_[v[2]]);
    if (!std::isfinite(a)) continue;
    for (uint32_t k : v) area_[k] += a / 3.0;
  }
}

namespace {
// Where the weighted mean of the unit normals is shorter than this (both sides of a thin sheet
// inside the ball, cancelling), the point keeps its own normal.
constexpr double kMinMean = 0.05;
}  // namespace

const std::vector<float3>& NormalField::At(float radius) {
  Prepare();
  if (!(radius > 0.f) || !std::isfinite(radius)) return own_;
  if (auto it = smoothed_.find(radius); it != smoothed_.end()) return it->second;

  // Bucket the finite points in cells of side r: a ball of radius r about a point lies in the
  // 27 cells around the point's own.
  const double r = radius, inv = 1.0 / r;
  auto key = [](int64_t x, int64_t y, int64_t z) {
    return (uint64_t(x) & 0x1fffff) | ((uint64_t(y) & 0x1fffff) << 21) | ((uint64_t(z) & 0x1fffff) << 42);
  };
  auto cell = [&](double v) { return int64_t(std::floor(v * inv)); };
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  const size_t np = points_.size();
  for (uint32_t p = 0; p < np; ++p) {
    const float3 q = points_[p];
    if (!IsFinite(q) || !(area_[p] > 0)) continue;
    grid[key(cell(q.x), cell(q.y), cell(q.z))].push_back(p);
  }

  std::vector<float3> out(own_);
  for (uint32_t p = 0; p < np; ++p) {
    const float3 c = points_[p];
    if (!IsFinite(c)) continue;
    const int64_t cx = cell(c.x), cy = cell(c.y), cz = cell(c.z);
    double sum[3] = {0, 0, 0}, weight = 0;
    for (int64_t dz = -1; dz <= 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
          if (it == grid.end()) continue;
          for (uint32_t q : it->second) {
            const float3 m = own_[q];
            const double ex = double(points_[q].x) - c.x, ey = double(points_[q].y) - c.y,
                         ez = double(points_[q].z) - c.z;
            const double t2 = (ex * ex + ey * ey + ez * ez) * inv * inv;
            if (!(t2 < 1.0)) continue;
            const double w = (1.0 - t2) * (1.0 - t2) * area_[q];
            sum[0] += w * m.x, sum[1] += w * m.y, sum[2] += w * m.z;
            weight += w;
          }
        }
    const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (len > kMinMean * weight && std::isfinite(len))
      out[p] = {float(sum[0] / len), float(sum[1] / len), float(sum[2] / len)};
  }
  return smoothed_.emplace(radius, std::move(out)).first->second;
}

}  // namespace mimetic
