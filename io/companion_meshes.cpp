#include "io/companion_meshes.h"

namespace mimetic {

bool LoadCompanionMeshes(const LoadedRig& loaded, CompanionMeshes* out, Diagnostics* diag) {
  *out = CompanionMeshes{};
  if (loaded.compiled || loaded.spec.mesh_path.empty()) return true;
  Diagnostics local;
  const bool ok = ImportOtherMeshes(loaded.spec.mesh_path, loaded.spec.mesh_name, &out->others,
                                    &local, &out->skin_name);
  diag->Append(local, loaded.spec.mesh_path);
  return ok;
}

bool WritePosedWithCompanions(const std::string& path, const MeshData& posed,
                              const CompanionMeshes& companions, Diagnostics* diag,
                              double metres_per_unit) {
  if (companions.others.empty()) return ExportMesh(path, posed, diag, metres_per_unit);
  std::vector<NamedMesh> meshes{{companions.skin_name.empty() ? "mesh" : companions.skin_name, &posed}};
  for (const NamedMeshData& m : companions.others) meshes.push_back({m.name, &m.mesh});
  return ExportMeshes(path, meshes, diag, metres_per_unit);
}

MeshData MergeForDrawing(const MeshData& skin, const CompanionMeshes& companions) {
  MeshData out = skin;
  bool normals = skin.normals.size() == skin.positions.size();
  bool uvs = skin.uvs.size() == skin.positions.size();
  for (const NamedMeshData& m : companions.others) {
    normals = normals && m.mesh.normals.size() == m.mesh.positions.size();
    uvs = uvs && m.mesh.uvs.size() == m.mesh.positions.size();
  }
  for (const NamedMeshData& m : companions.others) {
    const uint32_t base = static_cast<uint32_t>(out.positions.size());
    out.positions.insert(out.positions.end(), m.mesh.positions.begin(), m.mesh.positions.end());
    if (normals) out.normals.insert(out.normals.end(), m.mesh.normals.begin(), m.mesh.normals.end());
    if (uvs) out.uvs.insert(out.uvs.end(), m.mesh.uvs.begin(), m.mesh.uvs.end());
    for (uint32_t i : m.mesh.indices) out.indices.push_back(base + i);
  }
  if (!normals) out.normals.clear();
  if (!uvs) out.uvs.clear();
  return out;
}

}  // namespace mimetic
