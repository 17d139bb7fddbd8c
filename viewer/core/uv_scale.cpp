// viewer/core/uv_scale.cpp: see uv_scale.h.
#include "viewer/core/uv_scale.h"

#include <algorithm>
#include <cmath>

namespace mimetic::viewer {

float UvScaleGrid::At(float2 uv) const {
  if (cells <= 0 || scale.empty()) return whole;
  const auto cell = [&](float t) {
    const float c = std::isfinite(t) ? t * float(cells) : 0.f;
    return std::clamp(int(std::floor(c)), 0, cells - 1);
  };
  return scale[size_t(cell(uv.y)) * size_t(cells) + size_t(cell(uv.x))];
}

UvScaleGrid MakeUvScaleGrid(const MeshData& mesh, int cells) {
  UvScaleGrid g;
  if (mesh.uvs.size() != mesh.positions.size() || mesh.indices.empty()) return g;
  g.cells = std::clamp(cells, 1, 1024);
  const size_t n = size_t(g.cells) * size_t(g.cells);
  std::vector<double> area3(n, 0.0), area2(n, 0.0);
  double all3 = 0, all2 = 0;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    if (a >= mesh.positions.size() || b >= mesh.positions.size() || c >= mesh.positions.size())
      continue;
    const double s3 = 0.5 * double(Length(Cross(mesh.positions[b] - mesh.positions[a],
                                                mesh.positions[c] - mesh.positions[a])));
    const float2 p = mesh.uvs[a], q = mesh.uvs[b], r = mesh.uvs[c];
    const double s2 = 0.5 * std::fabs(double(q.x - p.x) * (r.y - p.y) - double(q.y - p.y) * (r.x - p.x));
    if (!(s2 > 0.0) || !std::isfinite(s2) || !std::isfinite(s3)) continue;
    const float u = (p.x + q.x + r.x) / 3.f, v = (p.y + q.y + r.y) / 3.f;
    const int cu = std::clamp(int(std::floor(u * float(g.cells))), 0, g.cells - 1);
    const int cv = std::clamp(int(std::floor(v * float(g.cells))), 0, g.cells - 1);
    area3[size_t(cv) * size_t(g.cells) + size_t(cu)] += s3;
    area2[size_t(cv) * size_t(g.cells) + size_t(cu)] += s2;
    all3 += s3, all2 += s2;
  }
  if (!(all2 > 0.0)) return UvScaleGrid{};
  g.whole = float(std::sqrt(all3 / all2));
  g.scale.assign(n, g.whole);
  for (size_t i = 0; i < n; ++i)
    if (area2[i] > 0.0) g.scale[i] = float(std::sqrt(area3[i] / area2[i]));
  return g;
}

}  // namespace mimetic::viewer
