// geometry/surface_query.h: ray casts and nearest-point queries on a triangle mesh, with the
// smooth (interpolated vertex) normal at the point found.
//
// A bounding-volume hierarchy over the triangles: binary, median split on the longest axis of
// the centroid bounds, at most 4 triangles per leaf, built in O(#T log #T); a query visits
// O(log #T) nodes on typical meshes. Positions in mesh units. Vertex normals are
// area-weighted and shared by vertices at the same position (geometry/normals.h with
// share_by_position), so a UV seam does not crease them.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "geometry/mesh.h"

namespace mimetic {

class SurfaceQuery {
 public:
  // Keeps a reference to `mesh`: it must outlive the query and not change. Its indices must
  // be < #V; its own normals are not read.
  explicit SurfaceQuery(const MeshData& mesh);

  struct Hit {
    bool found = false;
    float t = 0.f;          // Raycast: distance along the unit direction; Nearest: distance
    float3 point;           // mesh units
    float3 normal;          // unit: NormalAt(triangle, point) (Raycast: facing the ray origin)
    float3 bary;            // weights of `point` on the triangle's corners 0, 1, 2
    uint32_t triangle = 0;  // index into the mesh's triangles
  };

  // First hit of the ray origin + t * dir, t > 0 (`dir` need not be unit; both sides of a
  // triangle count). found = false when it misses, for a zero `dir` and an empty mesh.
  Hit Raycast(float3 origin, float3 dir) const;

  // The closest surface point to `p` (found = false only for an empty mesh); t = distance.
  Hit Nearest(float3 p) const;

  // The normal at `p` on triangle `tri` (p on or near it): the vertex normals interpolated
  // with p's barycentric weights (stored in *bary when given), normalised; the face normal
  // where that is zero or points away from the face (inconsistent winding around a vertex).
  float3 NormalAt(uint32_t tri, float3 p, float3* bary = nullptr) const;

 private:
  struct Node {
    float3 lo, hi;
    uint32_t first = 0, count = 0;  // leaf: triangles [first, first + count) of order_
    uint32_t left = 0, right = 0;   // inner: children (count == 0)
  };
  uint32_t Build(uint32_t first, uint32_t count, int depth);
  const MeshData& mesh_;
  std::vector<float3> vertex_normals_;
  std::vector<uint32_t> order_;
  std::vector<float3> centroids_;
  std::vector<Node> nodes_;
};

}  // namespace mimetic
