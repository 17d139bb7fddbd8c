// wrinkles/offline/wrinkle_builder.h: compile-time tables for the wrinkle jobs (docs/model.md §4-8):
// triangle areas, muscle wrinkling regions (001), curve-wrinkle distances and directional
// shrinkage probes (000), and thickness-map sampling (002 §6). Inputs are the welded rest mesh:
// points (#P float3, mesh units) and triangles (3 point indices each).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "core/span.h"
#include "geometry/topology.h"
#include "wrinkles/offline/wrinkle_spec.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {

// CsrTable, BuildPointTriangles and BuildPointNeighbors (point -> triangles, point -> points)
// are geometry/topology.h's, included above.

// Rest area of each triangle, mesh units^2 (0 for a triangle with an out-of-range index).
std::vector<float> ComputeTriangleAreas(span<const float3> points, span<const uint32_t> triangles);

// |cos theta| between each edge (points[i] -> neighbour) and a unit direction per row, and the
// edge's length, on the REST positions (EdgeCompressionJob's weights, docs/model.md §5). A zero-length
// edge gets weight 0.
void ComputeCompressionWeights(span<const float3> rest_points, span<const uint32_t> row_points,
                               span<const float3> row_directions, span<const uint32_t> offsets,
                               span<const uint32_t> neighbors, std::vector<float>* rest_lengths,
                               std::vector<float>* weights);

// Muscle wrinkling region and its run-time table (docs/model.md §6, 001 eq. 1-3, 6-7, 12-15).
struct MuscleWrinkleTable {
  std::vector<uint32_t> points;        // region points, ascending
  std::vector<float> phase;            // w_i in [0, 2u) per row, mesh units
  std::vector<float> attenuation;      // At_i in [0, 1] per row
  std::vector<float3> directions;      // unit contraction direction per row (x_i -> mA for a
                                       // linear muscle, the fiber for a sheet), rest pose
  std::vector<uint32_t> edge_offsets;  // #rows + 1: row -> neighbour entries
  std::vector<uint32_t> edge_neighbors;
  std::vector<float> edge_rest_lengths;  // L_ij, mesh units
  std::vector<float> edge_weights;       // |cos theta_ij|
  float half_cycle = 0.f;              // u (001 eq. 6), mesh units
  float furrow_depth = 0.f;            // k0
  float shape = 0.f;                   // alpha
};

// One point's place in a muscle's wrinkling region (the per-point part of the table below).
// The spec must be valid (ValidateMuscleWrinkleSpec).
struct MuscleWrinkleSample {
  bool inside = false;       // in S_w (001 eq. 3 / 14)
  float phase = 0.f;         // w_i (eq. 7), mesh units, when inside
  float attenuation = 0.f;   // At_i (eq. 12 / 15), when inside
  float3 direction;          // unit contraction direction at the point
  float half_cycle = 0.f;    // u (eq. 6), mesh units (independent of the point)
};
MuscleWrinkleSample SampleMuscleWrinkleRegion(const MuscleWrinkleSpec& spec,
                                              const WrinkleMuscleGeometry& muscle, float3 x);

// Membership, per point, from the rest positions (001 eq. 1-3 / 13-14):
// linear: phi_i = angle(mI - mA, x_i - mA), l_i = |x_i - mA| cos(phi_i), lambda_i = l_i/R,
//         gamma_i = phi_i/phi; sheet: l_i = (x_i - mAc).f, h_i = distance to the central fiber,
//         lambda_i = l_i/Ls, gamma_i = 2 h_i/Ws, R -> Ls.
// A point is in the region when lambda_w <= lambda_i <= 1 and gamma_i <= 1. Then
// w_i = (l_i - lambda_w R) mod 2u (eq. 7) and At_i = Attenuation(q) with q from eq. 12 / 15.
// `neighbors` is the point adjacency (BuildPointNeighbors). Validates the spec first (errors
// under `where`); returns false on errors. An empty region is a warning, not an error.
bool BuildMuscleWrinkleTable(const MuscleWrinkleSpec& spec, const WrinkleMuscleGeometry& muscle,
                             span<const float3> rest_points, const CsrTable& neighbors,
                             const std::string& where, MuscleWrinkleTable* out, Diagnostics* diag);

// A directional shrinkage probe (000 eq. 4) for point `point` and a unit texture-space
// direction `dp` (the direction ACROSS which shrinkage is measured): the incident triangles hit
// along +dp and -dp (the first in point->triangle order when the ray runs along an edge), with
// the crossing of the opposite edge. `corner_uvs` holds 3 texture coordinates per triangle (so
// seams are handled: each triangle is used in its own chart). Sides whose texture triangle is
// degenerate or whose rest edges have zero length are left out.
ShrinkageProbe BuildShrinkageProbe(uint32_t point, float2 dp, span<const float3> rest_points,
                                   span<const uint32_t> triangles, span<const float2> corner_uvs,
                                   const CsrTable& point_triangles);

// How far a curve wrinkle reaches, mesh units: 8 w for Bando (beyond it |S| < 0.0023 d and the
// tail holds 0.73% of the furrow volume on that side), 20/3 sqrt(a0^2 + h0^2) for Yang-Zhang with eq. 9 (the widest profile that
// still has depth) and 20/3 times the flank length for the exact variant.
float CurveWrinkleSupport(const CurveWrinkleSpec& spec);

// Curve-wrinkle table (docs/model.md §7-8). For each point, its texture coordinate is each of its
// triangle corners' uvs; the distance to the curve is the smallest over them, converted to mesh
// units by the point's texture-to-mesh scale sqrt(sum of incident 3D areas / sum of their
// texture areas) (**choice**: widths and distances in mesh units, so both profiles and eq. 9 see
// one unit). Points within the support get an entry (wrinkles in spec order) and a shrinkage
// probe across the curve's tangent at the closest point.
struct CurveWrinkleTable {
  std::vector<CurveWrinkleParams> wrinkles;  // one per spec
  std::vector<uint32_t> points;              // rows: affected points, ascending
  std::vector<uint32_t> offsets;             // #rows + 1
  std::vector<CurveWrinkleEntry> entries;
  std::vector<ShrinkageProbe> probes;        // one per entry, same order: run
                                             // DirectionalShrinkageJob over entry ranges
};
bool BuildCurveWrinkleTable(span<const CurveWrinkleSpec> specs, span<const float3> rest_points,
                            span<const uint32_t> triangles, span<const float2> corner_uvs,
                            const std::string& where, CurveWrinkleTable* out, Diagnostics* diag);

// Thickness per point from an 8-bit grayscale map (002 §6: black 0, white max_thickness),
// bilinear, clamped at the border; texture coordinate (0, 0) is the first pixel (glTF), pixel
// centres at ((x + 0.5)/width, (y + 0.5)/height). Errors (empty or short image, bad size,
// negative or non-finite max) go to `diag` under `where`.
bool SampleThicknessMap(span<const uint8_t> gray, int width, int height, float max_thickness,
                        span<const float2> point_uvs, const std::string& where,
                        std::vector<float>* out, Diagnostics* diag);

}  // namespace mimetic
