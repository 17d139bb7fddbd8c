// fitting/compare.h: how close a mesh A (a rig's output) is to a mesh B (a real expression
// shape), the measurements behind `mimetic compare` and the fidelity report
// (docs/model.md §13).
//
// Bando's metric (000 §8): the distance from each vertex of B's region to A's surface (the
// nearest point of any triangle of A), mean and max; and the other way, from A's vertices to
// B's surface. When A and B share topology (the same vertex count and triangles), and a
// neutral N of that topology is given, also the per-vertex error |A_v - B_v| and how well the
// motions agree, with the displacements dA = A - N and dB = B - N:
//   direction cosine  = sum_v |dB_v| cos(dA_v, dB_v) / sum_v |dB_v|   (weighted by the real motion;
//                       a vertex where dA_v = 0 counts as cos = 0)
//   magnitude ratio   = sum_v |dA_v| / sum_v |dB_v|
//   ratio             = mean(B -> A) / mean(B -> N)   (< 1: closer than doing nothing)
// all over the region's vertices.
#pragma once

#include <cstdint>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"

namespace mimetic {

struct CompareRegion {
  enum class Kind {
    kAll,       // every vertex of B
    kMoved,     // vertices of B farther than `threshold` from the neutral (needs the neutral)
    kVertices,  // the vertices listed in `vertices` (indices into B)
  };
  Kind kind = Kind::kAll;
  float threshold = 0.f;           // kMoved: mesh units, >= 0
  std::vector<uint32_t> vertices;  // kVertices
};

struct CompareOptions {
  const MeshData* neutral = nullptr;  // optional; same vertex count as B
  CompareRegion region;
};

struct SurfaceDistance {
  double mean = 0.0, max = 0.0;  // mesh units
  uint32_t count = 0;            // vertices measured
};

struct CompareResult {
  uint32_t region_count = 0;            // vertices of B in the region
  std::vector<uint8_t> in_region;       // #V(B): 1 where the vertex is in the region
  std::vector<float> b_distance;        // #V(B): distance to A's surface (0 outside the region)
  SurfaceDistance b_to_a;               // B's region -> A's surface
  // A -> B's surface, over A's vertices that correspond to the region: the same indices when
  // the topology is shared, else A's vertices whose nearest point on B lies on a triangle
  // with a corner in the region.
  SurfaceDistance a_to_b;
  bool same_topology = false;
  bool has_neutral_measures = false;    // the neutral was given (and, for the per-vertex
                                        // measures, A shares its topology)
  SurfaceDistance b_to_neutral;         // B's region -> the neutral's surface
  double ratio = 0.0;                   // b_to_a.mean / b_to_neutral.mean (1 when both are 0,
                                        // inf when only b_to_neutral.mean is)
  bool has_vertex_measures = false;     // same topology and a neutral
  SurfaceDistance vertex_error;         // |A_v - B_v| over the region
  double direction_cosine = 0.0;        // see the top of the file; 0 when B does not move
  double magnitude_ratio = 0.0;         // sum |dA| / sum |dB|; 0 when B does not move
  double mean_b_displacement = 0.0;     // mean |dB| over the region, mesh units
  double mean_a_displacement = 0.0;     // mean |dA| over the region (same topology only)
};

// True when the two meshes have the same vertex count and the same triangles.
bool SameTopology(const MeshData& a, const MeshData& b);

// Measures A against B. Returns false and records why for: an empty mesh (no vertex or no
// triangle), a neutral whose vertex count differs from B's, a kMoved region without a neutral
// or with a negative / non-finite threshold, a listed vertex out of range, or an empty region.
// Never throws; deterministic.
bool CompareMeshes(const MeshData& a, const MeshData& b, const CompareOptions& options,
                   CompareResult* out, Diagnostics* diag);

// Where the remaining error of A against B lies, with A, B and the neutral N of one topology,
// over the region's vertices:
//   normal_share   = sum (r_v . n_v)^2 / sum |r_v|^2, r_v = A_v - B_v, n_v N's vertex normal
//                    (ComputeVertexNormals): the share of the per-vertex error that is height
//                    (1: the rig's surface is only too high or too deep; 0: it slides to the
//                    wrong place within the skin, which a surface distance does not see);
//   part_share[k]  = sum over the region's vertices labelled k of distance[v], over the sum
//                    over the region: where the surface distance (B -> A, the ratio's
//                    numerator; CompareResult::b_distance) lies, by part of the face (labels
//                    from the caller, < part_count).
// A share is 0 when what it divides is 0.
struct ResidualSplit {
  double normal_share = 0.0;
  std::vector<double> part_share;  // part_count entries
};
// False, with a message, for meshes of different vertex counts, `in_region`, `distance` or
// `parts` of another length, a label >= part_count. Deterministic (serial sums in double).
bool SplitResidual(const MeshData& a, const MeshData& b, const MeshData& neutral,
                   const std::vector<uint8_t>& in_region, const std::vector<float>& distance,
                   const std::vector<uint8_t>& parts, uint32_t part_count, ResidualSplit* out,
                   Diagnostics* diag);

}  // namespace mimetic
