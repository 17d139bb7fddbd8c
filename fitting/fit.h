// fitting/fit.h: place a landmark-relative muscle template (muscle_template.h) on a head.
//
// Method (docs/fitting.md): the 68 landmarks give a face frame (FaceFrame); each template
// point is the weighted mean of its landmarks plus an offset in the face plane (units of the
// eye-corner distance s), cast onto the head along -z of the frame (first hit from the
// front; the nearest surface point when the ray misses) and moved `depth * s` along the
// inward surface normal. Radii, lengths, widths and strengths scale by s; the skin thickness
// is evaluated per vertex from the template's regions. The result is an ordinary RigSpec.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "fitting/landmarks.h"
#include "fitting/muscle_template.h"
#include "geometry/mesh.h"
#include "geometry/surface_query.h"
#include "rig/offline/rig_spec.h"

namespace mimetic {

// Orthonormal face frame from the 68 iBUG landmarks.
struct FaceFrame {
  float3 origin;            // landmark 27 (top of the nose bridge), mesh units
  float3 x{1.f, 0.f, 0.f};  // unit: subject's right outer eye corner (36) -> left one (45)
  float3 y{0.f, 1.f, 0.f};  // unit: chin (8) -> bridge (27), made orthogonal to x
  float3 z{0.f, 0.f, 1.f};  // x cross y: toward the viewer
  float scale = 1.f;        // s = |45 - 36|, mesh units

  // Face-frame coordinates in units of s -> mesh position, and back.
  float3 ToWorld(float3 local) const;
  float3 ToLocal(float3 world) const;
  // A face-frame direction (no origin, no scale) -> mesh direction.
  float3 DirectionToWorld(float3 local) const;
};

// Builds the frame from 68 landmark positions. Errors: not 68 points, non-finite points,
// coincident eye corners (36, 45) or a chin (8) on the eye-corner line (degenerate frame).
bool ComputeFaceFrame(const std::vector<float3>& landmarks, FaceFrame* out, Diagnostics* diag);

// Landmark positions on `head`: the file's points, or the positions of its vertex indices
// (each must be < head.vertex_count()). Errors name the landmark and say what was expected.
bool ResolveLandmarks(const Landmarks& landmarks, const MeshData& head,
                      std::vector<float3>* out, Diagnostics* diag);

// Checks that 68 landmark positions belong to `head` as it lies (issue 11: mirrored,
// upside-down or other-unit landmarks used to place every muscle on the back of the head or
// around the nose without a word). Errors (where = "landmarks"), each saying what looks wrong:
//   - a landmark farther from the surface than kLandmarkSurfaceTolerance of the mesh's
//     bounding-box diagonal, naming the worst one; and when the landmarks, scaled by a unit
//     factor (10, 100, 1000, 25.4, 2.54 or their inverses), negated in y or in x (about 0 or
//     the mesh's centre), would lie on the surface, that diagnosis instead ("landmarks are about
//     10x the mesh size: another unit? ...", "landmarks look upside down: ...");
//   - a face frame (ComputeFaceFrame) whose z points into the head: seen along -z of the frame
//     most landmarks are hidden behind other surface, and seen along +z (from behind) they are
//     not; for a mesh open at the back (a face mask) the mesh's own normals (its winding) there
//     decide. Reported as upside down when the frame's up runs along -y of the mesh (heads face
//     +z with +y up), else as mirrored left/right (iBUG "right" is the subject's right:
//     docs/landmarks-format.md, Sides).
// Needs a valid frame (ComputeFaceFrame first). `query` is a SurfaceQuery of `head`.
inline constexpr float kLandmarkSurfaceTolerance = 0.05f;
bool CheckLandmarksOnHead(const std::vector<float3>& landmarks, const MeshData& head,
                          const SurfaceQuery& query, Diagnostics* diag);

// The ray casts and nearest-point queries that place points on the head: SurfaceQuery,
// geometry/surface_query.h (included above).

// What the fit did with one template point (for `mimetic fit` and tests).
struct PlacedPoint {
  std::string muscle;  // muscle name, or curve wrinkle name for a curve's control point
  std::string role;    // "attachment", "insertion", "attachment[0]", ..., "control[2]"
  float3 landmark_point;  // weighted landmark mean + offset, before projection (mesh units)
  float3 surface;         // where it met the surface
  float3 position;        // final position: surface + depth * s * inward normal
  float depth = 0.f;      // mesh units
  bool ray_hit = true;    // false: the ray missed and the nearest surface point was used
};

// A curve wrinkle's control points in texture space (the uvs of the surface hits).
struct PlacedCurve {
  std::string name;
  float2 uv[4];
};

struct FitReport {
  FaceFrame frame;
  std::string units;  // the units written into the rig
  std::vector<PlacedPoint> points;  // muscle points, then curve control points
  std::vector<PlacedCurve> curves;
};

// The jaw block of the rig from the template's (docs/model.md §18, docs/template-format.md):
// the right condyle at the weighted landmark mean plus `offset` (face frame, times s), the left
// one mirrored; the glide `translation` turned into the mesh frame and times s; the mouth point
// the midpoint of the inner lip midline (62, 66), the width the outer corners' distance (48, 54);
// the blend parameters copied. `lm` are the 68 resolved landmarks, `frame` their face frame.
void PlaceJaw(const TemplateJaw& tmpl, const std::vector<float3>& lm, const FaceFrame& frame,
              JawSpec* out);

// Places `tmpl` on `head` (units `units`: "mm", "cm", "dm", "m" or "in"; written into the
// rig). Fills every field of `out` except `file`, `mesh_path` and `mesh_name`, which the
// caller sets; `mesh_fingerprint` is `head`'s (geometry/fingerprint.h). Thickness is per vertex (`ThicknessSpec::kPerVertex`), in mesh units.
// Muscle wrinkle blocks go to `muscle_wrinkles` (depth and h_c times s; empty when no muscle
// has one); each curve wrinkle's control points are placed like muscle points (depth 0) and
// replaced by the texture coordinates of the surface hit (barycentric in the hit triangle),
// depth and width times s.
// Errors: landmarks count != 68, a vertex index out of range, a degenerate frame, landmarks
// that do not belong to the head as it lies (CheckLandmarksOnHead), unknown units, a point that found no surface (ray missed and nearest surface point farther than
// 0.5 s), a linear muscle whose attachment and insertion coincide, curve wrinkles on a head
// without texture coordinates, a curve whose control points' uvs lie more than 0.5 apart in u
// or v (the curve would cross a UV seam), a wrinkle the wrinkle module's checks refuse.
// `head_query`: a SurfaceQuery of `head` already built, for a caller that fits the same head
// many times (the calibration: hundreds of fits, each of which would otherwise build the
// query's tree again, most of a fit's time); null builds one.
bool FitTemplate(const MuscleTemplate& tmpl, const MeshData& head, const Landmarks& landmarks,
                 const std::string& units, RigSpec* out, Diagnostics* diag,
                 FitReport* report = nullptr, const SurfaceQuery* head_query = nullptr);

// The farthest, in units of s, that a point whose ray misses the mesh may lie from the nearest
// surface point the fit uses instead; farther, the fit refuses the point ("found no surface").
constexpr float kMaxOffMeshDistance = 0.5f;

// The largest distance, in units of s (`report.frame.scale`), from a point whose ray missed
// the mesh to the nearest surface point the fit used instead (0 when every ray hit); the fit
// refuses above kMaxOffMeshDistance. Its name, or "" when every ray hit. `mimetic calibrate` keeps a margin
// under 0.5 so that a head a little different (a coarser sample head) still fits.
float LargestMiss(const FitReport& report, std::string* where = nullptr);

// Guesses the mesh unit from the eye-corner distance s (about 9 cm on adults): the unit in
// which s is closest to 90 mm. Returns "" when s is not a positive finite number.
std::string GuessUnits(float eye_corner_distance);

// Writes a grayscale thickness map (docs/model.md §4, Bando 2003 §6) in texture space: each
// triangle is rasterised in UV space with its per-vertex thickness (v = 0 on the top row, as
// in glTF), the image is blurred with a small Gaussian (sigma in pixels) and holes are filled
// from their neighbours; black = 0, white = `max_value` (the largest value, rounded up).
// Errors: mesh without UVs, values.size() != #V, bad size.
bool RasterizeThicknessMap(const MeshData& mesh, const std::vector<float>& values, int size,
                           float blur_sigma_px, std::vector<uint8_t>* gray, float* max_value,
                           Diagnostics* diag);

// Landmark transfer for heads without landmarks (docs/landmarks-format.md): three midline
// features found geometrically on both meshes (nose tip = most forward midline point;
// nasion = deepest midline point above it; pogonion = most forward midline point below the
// mouth) give a similarity transform from `source` to `target`; each source landmark is moved
// by it and projected onto `target` along the source surface normal, then snapped to the
// nearest target vertex. Both heads must face +Z with +Y up and be roughly symmetric in x.
bool TransferLandmarks(const MeshData& source, const std::vector<float3>& source_landmarks,
                       const MeshData& target, std::vector<uint32_t>* target_vertices,
                       Diagnostics* diag);

}  // namespace mimetic
