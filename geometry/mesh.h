// geometry/mesh.h: a triangle mesh as read from a file, in the file's own vertex layout.
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

}  // namespace mimetic
