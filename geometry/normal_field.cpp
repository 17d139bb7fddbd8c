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
// A cell's (or a block's) three indices packed into one hash key, 21 bits each.
uint64_t CellKey(int64_t x, int64_t y, int64_t z) {
  return (uint64_t(x) & 0x1fffff) | ((uint64_t(y) & 0x1fffff) << 21) | ((uint64_t(z) & 0x1fffff) << 42);
}
}  // namespace

// The sources: one per non-empty cell of side h = r / kCellsPerRadius (cells anchored at the
// origin), with the summed area A_c, the summed area-weighted normal N_c and the area-weighted
// centroid x_c of the points in it, accumulated in point order. Then the sources by block of
// kCellsPerRadius^3 cells (side r), and the finite points by cell.
NormalField::Smoothed& NormalField::FieldOf(float radius) {
  if (auto it = smoothed_.find(radius); it != smoothed_.end()) return it->second;
  Smoothed& f = smoothed_[radius];
  const double h = double(radius) / kCellsPerRadius, inv_h = 1.0 / h;
  auto cell = [&](double v) { return int64_t(std::floor(v * inv_h)); };
  std::unordered_map<uint64_t, uint32_t> index;
  const size_t np = points_.size();
  for (uint32_t p = 0; p < np; ++p) {
    const float3 q = points_[p];
    if (!IsFinite(q) || !(area_[p] > 0)) continue;
    const int64_t c[3] = {cell(q.x), cell(q.y), cell(q.z)};
    const auto [it, fresh] = index.emplace(CellKey(c[0], c[1], c[2]), uint32_t(f.sources.size()));
    if (fresh) f.sources.push_back({{c[0], c[1], c[2]}});
    Smoothed::Source& s = f.sources[it->second];
    const double a = area_[p];
    const float3 m = own_[p];
    s.area += a;
    s.n[0] += a * m.x, s.n[1] += a * m.y, s.n[2] += a * m.z;
    s.x[0] += a * q.x, s.x[1] += a * q.y, s.x[2] += a * q.z;
  }
  for (Smoothed::Source& s : f.sources)
    for (double& v : s.x) v /= s.area;
  for (uint32_t k = 0; k < f.sources.size(); ++k) {
    const int64_t* c = f.sources[k].c;
    f.blocks[CellKey(BlockOf(c[0]), BlockOf(c[1]), BlockOf(c[2]))].push_back(k);
  }
  // Every finite point's cell (area or not: a point with no area still gets a normal), numbered
  // in the order the points first reach it.
  index.clear();
  f.point_cell.assign(np, UINT32_MAX);
  std::vector<uint32_t> count;
  for (uint32_t p = 0; p < np; ++p) {
    const float3 q = points_[p];
    if (!IsFinite(q)) continue;
    const auto [it, fresh] = index.emplace(CellKey(cell(q.x), cell(q.y), cell(q.z)), uint32_t(count.size()));
    if (fresh) count.push_back(0);
    f.point_cell[p] = it->second;
    ++count[it->second];
  }
  f.cell_start.assign(count.size() + 1, 0u);
  for (size_t c = 0; c < count.size(); ++c) f.cell_start[c + 1] = f.cell_start[c] + count[c];
  f.cell_points.resize(f.cell_start.back());
  std::vector<uint32_t> fill(f.cell_start.begin(), f.cell_start.end() - 1);
  for (uint32_t p = 0; p < np; ++p)
    if (f.point_cell[p] != UINT32_MAX) f.cell_points[fill[f.point_cell[p]]++] = p;
  f.cell_done.assign(count.size(), 0);
  f.cells_left = count.size();
  f.out = own_;
  return f;
}

// One cell's points: the sources they can reach (centroid within r of some point of the cell)
// are gathered once, then each point sums those within r of itself, in the same order whether
// the cell is asked for alone or with every other.
void NormalField::SolveCell(float radius, Smoothed& f, uint32_t c) {
  if (f.cell_done[c]) return;
  f.cell_done[c] = 1;
  --f.cells_left;
  const double r = radius, h = r / kCellsPerRadius, inv_h = 1.0 / h, inv_r = 1.0 / r;
  auto cell = [&](double v) { return int64_t(std::floor(v * inv_h)); };
  const uint32_t* members = f.cell_points.data() + f.cell_start[c];
  const uint32_t count = f.cell_start[c + 1] - f.cell_start[c];
  const float3 first = points_[members[0]];
  const int64_t k[3] = {cell(first.x), cell(first.y), cell(first.z)};
  const double centre[3] = {(double(k[0]) + 0.5) * h, (double(k[1]) + 0.5) * h, (double(k[2]) + 0.5) * h};
  const double reach = r + h * std::sqrt(3.0) * 0.5;
  std::vector<uint32_t>& near = near_;
  near.clear();
  const int64_t bx = BlockOf(k[0]), by = BlockOf(k[1]), bz = BlockOf(k[2]);
  for (int64_t dz = -1; dz <= 1; ++dz)
    for (int64_t dy = -1; dy <= 1; ++dy)
      for (int64_t dx = -1; dx <= 1; ++dx) {
        const auto it = f.blocks.find(CellKey(bx + dx, by + dy, bz + dz));
        if (it == f.blocks.end()) continue;
        for (uint32_t src : it->second) {
          const Smoothed::Source& s = f.sources[src];
          const double ex = s.x[0] - centre[0], ey = s.x[1] - centre[1], ez = s.x[2] - centre[2];
          if (ex * ex + ey * ey + ez * ez < reach * reach) near.push_back(src);
        }
      }
  for (uint32_t m = 0; m < count; ++m) {
    const uint32_t p = members[m];
    const float3 q = points_[p];
    double sum[3] = {0, 0, 0}, weight = 0;
    for (uint32_t src : near) {
      const Smoothed::Source& s = f.sources[src];
      const double ex = s.x[0] - q.x, ey = s.x[1] - q.y, ez = s.x[2] - q.z;
      const double t2 = (ex * ex + ey * ey + ez * ez) * inv_r * inv_r;
      if (!(t2 < 1.0)) continue;
      const double w = (1.0 - t2) * (1.0 - t2);
      sum[0] += w * s.n[0], sum[1] += w * s.n[1], sum[2] += w * s.n[2];
      weight += w * s.area;
    }
    const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (len > kMinMean * weight && std::isfinite(len))
      f.out[p] = {float(sum[0] / len), float(sum[1] / len), float(sum[2] / len)};
  }
}

const std::vector<float3>& NormalField::At(float radius) {
  Prepare();
  if (!(radius > 0.f) || !std::isfinite(radius)) return own_;
  Smoothed& f = FieldOf(radius);
  for (uint32_t c = 0; f.cells_left > 0 && c < f.cell_done.size(); ++c) SolveCell(radius, f, c);
  return f.out;
}

float3 NormalField::At(float radius, uint32_t point) {
  Prepare();
  if (point >= points_.size()) return {0.f, 0.f, 0.f};
  if (!(radius > 0.f) || !std::isfinite(radius)) return own_[point];
  Smoothed& f = FieldOf(radius);
  if (f.point_cell[point] != UINT32_MAX) SolveCell(radius, f, f.point_cell[point]);
  return f.out[point];
}

}  // namespace mimetic
