// io/rig_loader.h: a rig file, its mesh and its images, built into a runtime Rig.
#pragma once

#include <string>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_builder.h"
#include "rig/offline/rig_spec.h"
#include "rig/runtime/rig.h"

namespace mimetic {

// Everything a tool needs about one rig file.
struct LoadedRig {
  RigSpec spec;
  MeshData mesh;
  Rig rig;
};
// LoadRigSpec + ImportMesh + the thickness image (LoadGrayImage) + BuildRig. Diagnostics are prefixed with the file they concern.
bool LoadRig(const std::string& rig_path, LoadedRig* out, Diagnostics* diag,
             const BuildOptions& options = {});

}  // namespace mimetic
