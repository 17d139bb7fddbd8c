// geometry/topology.cpp: see topology.h.
#include "geometry/topology.h"

#include <algorithm>
#include <utility>

namespace mimetic {

CsrTable BuildPointTriangles(span<const uint32_t> triangles, size_t point_count) {
  CsrTable t;
  t.offsets.assign(point_count + 1, 0);
  const size_t tri_count = triangles.size() / 3;
  for (size_t k = 0; k < tri_count * 3; ++k) {
    if (triangles[k] < point_count) ++t.offsets[triangles[k] + 1];
  }
  for (size_t p = 0; p < point_count; ++p) t.offsets[p + 1] += t.offsets[p];
  t.items.resize(t.offsets[point_count]);
  std::vector<uint32_t> fill(t.offsets.begin(), t.offsets.end() - 1);
  for (size_t k = 0; k < tri_count * 3; ++k) {
    if (triangles[k] < point_count) t.items[fill[triangles[k]]++] = static_cast<uint32_t>(k / 3);
  }
  return t;
}

CsrTable BuildPointNeighbors(span<const uint32_t> triangles, size_t point_count) {
  std::vector<std::vector<uint32_t>> lists(point_count);
  const size_t tri_count = triangles.size() / 3;
  for (size_t t = 0; t < tri_count; ++t) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = triangles[3 * t + e], b = triangles[3 * t + (e + 1) % 3];
      if (a >= point_count || b >= point_count || a == b) continue;
      lists[a].push_back(b);
      lists[b].push_back(a);
    }
  }
  CsrTable out;
  out.offsets.assign(point_count + 1, 0);
  for (size_t p = 0; p < point_count; ++p) {
    auto& l = lists[p];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    out.offsets[p + 1] = out.offsets[p] + static_cast<uint32_t>(l.size());
    out.items.insert(out.items.end(), l.begin(), l.end());
  }
  return out;
}

void BuildEdgeTable(span<const uint32_t> triangles, EdgeTable* et) {
  const size_t n = triangles.size() / 3 * 3;
  // The (edge key, corner) pairs in ascending order, as a sort of all of them would give:
  // a counting sort by the key's low vertex (stable: corners stay ascending), then each
  // low vertex's few pairs sorted by (high vertex, corner).
  // (Sparse indices, far more points than corners, take one sort of everything instead.)
  size_t points = 0;
  for (size_t i = 0; i < n; ++i) points = std::max(points, size_t(triangles[i]) + 1);
  const bool sparse = points > 2 * n + 1024;
  if (sparse) points = 1;
  std::vector<uint32_t> bucket(points + 1, 0);
  auto degenerate = [&](size_t t) {
    const uint32_t* v = &triangles[t];
    return v[0] == v[1] || v[1] == v[2] || v[0] == v[2];  // no edges
  };
  for (size_t t = 0; t < n; t += 3) {
    if (degenerate(t)) continue;
    for (size_t k = 0; k < 3; ++k)
      ++bucket[sparse ? 1 : std::min(triangles[t + k], triangles[t + (k + 1) % 3]) + size_t(1)];
  }
  for (size_t p = 0; p < points; ++p) bucket[p + 1] += bucket[p];
  std::vector<std::pair<uint64_t, uint32_t>> uses(bucket[points]);  // (edge key, corner)
  {
    std::vector<uint32_t> fill(bucket.begin(), bucket.end() - 1);
    for (size_t t = 0; t < n; t += 3) {
      if (degenerate(t)) continue;
      for (size_t k = 0; k < 3; ++k) {
        const uint32_t a = triangles[t + k], b = triangles[t + (k + 1) % 3];
        uses[fill[sparse ? 0 : std::min(a, b)]++] = {EdgeKey(a, b), static_cast<uint32_t>(t + k)};
      }
    }
  }
  for (size_t p = 0; p < points; ++p)
    std::sort(uses.begin() + bucket[p], uses.begin() + bucket[p + 1]);
  et->keys.clear();
  et->start.clear();
  et->tri_edge.assign(n, EdgeTable::kNoEdge);
  et->corners.resize(uses.size());
  for (size_t i = 0; i < uses.size(); ++i) {
    if (i == 0 || uses[i].first != uses[i - 1].first) {
      et->keys.push_back(uses[i].first);
      et->start.push_back(static_cast<uint32_t>(i));
    }
    et->tri_edge[uses[i].second] = static_cast<uint32_t>(et->keys.size() - 1);
    et->corners[i] = uses[i].second;
  }
  et->start.push_back(static_cast<uint32_t>(uses.size()));
}

std::vector<uint32_t> BoundaryEdges(const EdgeTable& edges) {
  std::vector<uint32_t> out;
  for (size_t e = 0; e < edges.edge_count(); ++e)
    if (edges.use_count(e) == 1) out.push_back(static_cast<uint32_t>(e));
  return out;
}

std::vector<uint32_t> NonManifoldEdges(const EdgeTable& edges) {
  std::vector<uint32_t> out;
  for (size_t e = 0; e < edges.edge_count(); ++e)
    if (edges.use_count(e) > 2) out.push_back(static_cast<uint32_t>(e));
  return out;
}

}  // namespace mimetic
