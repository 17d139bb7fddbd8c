// BuildRig's checks of the mesh against the rig (issue 11): inconsistent triangle winding is
// turned round with a warning.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "content/procedural.h"
#include "rig/offline/rig_builder.h"

namespace mimetic {
namespace {

constexpr uint32_t kSide = 21;  // vertices per side; 800 triangles

MeshData Surface() {
  MeshData m = MakeSurfaceMesh(kSide, kSide, 100.f, 100.f, 10.f);
  m.source = "surface.obj";
  return m;
}

RigSpec Spec() { return MakeSurfaceRigSpec(4, 100.f, 100.f, 10.f, 0.3f, 3.f); }

TEST(BuildRigWinding, EveryOtherTriangleFlippedIsTurnedBackWithAWarning) {
  const MeshData good = Surface();
  MeshData bad = good;
  const size_t tris = bad.triangle_count();
  ASSERT_EQ(tris, 800u);
  for (size_t t = 1; t < tris; t += 2) std::swap(bad.indices[3 * t + 1], bad.indices[3 * t + 2]);
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(Spec(), bad, {}, &rig, &diag)) << diag.Format();
  EXPECT_FALSE(diag.HasErrors());
  ASSERT_TRUE(diag.Contains("400 of 800 triangles (50.0%) were wound against their neighbours "
                            "(first: triangle 1)"))
      << diag.Format();
  EXPECT_EQ(diag.items()[0].severity, Severity::kWarning);
  EXPECT_EQ(diag.items()[0].where, "surface.obj");
  // A tie keeps triangle 0's winding: the output's triangles are the unflipped surface's, and
  // every posed normal faces +z as the surface does (MakeSurfaceMesh: triangles face +Z).
  EXPECT_EQ(RestMesh(rig).indices, good.indices);
  MeshData posed;
  const std::vector<float> activations(rig.muscle_count(), 0.7f);
  ASSERT_TRUE(PosedMesh(rig, activations, {}, &posed));
  size_t backwards = 0;
  for (const float3& n : posed.normals) backwards += n.z <= 0.f;
  EXPECT_EQ(backwards, 0u);
  // The consistent surface builds with nothing to say about winding.
  Diagnostics quiet;
  ASSERT_TRUE(BuildRig(Spec(), good, {}, &rig, &quiet));
  EXPECT_FALSE(quiet.Contains("wound")) << quiet.Format();
}

}  // namespace
}  // namespace mimetic
