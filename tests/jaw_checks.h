// tests/jaw_checks.h: what the jaw tests measure on any head (ICT-FaceKit in
// tests/fitting/jaw_test.cpp, the sample head in tests/fitting/jaw_sample_head_test.cpp): the posed mesh at a jaw opening,
// the triangles that turn over against the rest pose, the smallest distance between two sets
// of vertices (the lips).
#pragma once

#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "core/math.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/rig.h"

namespace mimetic::test {

// The rig posed with every muscle at 0, every skin layer and the fold limiter on, the jaw at
// `jaw`: RestMesh's layout (the mesh file's vertices first).
inline std::vector<float3> PosedAtJaw(const Rig& rig, float jaw) {
  MeshData m;
  const std::vector<float> zero(rig.muscle_count(), 0.f);
  EXPECT_TRUE(PosedMesh(rig, zero, SkinLayers{}, &m, jaw));
  return m.positions;
}

// Triangles whose posed normal turned over against the rest one (the criterion of
// tests/fitting/foldover_test.cpp: dot <= 0, or a collapsed triangle, is a flip; triangles with
// no rest area are skipped). `first` is the first one found (0 when none).
struct TurnedOver {
  size_t count = 0;
  size_t first = 0;
};
inline TurnedOver CountTurnedOver(const MeshData& rest, const std::vector<float3>& posed) {
  TurnedOver out;
  for (size_t t = 0; t < rest.triangle_count(); ++t) {
    const uint32_t* i = &rest.indices[3 * t];
    const float3 n0 = Cross(rest.positions[i[1]] - rest.positions[i[0]],
                            rest.positions[i[2]] - rest.positions[i[0]]);
    const float3 n1 = Cross(posed[i[1]] - posed[i[0]], posed[i[2]] - posed[i[0]]);
    if (!(Length(n0) > 0.f)) continue;
    if (!(Dot(n0, n1) > 0.f) && out.count++ == 0) out.first = t;
  }
  return out;
}

// The smallest distance between a vertex of `a` and one of `b` at positions `x`.
inline float SmallestDistance(const std::vector<float3>& x, const std::vector<uint32_t>& a,
                              const std::vector<uint32_t>& b) {
  float best = 1e30f;
  for (uint32_t i : a)
    for (uint32_t j : b) best = std::min(best, Length(x[i] - x[j]));
  return best;
}

}  // namespace mimetic::test
