// io/companion_meshes.h: the meshes that travel with a rig's skin in its mesh file (the
// sample head's eyeballs): read once, written unchanged beside every posed skin.
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"

namespace mimetic {

struct CompanionMeshes {
  std::string skin_name;              // the rig's mesh as the file names it ("" when unnamed)
  std::vector<NamedMeshData> others;  // the file's other meshes (ImportOtherMeshes)
};

// The rig's mesh file's other meshes; none for a compiled rig (a .mrig keeps no mesh file) or
// an OBJ. False (with the file's diagnostics) when the mesh file cannot be read.
bool LoadCompanionMeshes(const LoadedRig& loaded, CompanionMeshes* out, Diagnostics* diag);

// Writes the posed skin: alone (ExportMesh, one mesh named "mesh", as always) when there are
// no companions; else first (named as in the source, "mesh" when unnamed) followed by the
// companions, unchanged (ExportMeshes: a .glb's further meshes, an .obj's further objects).
bool WritePosedWithCompanions(const std::string& path, const MeshData& posed,
                              const CompanionMeshes& companions, Diagnostics* diag,
                              double metres_per_unit);

// The skin and the companions as one mesh to draw (vertices and triangles appended in order;
// normals and uvs kept only when every part has them).
MeshData MergeForDrawing(const MeshData& skin, const CompanionMeshes& companions);

}  // namespace mimetic
