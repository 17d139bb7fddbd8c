// io/rig_loader.h: a rig file, its mesh and its images, built into a runtime Rig.
#pragma once

#include <cstdint>
#include <string>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_builder.h"
#include "rig/offline/rig_spec.h"
#include "rig/runtime/rig.h"

namespace mimetic {

// Everything a tool needs about one rig file.
struct LoadedRig {
  RigSpec spec;  // a compiled rig: only `units` (the rest is not kept in a .mrig)
  MeshData mesh;  // a compiled rig: empty
  Rig rig;
  bool compiled = false;             // loaded from a .mrig (docs/mrig-format.md)
  uint32_t source_vertex_count = 0;  // the source mesh file's vertices (0: not known)
};

// True when `path` names a compiled rig: it ends in .mrig (any case) or starts with "MRIG".
bool IsCompiledRigPath(const std::string& path);

// LoadRigSpec + ImportMesh + the thickness image (LoadGrayImage) + BuildRig; or, for a
// compiled rig (IsCompiledRigPath), ReadRigBinary alone. Diagnostics are prefixed with the file
// they concern.
bool LoadRig(const std::string& rig_path, LoadedRig* out, Diagnostics* diag,
             const BuildOptions& options = {});

}  // namespace mimetic
