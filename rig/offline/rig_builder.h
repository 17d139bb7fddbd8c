// rig/offline/rig_builder.h: RigSpec + mesh -> runtime Rig (the offline "builder").
#pragma once

#include <functional>
#include <string>

#include "core/diagnostics.h"
#include "core/span.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_spec.h"
#include "rig/runtime/rig.h"

namespace mimetic {

// Refinement where wrinkles act (docs/model.md §11) may grow the mesh to at most
// kMaxRefinementGrowth times its triangles, or kMinRefinementLimit triangles where that is more
// (a coarse mesh under a narrow wrinkle legitimately grows 30x and stays cheap), and never past
// RefineOptions::max_triangles (4 million): BuildRig estimates the refined size before refining
// (geometry/refine_estimate.h) and refuses a rig that would exceed it, naming the key that asks
// for the smallest edges.
inline constexpr double kMaxRefinementGrowth = 16.0;
inline constexpr double kMinRefinementLimit = 1'000'000.0;

// Magnitudes BuildRig accepts (issue 11: a thickness of 3e38 validated and evaluated to
// inf): mesh coordinates at most kMaxCoordinateMm millimetres (in the rig's units) from 0;
// lengths in the rig (thickness, strengths, fall-off radii, sheet sizes, wrinkle depths and
// widths) at most kMaxLengthFactor times the mesh's bounding-box diagonal; muscle points at
// most that far from the bounding box's centre. Errors name the key (`muscles[2].strength`).
inline constexpr double kMaxCoordinateMm = 1e6;
inline constexpr double kMaxLengthFactor = 10.0;

struct BuildOptions {
  float weld_tolerance = 0.f;  // mesh units; <= 0: 1e-6 of the bounding-box diagonal
  // The magnitude checks above (kMaxCoordinateMm, kMaxLengthFactor). Only tests of the
  // evaluation's own guard (CheckPosedFinite) turn them off.
  bool check_magnitudes = true;
  // Called from the building thread as each stage starts, with the share of the build done
  // before it (0 before the checks, 1 when the rig is built) and the stage's name ("refining",
  // "welding", "muscles", "ordering", "muscles (ordered)", "fine scale", "tables"). The shares
  // are the sample head's measured stage times (rig/offline/rig_builder.cpp), so a bar moves
  // about evenly on any head. Empty: no calls. It must not throw.
  std::function<void(float done, const char* stage)> progress;
  // False: the fine_scale block's per-point probes (docs/model.md §23) are not compiled, so
  // the rig has no fine-scale amplitudes (RigFineScale empty) and the build skips the direction
  // fields' sparse solve. For a caller that only needs the rig's mesh and spec, such as
  // `mimetic texture` (which solves the fields itself for the maps).
  bool fine_scale_probes = true;
};

// Welds and validates the mesh (weld.h), resolves the skin thickness per point (constant;
// per file vertex, averaged over a point's vertices; or sampled bilinearly from a grayscale
// image at the vertices' UVs, black = min, white = max, v = 0 on the image's top row as in
// glTF), and compiles the muscle influence tables. Before that: the mesh must match the rig's
// fingerprint where the rig has per-vertex or texture-space data (geometry/fingerprint.h), its
// winding is made consistent (geometry/orientation.h, a warning), and refinement that would
// grow the mesh past kMaxRefinementGrowth is an error. Returns false with every problem
// recorded.
bool BuildRig(const RigSpec& spec, const MeshData& mesh, const BuildOptions& options, Rig* out,
              Diagnostics* diag);

// The fine-scale geometry of a rig (docs/model.md §20): its welded points with the triangles
// of the file's index buffer (RigData::vertex_indices through vertex_points), their corner
// uvs (empty when the mesh has none) and each field's anchors as points (file vertex ->
// point). `view()` is what wrinkles/offline/fine_scale.h reads. Anchors are checked against
// `file_vertex_count` (errors under "fine_scale").
struct FineScaleRigMesh {
  span<const float3> points;
  std::vector<uint32_t> triangles;
  std::vector<float2> corner_uvs;
  std::vector<uint32_t> anchor_points[2];
  FineScaleMesh view() const { return {points, triangles, corner_uvs}; }
};
bool MakeFineScaleRigMesh(const FineScaleSpec& spec, const RigData& rig,
                          size_t file_vertex_count, FineScaleRigMesh* out, Diagnostics* diag);

// The rig's rest mesh in its output layout (refined where wrinkles act): positions, uvs and
// triangles per output vertex. Tools use it to write posed meshes and measure displacements.
MeshData RestMesh(const Rig& rig);

// The rig posed: RestMesh's layout with the positions and unit normals EvaluateJob gives for
// `activations` (one per muscle; fewer is an error) and the skin layers `layers`. An offline
// convenience (it sizes a context per call): per-frame code runs EvaluateJob itself. Returns
// false (and leaves `out` alone) when the job does not validate.
// `jaw` is the jaw opening (EvaluateJob::jaw; ignored by a rig without a jaw).
bool PosedMesh(const Rig& rig, span<const float> activations, const SkinLayers& layers,
               MeshData* out, float jaw = 0.f);

// Offline check of what an evaluation gave (PosedMesh's `posed`, `activations` and `layers`
// as passed to it): true when every position and normal is finite. Otherwise records one error
// naming the rig key that makes them non-finite, found by evaluating again with less (the
// per-frame code stays as it is: exception- and allocation-free): the muscles alone, then each
// active muscle alone (`muscles[i]`); with the thickness layer (`thickness`); with the muscle
// wrinkles, each active muscle's alone (`muscles[i].wrinkles`); with the curve wrinkles, the
// curve wrinkles that reach the first bad point (`curve_wrinkles[j]`). `spec` is the rig's
// spec (for its key names; muscle i of the rig is muscles[i] of the file).
bool CheckPosedFinite(const Rig& rig, const RigSpec& spec, span<const float> activations,
                      const SkinLayers& layers, const MeshData& posed, Diagnostics* diag);

// docs/model.md §18, the mouth's free edge: every point's distance (mesh units) from the edge
// of the slit between the lips, that is from the boundary loop of (points, triangles) nearest
// jaw.mouth, when that loop passes within a quarter of jaw.mouth_width of it. Empty when no
// loop does (a closed lip line) or the mesh has no boundary. O(#P * loop edges), but for a
// finite `beyond`: a point whose distance from the loop's bounding box is `beyond` or more (so
// is its distance from the loop) gets infinity without measuring, for a caller that needs the
// distances below `beyond` alone (the thickness fade: 1 from its width on).
std::vector<float> MouthEdgeDistances(const JawSpec& jaw, span<const float3> points,
                                      span<const uint32_t> triangles,
                                      float beyond = std::numeric_limits<float>::infinity());

}  // namespace mimetic
