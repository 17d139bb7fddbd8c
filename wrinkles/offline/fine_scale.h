// wrinkles/offline/fine_scale.h: fine-scale wrinkle textures (docs/model.md §20-22; Bando et al.
// 2002 §4-5, Bando 2001 §3-5): two direction fields on the mesh, the texture space, furrow
// carving into height images, their merge, noise and the tangent-space normal map.
//
// Offline code (Eigen for the harmonic solves). The run-time half, the per-vertex amplitudes
// M(s) of docs/model.md §23, is EvaluateJob's out_fine_amplitudes (rig/runtime).
// Everything here is deterministic: the same inputs and seed give the same bits, whatever
// the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "core/span.h"

namespace mimetic {

// A user direction vector (000 §5.1, 003 §3.1) at a file vertex: its direction (projected
// onto the vertex's tangent plane) and its magnitude (its length: [0, 1] for the 000
// parameters, [0, 2] for the 003 ones).
struct DirectionAnchor {
  uint32_t vertex = 0;  // file vertex (the mesh's own layout)
  float3 vector{};      // mesh axes; length = magnitude
  float weight = 1.f;   // lambda_i of 003 eq. 3.1 (inverse-distance interpolation only), > 0
};

struct DirectionFieldSpec {
  std::string name;
  std::vector<DirectionAnchor> anchors;  // at least one
};

enum class FieldInterpolation { kHarmonic, kInverseDistance };
// The texture space (003 §3.2, 000 §4): the mesh's uvs, or a projection (planar onto the mesh's
// x-y plane, cylindrical about its vertical axis y through the bounding box centre). kAuto =
// the uvs when the mesh has them, else cylindrical.
enum class TextureProjection { kAuto, kUv, kPlanar, kCylindrical };
// 000 eq. 1 (magnitude m in [0, 1]) or 003 eq. 5.1-5.6 (magnitude x in [0, 2], k_scale).
enum class FurrowParameterSet { kBando2002, kBando2001 };

inline constexpr int kMaxFineScaleSize = 8192;
inline constexpr float kDefaultFineRestAmplitude = 0.5f;  // r of 000 eq. 5 (docs/model.md §23)

// The rig file's `fine_scale` block (docs/rig-format.md), parsed.
struct FineScaleSpec {
  DirectionFieldSpec fields[2];
  FieldInterpolation interpolation = FieldInterpolation::kHarmonic;
  TextureProjection projection = TextureProjection::kAuto;
  bool minimize_distortion = false;  // 000 §4 harmonic smoothing of a projection's interior
  FurrowParameterSet parameters = FurrowParameterSet::kBando2002;
  float k_scale = 1.f;  // 003 eq. 5.2-5.4 (kBando2001 only), in (0, 16]
  float k_noise = 0.f;  // 003 §3.3 step 9, in [0, 1]
  float k_bump = 1.f;   // 003 §4.1, in [0, 64]
  float rest_amplitude = kDefaultFineRestAmplitude;  // r of M(s), [0, 1]
  // Where `mimetic texture` wrote the maps (resolved against the rig file; "" = not made yet).
  std::string height_maps[2];
  std::string normal_map;
};

// Checks the spec (errors under `where`, e.g. "fine_scale.fields[0].anchors[2].vector").
bool ValidateFineScaleSpec(const FineScaleSpec& spec, size_t vertex_count,
                           const std::string& where, Diagnostics* diag);

// The six furrow parameters (000 eq. 1; 003 eq. 5.1-5.6 with x = the magnitude), pixels and
// radians. max_angle is the bound of theta = max_angle * rand(-1, 1).
struct FurrowParams {
  int segments = 0;        // N
  float max_angle = 0.f;   // |theta| bound
  float length = 0.f;      // D
  float intensity = 1.f;   // I, the grey level drawn (1 = no furrow)
  float width = 0.f;       // W_h
  float spacing = 0.f;     // W_o
};
FurrowParams FurrowParamsFor(FurrowParameterSet set, float magnitude, float k_scale);
// The largest magnitude of a set (1 for 000, 2 for 003).
float MaxMagnitude(FurrowParameterSet set);

// The welded mesh the fields live on.
struct FineScaleMesh {
  span<const float3> points;      // #P rest positions
  span<const uint32_t> triangles; // 3 per triangle, into points
  span<const float2> corner_uvs;  // 3 per triangle (the mesh's uvs), or empty
};

// Interpolates the per-point field (3D tangent vectors, length = magnitude) from anchors given
// at points (`anchor_points`, `anchor_vectors`, `anchor_weights`): harmonic (cotangent spring
// energy minimised with the anchors fixed, 000 §5.1; Eigen's sparse Cholesky) or inverse
// distance (003 eq. 3.1). Each result is projected onto its point's tangent plane (the
// area-weighted normal). Errors (no anchor, an anchor out of range, a solve that fails) name
// `where`.
bool InterpolateDirectionField(const FineScaleMesh& mesh, span<const uint32_t> anchor_points,
                               span<const float3> anchor_vectors,
                               span<const float> anchor_weights, FieldInterpolation method,
                               const std::string& where, std::vector<float3>* out,
                               Diagnostics* diag);

// Both (or any number of) fields at once: the same result as one InterpolateDirectionField per
// field; the harmonic method factors the mesh's Laplacian once for all of them (over the
// points that are no field's anchor; each field's other anchors are solved as a small dense
// system on the harmonic extensions). `out` holds fields.size() vectors. Errors name
// `where`.fields[k].
struct FieldAnchors {
  span<const uint32_t> points;
  span<const float3> vectors;
  span<const float> weights;
};
bool InterpolateDirectionFields(const FineScaleMesh& mesh, span<const FieldAnchors> fields,
                                FieldInterpolation method, const std::string& where,
                                std::vector<float3>* out, Diagnostics* diag);
// The two fields of `spec` (anchors as points), InterpolateDirectionFields.
bool InterpolateSpecFields(const FineScaleSpec& spec, const FineScaleMesh& mesh,
                           const std::vector<uint32_t> anchor_points[2], std::vector<float3> out[2],
                           Diagnostics* diag);

// Texture coordinates of every triangle corner (3 per triangle) for `projection` (kAuto
// resolved by the caller's corner_uvs), with the optional 000 §4 harmonic distortion
// minimisation (boundary points fixed, interior points at the cotangent-weighted harmonic
// map; needs a projection without seams, i.e. one uv per point). Cylindrical coordinates use
// u = angle / 2 pi about +y from +z (003 eq. 3.2), v = 1 - normalised height; planar u, v =
// x, 1 - y normalised to the bounding square.
bool MakeTextureSpace(const FineScaleMesh& mesh, TextureProjection projection,
                      bool minimize_distortion, const std::string& where,
                      std::vector<float2>* corner_uvs, Diagnostics* diag);

// Unit texture-space direction of the field at `point`, from the first incident triangle with
// a non-degenerate texture triangle (the field's 3D vector expressed in that triangle's
// texture chart); (0, 0) when there is none or the field vanishes.
float2 TextureDirectionAt(const FineScaleMesh& mesh, span<const float2> corner_uvs,
                          span<const uint32_t> point_triangle_offsets,
                          span<const uint32_t> point_triangles, span<const float3> field,
                          uint32_t point);

// A field rasterised into texture space: per pixel a direction (x right = +u, y down = +v,
// unit or 0) and a magnitude; `mapped` = the pixel centre lies on a texture triangle.
// Pixel (x, y) has centre uv ((x + 0.5) / size, (y + 0.5) / size).
struct FieldImage {
  int size = 0;
  std::vector<float2> direction;
  std::vector<float> magnitude;
  std::vector<uint8_t> mapped;
};
// Rasterises `field` (per point, 3D) with corner uvs; each corner's vector is mapped to its
// triangle's texture chart, interpolated linearly (003 §3.3 step 1, Gouraud-like), and
// normalised; the magnitude is interpolated linearly.
FieldImage RasterizeField(const FineScaleMesh& mesh, span<const float2> corner_uvs,
                          span<const float3> field, int size);
// Both fields of a rig in one walk over the triangles: out[f] equals RasterizeField of field f.
void RasterizeFields(const FineScaleMesh& mesh, span<const float2> corner_uvs,
                     span<const float3> field1, span<const float3> field2, int size,
                     FieldImage out[2]);

// One carved segment, pixels (image space).
struct FurrowSegment {
  float2 p, q;
  uint32_t furrow = 0;
};
// Why one side of a furrow stopped.
enum class FurrowEnd : uint8_t { kBudget, kCrossing, kBorder, kNoField };
struct FurrowSide {
  uint32_t segments = 0;  // drawn on this side
  FurrowEnd end = FurrowEnd::kBudget;
  float2 end_point{};
};
struct Furrow {
  float2 start{};
  float start_magnitude = 0.f;
  uint32_t first_segment = 0, segment_count = 0;  // into CarveResult::segments
  FurrowSide sides[2];                            // along +d, along -d
};
struct CarveResult {
  int size = 0;
  std::vector<float> height;  // size^2, row-major, 1 = white (no furrow), 0 = deepest
  std::vector<Furrow> furrows;
  std::vector<FurrowSegment> segments;
  uint32_t random_starts = 0, scan_starts = 0;  // furrows from each phase
};

struct CarveOptions {
  FurrowParameterSet parameters = FurrowParameterSet::kBando2002;
  float k_scale = 1.f;
  uint64_t seed = 1;
  // The random phase ends after this many consecutive picks land on occupied pixels ("until
  // many furrows fail", 000 §5.2); then every free pixel is a start.
  uint32_t max_failures = 256;
  bool record = false;  // keep furrows and segments (tests; costs memory)
  // Called with a fraction in [0, 1] now and then (from the carving thread).
  std::function<void(float)> progress;
};

// 000 §5.2 steps 1-7 on one field: growth both ways from each start (+d first), the budget
// n = min(n, N), the perturbation theta, the step D, the cut at the nearest crossing of
// another furrow's centre line or at the border of the mapped area (then n = 0), the segment
// drawn into the height image with intensity I and real width W_h (box-filtered coverage:
// h = min(h, 1 - (1 - I) cov)), the occupancy drawn to distance W_o of the centre line.
void CarveFurrows(const FieldImage& field, const CarveOptions& options, CarveResult* out);

// Everything `mimetic texture` makes, at size x size.
struct FineScaleMaps {
  int size = 0;
  std::vector<float> height[2];  // per field, [0, 1]
  std::vector<float> merged;     // min of the two (003 step 8), minus k_noise noise (step 9)
  std::vector<uint8_t> normal;   // 3 per pixel: tangent-space normal map (8-bit)
};
struct FineScaleTextureOptions {
  int size = 1024;
  uint64_t seed = 1;
  int threads = 1;  // 1 or 2 (one field per thread): the same bytes
  std::function<void(float)> progress;  // overall fraction, called from one thread at a time
};
// Fields (interpolated), texture space, both carvings, merge, noise and normal map.
// `anchor_points` per field: the anchors' points (the caller maps file vertices).
bool MakeFineScaleMaps(const FineScaleSpec& spec, const FineScaleMesh& mesh,
                       const std::vector<uint32_t> anchor_points[2],
                       const FineScaleTextureOptions& options, FineScaleMaps* out,
                       Diagnostics* diag);

// The merged map's noise (003 §3.3 step 9): h -= k_noise * rand[0, 1), clamped at 0.
void AddHeightNoise(float k_noise, uint64_t seed, std::vector<float>* height);
// Tangent-space normal map by bump mapping (003 §4.1): with central differences of h in
// pixels, n = normalize(-k_bump dh/dx, k_bump dh/dy, 1) (+x = +u; +y = up in the image, i.e.
// -v: the glTF / OpenGL convention), stored as round(255 (n + 1) / 2).
std::vector<uint8_t> BumpNormalMap(span<const float> height, int size, float k_bump, int threads);

}  // namespace mimetic
