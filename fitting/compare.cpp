// fitting/compare.cpp: CompareMeshes (Bando's surface distance, 000 §8, and the per-vertex
// motion measures of docs/model.md §13).
#include "fitting/compare.h"

#include <cmath>
#include <limits>
#include <string>

#include "geometry/normals.h"
#include "geometry/surface_query.h"

namespace mimetic {
namespace {

void Accumulate(double d, SurfaceDistance* s) {
  s->mean += d;
  s->max = std::max(s->max, d);
  ++s->count;
}

void Finish(SurfaceDistance* s) {
  if (s->count) s->mean /= double(s->count);
}

double Length64(float3 v) { return std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z); }
double Dot64(float3 a, float3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }

bool Usable(const MeshData& m, const char* name, Diagnostics* diag) {
  if (m.vertex_count() == 0 || m.triangle_count() == 0) {
    diag->Error(name, "mesh '" + m.source + "' has no " +
                          (m.vertex_count() == 0 ? "vertices" : "triangles") +
                          "; expected a triangle mesh");
    return false;
  }
  return true;
}

}  // namespace

bool SameTopology(const MeshData& a, const MeshData& b) {
  return a.vertex_count() == b.vertex_count() && a.indices == b.indices;
}

bool CompareMeshes(const MeshData& a, const MeshData& b, const CompareOptions& options,
                   CompareResult* out, Diagnostics* diag) {
  Diagnostics local;
  Diagnostics* d = diag ? diag : &local;
  *out = CompareResult{};
  if (!Usable(a, "A", d) || !Usable(b, "B", d)) return false;
  const MeshData* n = options.neutral;
  if (n && n->vertex_count() != b.vertex_count()) {
    d->Error("neutral", "has " + std::to_string(n->vertex_count()) + " vertices, B has " +
                            std::to_string(b.vertex_count()) +
                            "; expected the neutral of B (the same vertex count)");
    return false;
  }
  if (n && !Usable(*n, "neutral", d)) return false;
  const uint32_t nb = uint32_t(b.vertex_count());

  // The region.
  const CompareRegion& region = options.region;
  out->in_region.assign(nb, 0);
  switch (region.kind) {
    case CompareRegion::Kind::kAll:
      out->in_region.assign(nb, 1);
      break;
    case CompareRegion::Kind::kMoved:
      if (!n) {
        d->Error("region", "a region by displacement ('moved:T') needs the neutral (--neutral)");
        return false;
      }
      if (!(region.threshold >= 0.f) || !std::isfinite(region.threshold)) {
        d->Error("region", "displacement threshold " + std::to_string(region.threshold) +
                               "; expected a finite number >= 0 (mesh units)");
        return false;
      }
      for (uint32_t v = 0; v < nb; ++v)
        out->in_region[v] = Length64(b.positions[v] - n->positions[v]) > region.threshold;
      break;
    case CompareRegion::Kind::kVertices:
      for (size_t i = 0; i < region.vertices.size(); ++i) {
        const uint32_t v = region.vertices[i];
        if (v >= nb) {
          d->Error("region[" + std::to_string(i) + "]",
                   "vertex " + std::to_string(v) + " is out of range; B has " +
                       std::to_string(nb) + " vertices");
          return false;
        }
        out->in_region[v] = 1;
      }
      break;
  }
  for (uint8_t r : out->in_region) out->region_count += r;
  if (out->region_count == 0) {
    d->Error("region", region.kind == CompareRegion::Kind::kMoved
                           ? "is empty: no vertex of B moves more than " +
                                 std::to_string(region.threshold) + " from the neutral"
                           : std::string("is empty; expected at least one vertex of B"));
    return false;
  }

  // B's region -> A's surface (and -> the neutral's).
  const SurfaceQuery query_a(a);
  out->b_distance.assign(nb, 0.f);
  for (uint32_t v = 0; v < nb; ++v) {
    if (!out->in_region[v]) continue;
    const float dist = query_a.Nearest(b.positions[v]).t;
    out->b_distance[v] = dist;
    Accumulate(dist, &out->b_to_a);
  }
  Finish(&out->b_to_a);
  if (n) {
    const SurfaceQuery query_n(*n);
    for (uint32_t v = 0; v < nb; ++v)
      if (out->in_region[v]) Accumulate(query_n.Nearest(b.positions[v]).t, &out->b_to_neutral);
    Finish(&out->b_to_neutral);
    out->has_neutral_measures = true;
    const double num = out->b_to_a.mean, den = out->b_to_neutral.mean;
    out->ratio = den > 0.0 ? num / den
                           : (num > 0.0 ? std::numeric_limits<double>::infinity() : 1.0);
  }

  // A's corresponding vertices -> B's surface.
  out->same_topology = SameTopology(a, b);
  const SurfaceQuery query_b(b);
  for (uint32_t v = 0; v < uint32_t(a.vertex_count()); ++v) {
    if (out->same_topology) {
      if (out->in_region[v]) Accumulate(query_b.Nearest(a.positions[v]).t, &out->a_to_b);
      continue;
    }
    const SurfaceQuery::Hit hit = query_b.Nearest(a.positions[v]);
    const uint32_t* c = &b.indices[3 * size_t(hit.triangle)];
    if (out->in_region[c[0]] || out->in_region[c[1]] || out->in_region[c[2]])
      Accumulate(hit.t, &out->a_to_b);
  }
  Finish(&out->a_to_b);

  // Per-vertex measures.
  if (out->same_topology && n) {
    out->has_vertex_measures = true;
    double weight = 0.0, cosine = 0.0, moved_a = 0.0;
    for (uint32_t v = 0; v < nb; ++v) {
      if (!out->in_region[v]) continue;
      Accumulate(Length64(a.positions[v] - b.positions[v]), &out->vertex_error);
      const float3 da = a.positions[v] - n->positions[v], db = b.positions[v] - n->positions[v];
      const double la = Length64(da), lb = Length64(db);
      weight += lb;
      moved_a += la;
      if (la > 0.0 && lb > 0.0) cosine += Dot64(da, db) / la;  // |dB| cos = dA . dB / |dA|
    }
    Finish(&out->vertex_error);
    out->direction_cosine = weight > 0.0 ? cosine / weight : 0.0;
    out->magnitude_ratio = weight > 0.0 ? moved_a / weight : 0.0;
    out->mean_b_displacement = weight / out->region_count;
    out->mean_a_displacement = moved_a / out->region_count;
  } else if (n) {
    double moved_b = 0.0;
    for (uint32_t v = 0; v < nb; ++v)
      if (out->in_region[v]) moved_b += Length64(b.positions[v] - n->positions[v]);
    out->mean_b_displacement = moved_b / out->region_count;
  }
  return true;
}

bool SplitResidual(const MeshData& a, const MeshData& b, const MeshData& neutral,
                   const std::vector<uint8_t>& in_region, const std::vector<float>& distance,
                   const std::vector<uint8_t>& parts, uint32_t part_count, ResidualSplit* out,
                   Diagnostics* diag) {
  const size_t nv = b.vertex_count();
  if (a.vertex_count() != nv || neutral.vertex_count() != nv) {
    diag->Error("residual", "A, B and the neutral have " + std::to_string(a.vertex_count()) +
                                ", " + std::to_string(nv) + " and " +
                                std::to_string(neutral.vertex_count()) +
                                " vertices; the split needs one topology");
    return false;
  }
  if (in_region.size() != nv || distance.size() != nv || parts.size() != nv) {
    diag->Error("residual", "the region has " + std::to_string(in_region.size()) +
                                " entries, the distances " + std::to_string(distance.size()) +
                                " and the parts " + std::to_string(parts.size()) + ", for " +
                                std::to_string(nv) + " vertices");
    return false;
  }
  for (size_t v = 0; v < nv; ++v)
    if (parts[v] >= part_count) {
      diag->Error("residual", "vertex " + std::to_string(v) + " has part " +
                                  std::to_string(parts[v]) + ", of " +
                                  std::to_string(part_count));
      return false;
    }
  const std::vector<float3> normals = ComputeVertexNormals(neutral);
  std::vector<double> by_part(part_count, 0.0);
  double total = 0.0, along = 0.0, far = 0.0;
  for (size_t v = 0; v < nv; ++v) {
    if (!in_region[v]) continue;
    const float3 r = a.positions[v] - b.positions[v];
    const double rn = Dot64(r, normals[v]);
    total += Dot64(r, r);
    along += rn * rn;
    far += double(distance[v]);
    by_part[parts[v]] += double(distance[v]);
  }
  out->normal_share = total > 0.0 ? along / total : 0.0;
  out->part_share.assign(part_count, 0.0);
  for (uint32_t k = 0; k < part_count; ++k)
    out->part_share[k] = far > 0.0 ? by_part[k] / far : 0.0;
  return true;
}

}  // namespace mimetic
