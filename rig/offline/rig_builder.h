// rig/offline/rig_builder.h: RigSpec + mesh -> runtime Rig (the offline "builder").
#pragma once

#include <string>

#include "core/diagnostics.h"
#include "core/span.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_spec.h"
#include "rig/runtime/rig.h"

namespace mimetic {

struct BuildOptions {
  float weld_tolerance = 0.f;  // mesh units; <= 0: 1e-6 of the bounding-box diagonal
};

// Welds and validates the mesh (weld.h), resolves the skin thickness per point (constant;
// per file vertex, averaged over a point's vertices; or sampled bilinearly from a grayscale
// image at the vertices' UVs, black = min, white = max, v = 0 on the image's top row as in
// glTF), and compiles the muscle influence tables. Returns false with every problem recorded.
bool BuildRig(const RigSpec& spec, const MeshData& mesh, const BuildOptions& options, Rig* out,
              Diagnostics* diag);

// The rig's rest mesh in its output layout (refined where wrinkles act): positions, uvs and
// triangles per output vertex. Tools use it to write posed meshes and measure displacements.
MeshData RestMesh(const Rig& rig);

// The rig posed: RestMesh's layout with the positions and unit normals EvaluateJob gives for
// `activations` (one per muscle; fewer is an error) and the skin layers `layers`. An offline
// convenience (it sizes a context per call): per-frame code runs EvaluateJob itself. Returns
// false (and leaves `out` alone) when the job does not validate.
bool PosedMesh(const Rig& rig, span<const float> activations, const SkinLayers& layers,
               MeshData* out);

}  // namespace mimetic
