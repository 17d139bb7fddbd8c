// rig/offline/mesh.h: a triangle mesh as read from a file, in the file's own vertex layout.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"

namespace mimetic {

// Vertices as the file lays them out: a vertex split at a UV or normal seam appears several
// times with the same position. Welding (weld.h) maps them to one surface point.
struct MeshData {
  std::vector<float3> positions;  // #V
  std::vector<float3> normals;    // empty, or #V
  std::vector<float2> uvs;        // empty, or #V (TEXCOORD_0; v as stored in the file)
  std::vector<uint32_t> indices;  // 3 per triangle, into positions
  std::string source;             // file the mesh came from, for messages

  size_t vertex_count() const { return positions.size(); }
  size_t triangle_count() const { return indices.size() / 3; }
};

// Reads .gltf / .glb (tinygltf: POSITION, NORMAL, TEXCOORD_0, indices; the mesh named
// `mesh_name`, or the first when empty; every triangle primitive of it) or .obj (OpenMesh;
// polygons are fan-triangulated). Returns false and records why in `diag` on any problem:
// unreadable file, unknown extension, missing mesh, non-finite values, out-of-range indices,
// empty mesh. Never throws.
bool ImportMesh(const std::string& path, const std::string& mesh_name, MeshData* out,
                Diagnostics* diag);

// Writes positions, normals (when present), uvs (when present) and triangles.
// `.obj` or `.glb` by extension. The file is written to a temporary name and renamed.
bool ExportMesh(const std::string& path, const MeshData& mesh, Diagnostics* diag);

}  // namespace mimetic
