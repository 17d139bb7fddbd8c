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
// Cells per radius: the sources are cells of side r / 8 (about 200 of them in a ball on a
// surface), so the cost per point does not grow with the mesh's density.
constexpr int64_t kCellsPerRadius = 8;
// floor(v / kCellsPerRadius) for negative v too.
int64_t BlockOf(int64_t v) {
  return v >= 0 ? v / kCellsPerRadius : -((-v + kCellsPerRadius - 1) / kCellsPerRadius);
}
}  // namespace

const std::vector<float3>& NormalField::At(float radius) {
  Prepare();
  if (!(radius > 0.f) || !std::isfinite(radius)) return own_;
  if (auto it = smoothed_.find(radius); it != smoothed_.end()) return it->second;

  // The sources: one per non-empty cell of side h = r / kCellsPerRadius (cells anchored at the
  // origin), with the summed area A_c, the summed area-weighted normal N_c and the area-weighted
  // centroid x_c of the points in it, accumulated in point order.
  const double r = radius, h = r / kCellsPerRadius, inv_h = 1.0 / h, inv_r = 1.0 / r;
  auto cell = [&](double v) { return int64_t(std::floor(v * inv_h)); };
  auto key = [](int64_t x, int64_t y, int64_t z) {
    return (uint64_t(x) & 0x1fffff) | ((uint64_t(y) & 0x1fffff) << 21) | ((uint64_t(z) & 0x1fffff) << 42);
  };
  struct Source {
    int64_t c[3];
    double area = 0, n[3] = {0, 0, 0}, x[3] = {0, 0, 0};
  };
  std::vector<Source> sources;
  std::unordered_map<uint64_t, uint32_t> index;
  const size_t np = points_.size();
  for (uint32_t p = 0; p < np; ++p) {
    const float3 q = points_[p];
    if (!IsFinite(q) || !(area_[p] > 0)) continue;
    const int64_t c[3] = {cell(q.x), cell(q.y), cell(q.z)};
    const auto [it, fresh] = index.emplace(key(c[0], c[1], c[2]), uint32_t(sources.size()));
    if (fresh) sources.push_back({{c[0], c[1], c[2]}});
    Source& s = sources[it->second];
    const double a = area_[p];
    const float3 m = own_[p];
    s.area += a;
    s.n[0] += a * m.x, s.n[1] += a * m.y, s.n[2] += a * m.z;
    s.x[0] += a * q.x, s.x[1] += a * q.y, s.x[2] += a * q.z;
  }
  for (Source& s : sources)
    for (double& v : s.x) v /= s.area;

  // The sources by block of kCellsPerRadius^3 cells (side r): a ball of radius r about a point
  // reaches its own block and the 26 around it.
  std::unordered_map<uint64_t, std::vector<uint32_t>> blocks;
  for (uint32_t k = 0; k < sources.size(); ++k) {
    const int64_t* c = sources[k].c;
    blocks[key(BlockOf(c[0]), BlockOf(c[1]), BlockOf(c[2]))].push_back(k);
  }

  // The points by cell: the sources a cell's points can reach (centroid within r of some point
  // of the cell) are gathered once per cell, then each point sums those within r of itself.
  std::unordered_map<uint64_t, std::vector<uint32_t>> cell_points;
  std::vector<uint64_t> cell_order;
  for (uint32_t p = 0; p < np; ++p) {
    const float3 q = points_[p];
    if (!IsFinite(q)) continue;
    const uint64_t k = key(cell(q.x), cell(q.y), cell(q.z));
    auto [it, fresh] = cell_points.try_emplace(k);
    if (fresh) cell_order.push_back(k);
    it->second.push_back(p);
  }
  std::vector<float3> out(own_);
  std::vector<uint32_t> near;
  const double reach = r + h * std::sqrt(3.0) * 0.5;
  for (uint64_t k : cell_order) {
    const std::vector<uint32_t>& members = cell_points[k];
    const float3 first = points_[members[0]];
    const int64_t c[3] = {cell(first.x), cell(first.y), cell(first.z)};
    const double centre[3] = {(double(c[0]) + 0.5) * h, (double(c[1]) + 0.5) * h, (double(c[2]) + 0.5) * h};
    near.clear();
    const int64_t bx = BlockOf(c[0]), by = BlockOf(c[1]), bz = BlockOf(c[2]);
    for (int64_t dz = -1; dz <= 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const auto it = blocks.find(key(bx + dx, by + dy, bz + dz));
          if (it == blocks.end()) continue;
          for (uint32_t src : it->second) {
            const Source& s = sources[src];
            const double ex = s.x[0] - centre[0], ey = s.x[1] - centre[1], ez = s.x[2] - centre[2];
            if (ex * ex + ey * ey + ez * ez < reach * reach) near.push_back(src);
          }
        }
    for (uint32_t p : members) {
      const float3 q = points_[p];
      double sum[3] = {0, 0, 0}, weight = 0;
      for (uint32_t src : near) {
        const Source& s = sources[src];
        const double ex = s.x[0] - q.x, ey = s.x[1] - q.y, ez = s.x[2] - q.z;
        const double t2 = (ex * ex + ey * ey + ez * ez) * inv_r * inv_r;
        if (!(t2 < 1.0)) continue;
        const double w = (1.0 - t2) * (1.0 - t2);
        sum[0] += w * s.n[0], sum[1] += w * s.n[1], sum[2] += w * s.n[2];
        weight += w * s.area;
      }
      const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
      if (len > kMinMean * weight && std::isfinite(len))
        out[p] = {float(sum[0] / len), float(sum[1] / len), float(sum[2] / len)};
    }
  }
  return smoothed_.emplace(radius, std::move(out)).first->second;
}

}  // namespace mimetic
