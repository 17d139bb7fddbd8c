// io/gltf_bake.h: a played clip baked into one glTF 2.0 binary (.glb) that standard viewers
// play: the base mesh plus one morph target per frame, and a `weights` animation that shows
// frame k at its time (docs/expressions.md "Bake").
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"

namespace mimetic {

// What to bake. Sizes: #V = base.vertex_count(), #F = times.size().
struct BakedFrames {
  // The base mesh in mesh units: positions, normals (optional: empty = no NORMAL and no normal
  // deltas), uvs (optional), triangles. mimetic play passes the rig evaluated at zero
  // activations (the neutral) in the rig's output layout.
  MeshData base;
  std::vector<double> times;      // #F seconds, strictly increasing, >= 0 (frame k at times[k])
  std::vector<float> positions;   // #F * #V * 3: frame k, vertex v at [(k * #V + v) * 3]
  std::vector<float> normals;     // #F * #V * 3, or empty (no normal deltas)
  // Tension for engine shaders (docs/tension.md "Bake"), optional: per frame and vertex the
  // pair (r - 1, eps) (area ratio minus one, compression), #F * #V * 2, with base_tension
  // (#V * 2) the neutral's pair. When given, the primitive gets a `_TENSION` VEC2 attribute
  // (the base's pairs) and every morph target its `_TENSION` deltas, so the morphed attribute
  // is frame k's pair at frame k's time. Both empty = no tension.
  std::vector<float> tension;
  std::vector<float> base_tension;
  double metres_per_unit = 0.001; // the root node's uniform scale (none when 1), as ExportMesh
  // A vertex whose delta from the base is at most this in every coordinate is stored as not
  // moved (delta 0), so that the skin layers' sub-micrometre changes far from the acting
  // muscles do not defeat the sparse rule. Mesh units (positions), unitless (normals); 0 keeps
  // every non-zero delta (exact).
  float position_epsilon = 0.f;
  float normal_epsilon = 0.f;
  float tension_epsilon = 0.f;    // unitless, as normal_epsilon, for the _TENSION deltas
  // Named targets (blendshape export): empty, or one name per frame. When given, every frame
  // is its own morph target in frame order (no sharing of identical frames, and a frame equal
  // to the base still gets an all-zero target), and the names go to the mesh's
  // `extras.targetNames`, where three.js, Babylon and Blender read morph-target names.
  std::vector<std::string> target_names;
};

struct BakeStats {
  size_t frames = 0;
  size_t targets = 0;              // morph targets: the distinct frames that are not the base
  size_t sparse_targets = 0;       // morph targets whose POSITION deltas are sparse
  size_t moved_vertices = 0;       // vertices whose position differs from the base in any frame
  size_t max_moved_in_frame = 0;   // the most vertices moved in one frame
  size_t bytes = 0;                // size of the .glb
};

// The .glb bytes. Layout (docs/expressions.md "Bake"): one scene, one node ("mimetic_units",
// scaling mesh units to metres, as ExportMesh) holding mesh 0 ("baked") with one primitive:
// POSITION (with min/max), NORMAL, TEXCOORD_0, _TENSION (when given), u32 indices, and one
// morph target per distinct frame (frame minus the base: POSITION deltas with min/max, NORMAL
// and _TENSION deltas; a frame
// bit-identical to an earlier one, a held pose, shares its target; a frame whose deltas are all
// within the epsilons is the base and has none; a clip of base frames only gets one all-zero
// target so the animation stays well formed). A target's deltas are a
// sparse accessor (u16 or u32 indices of the vertices whose delta is above the epsilon, their
// deltas; no bufferView, so the rest are zero) when that is fewer bytes than the dense array;
// a target with no moved vertex is an accessor with neither bufferView nor sparse (all zeros).
// One animation ("clip"), one LINEAR sampler over input times[k]: output row k is 1 at frame
// k's target and 0 elsewhere (all 0 for a base frame), so frame k is shown exactly at its time
// and neighbouring frames blend
// linearly between (vertex positions move linearly from frame k to frame k+1). Refuses (false,
// a message) empty frames, mismatched sizes, non-increasing or non-finite times, non-finite
// values, out-of-range indices.
bool BakeGlbBytes(const BakedFrames& frames, std::string* out, BakeStats* stats,
                  Diagnostics* diag);

// The epsilons mimetic writes with, from frames.base: moves below a millionth of the base's
// bounding-box diagonal (0.25 um on the sample head), normal changes below 1e-4 and tension
// changes below 1e-5 are not stored; far from the acting muscles the skin layers change vertices by float noise, which
// would otherwise make nearly every target dense.
void SetDefaultEpsilons(BakedFrames* frames);

// The tension regions' weights of a bake (docs/tension.md "Bake"), beside the .glb: a JSON
// object {"format": "mimetic-tension-regions", "version": 1, "times": [#F seconds],
// "regions": [{"name": N, "weights": [#F values]}, ...]}, regions in `names` order, with
// `weights` frame-major (#F * names.size(): frame k, region i at [k * #R + i]).
std::string TensionRegionsToJson(const std::vector<std::string>& names,
                                 const std::vector<double>& times,
                                 const std::vector<float>& weights);

// BakeGlbBytes written to `path` atomically (temporary file + rename; WriteFileAtomic).
bool WriteBakedGlb(const std::string& path, const BakedFrames& frames, BakeStats* stats,
                   Diagnostics* diag);

}  // namespace mimetic
