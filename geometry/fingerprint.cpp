#include "geometry/fingerprint.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "geometry/bounds.h"

namespace mimetic {
namespace {

std::string Vec3(float3 v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", double(v.x), double(v.y), double(v.z));
  return buf;
}
std::string Vec2(float2 v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g)", double(v.x), double(v.y));
  return buf;
}

}  // namespace

std::vector<uint64_t> FingerprintSampleVertices(uint64_t vertex_count, size_t samples) {
  std::vector<uint64_t> out;
  if (vertex_count == 0 || samples == 0) return out;
  if (samples == 1) return {0};
  for (size_t k = 0; k < samples; ++k)
    out.push_back(uint64_t(k) * (vertex_count - 1) / uint64_t(samples - 1));
  return out;
}

MeshFingerprint ComputeMeshFingerprint(const MeshData& mesh) {
  MeshFingerprint f;
  f.vertices = mesh.vertex_count();
  f.triangles = mesh.triangle_count();
  uint64_t h = 14695981039346656037ull;
  for (uint32_t i : mesh.indices)
    for (int b = 0; b < 4; ++b) {
      h ^= (i >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  f.index_hash = h;
  const size_t n = std::min<size_t>(kFingerprintSamples, mesh.vertex_count());
  const bool uvs = mesh.uvs.size() == mesh.vertex_count();
  for (uint64_t v : FingerprintSampleVertices(mesh.vertex_count(), n)) {
    f.positions.push_back(mesh.positions[v]);
    if (uvs) f.uvs.push_back(mesh.uvs[v]);
  }
  return f;
}

std::string FingerprintMismatch(const MeshFingerprint& stored, const MeshData& mesh,
                                bool need_uvs) {
  if (stored.vertices != mesh.vertex_count())
    return "it has " + std::to_string(mesh.vertex_count()) + " vertices where the rig's mesh had " +
           std::to_string(stored.vertices);
  if (stored.triangles != mesh.triangle_count())
    return "it has " + std::to_string(mesh.triangle_count()) +
           " triangles where the rig's mesh had " + std::to_string(stored.triangles);
  const MeshFingerprint now = ComputeMeshFingerprint(mesh);
  if (now.index_hash != stored.index_hash)
    return "its triangles use other vertices (index hash " + FingerprintHashText(now.index_hash) +
           " where the rig has " + FingerprintHashText(stored.index_hash) +
           "): another vertex order";
  const std::vector<uint64_t> at = FingerprintSampleVertices(stored.vertices, stored.positions.size());
  const BoundingBox box = ComputeBounds(mesh.positions);
  const double tol = kFingerprintPositionTolerance * double(Length(box.Hi() - box.Lo()));
  for (size_t k = 0; k < at.size(); ++k) {
    const float3 p = mesh.positions[at[k]], q = stored.positions[k];
    if (!(double(Length(p - q)) <= tol))
      return "vertex " + std::to_string(at[k]) + " is at " + Vec3(p) + " where the rig has " +
             Vec3(q) + ": another vertex order or another shape";
  }
  if (!need_uvs) return "";
  if (mesh.uvs.size() != mesh.vertex_count()) return "it has no texture coordinates";
  if (stored.uvs.size() != stored.positions.size()) return "";  // the rig recorded none
  for (size_t k = 0; k < at.size(); ++k) {
    const float2 u = mesh.uvs[at[k]], w = stored.uvs[k];
    if (std::fabs(double(u.x) - w.x) <= kFingerprintUvTolerance &&
        std::fabs(double(u.y) - w.y) <= kFingerprintUvTolerance)
      continue;
    const bool flipped = std::fabs(double(u.x) - w.x) <= kFingerprintUvTolerance &&
                         std::fabs(double(u.y) - (1.0 - w.y)) <= kFingerprintUvTolerance;
    return "vertex " + std::to_string(at[k]) + " has texture coordinates " + Vec2(u) +
           " where the rig has " + Vec2(w) + (flipped ? " (v flipped: v -> 1 - v)" : "");
  }
  return "";
}

std::string FingerprintHashText(uint64_t hash) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash));
  return buf;
}

bool ParseFingerprintHash(const std::string& text, uint64_t* out) {
  if (text.size() != 16) return false;
  uint64_t v = 0;
  for (char c : text) {
    int d;
    if (c >= '0' && c <= '9') d = c - '0';
    else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
    else return false;
    v = (v << 4) | uint64_t(d);
  }
  *out = v;
  return true;
}

}  // namespace mimetic
