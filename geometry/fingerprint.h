// geometry/fingerprint.h: what ties per-vertex and texture-space data to one mesh (issue 11:
// per-vertex thickness was bound to its mesh by the vertex count only, so the same head
// re-exported with another vertex order or flipped v validated and put the values on the wrong
// vertices).
//
// A fingerprint holds the vertex and triangle counts, a 64-bit FNV-1a hash of the index buffer
// (exact: integers survive any re-export that keeps the layout), and the positions and texture
// coordinates of up to kFingerprintSamples vertices spread over the vertex range (vertex
// floor(k (#V - 1) / (n - 1)), k = 0..n-1), compared with a tolerance, because a re-export may
// round coordinates (a hash of quantised floats would flip on the least rounding across a
// quantisation step). Another vertex order changes the index hash and the samples; a flipped v
// changes the uv samples; an edited shape with the same layout keeps the data on the right
// vertices and passes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "geometry/mesh.h"

namespace mimetic {

inline constexpr size_t kFingerprintSamples = 16;
// Position samples match within this fraction of the mesh's bounding-box diagonal; uv
// samples within this many texture units.
inline constexpr double kFingerprintPositionTolerance = 1e-4;
inline constexpr double kFingerprintUvTolerance = 1e-4;

struct MeshFingerprint {
  uint64_t vertices = 0;
  uint64_t triangles = 0;
  uint64_t index_hash = 0;        // FNV-1a 64 of the indices as little-endian uint32
  std::vector<float3> positions;  // the sampled vertices' positions
  std::vector<float2> uvs;        // their texture coordinates; empty when the mesh has none

  bool empty() const { return vertices == 0 && positions.empty(); }
};

// The sampled vertex indices for a mesh of `vertex_count` vertices and `samples` samples.
std::vector<uint64_t> FingerprintSampleVertices(uint64_t vertex_count, size_t samples);

MeshFingerprint ComputeMeshFingerprint(const MeshData& mesh);

// "" when `mesh` matches `stored` (positions always; uvs when `need_uvs`), else what differs,
// e.g. "its triangles use other vertices (index hash 0x... where the rig has 0x...)" or
// "vertex 1234 is at (1, 2, 3) where the rig has (4, 5, 6)" or "vertex 17 has texture
// coordinates (0.2, 0.7) where the rig has (0.2, 0.3) (v flipped?)".
std::string FingerprintMismatch(const MeshFingerprint& stored, const MeshData& mesh,
                                bool need_uvs);

// The hash as the rig file writes it: 16 lowercase hex digits; and back (false when `text`
// is not 16 hex digits).
std::string FingerprintHashText(uint64_t hash);
bool ParseFingerprintHash(const std::string& text, uint64_t* out);

}  // namespace mimetic
