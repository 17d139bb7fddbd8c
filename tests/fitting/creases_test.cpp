// tests/fitting/creases_test.cpp: MeasureCreases (fitting/creases.h) on the test surface.
#include <gtest/gtest.h>

#include "content/procedural.h"
#include "fitting/creases.h"

#include <cmath>
#include <vector>
#include "rig/offline/rig_builder.h"

namespace mimetic {
namespace {

Rig Build(const MeshData& mesh, const RigSpec& spec) {
  Rig rig;
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  return rig;
}

RigSpec OneLinearMuscle(float3 attachment, float3 insertion, MuscleFalloff falloff) {
  RigSpec spec;
  spec.units = "mm";
  spec.layers = {.thickness = false, .muscle_wrinkles = false, .curve_wrinkles = false};
  spec.refinement.enabled = false;
  MuscleSpec m;
  m.name = "pull";
  m.type = MuscleType::kLinear;
  m.strength = 4.f;
  m.falloff = falloff;
  m.linear = {.attachment = attachment, .insertion = insertion, .zone_angle = 0.6f,
              .falloff_start = 15.f, .falloff_end = 30.f};
  spec.muscles = {m};
  spec.muscle_wrinkles.resize(1);
  return spec;
}

TEST(Creases, AFlatSheetPulledWithinItsPlaneStaysFlat) {
  // Attachment and insertion in the plane z = 0: every displacement lies in the plane, so no
  // dihedral angle changes, with either fall-off.
  const MeshData flat = MakeSurfaceMesh(41, 41, 100.f, 100.f, 0.f);
  for (MuscleFalloff f : {MuscleFalloff::kWaters, MuscleFalloff::kSmooth}) {
    const Rig rig = Build(flat, OneLinearMuscle({-30.f, 0.f, 0.f}, {10.f, 0.f, 0.f}, f));
    const CreaseReport r = MeasureCreases(rig);
    ASSERT_EQ(r.muscle_degrees.size(), 1u);
    EXPECT_GT(r.band_edges[0], 0u);
    EXPECT_LT(r.max_degrees, 1e-3f);
  }
}

TEST(Creases, SmoothFalloffsFoldFarLessThanWaters) {
  // The muscle pulls the bulged sheet toward an attachment under it: the skin moves out of
  // its plane, and Waters' kink at the zone's edges shows as a crease the squared fall-off
  // does not have.
  const MeshData bulged = MakeSurfaceMesh(61, 61, 100.f, 100.f, 10.f);
  const float3 a{-25.f, 0.f, -15.f}, i{5.f, 0.f, 8.f};
  const CreaseReport waters = MeasureCreases(Build(bulged, OneLinearMuscle(a, i, MuscleFalloff::kWaters)));
  const CreaseReport smooth = MeasureCreases(Build(bulged, OneLinearMuscle(a, i, MuscleFalloff::kSmooth)));
  EXPECT_GT(waters.max_degrees, 1.f);
  EXPECT_LT(smooth.max_degrees, 0.5f * waters.max_degrees)
      << "waters " << waters.max_degrees << ", smooth " << smooth.max_degrees;
  // The band is the same zone boundary for both (the same points move).
  EXPECT_EQ(waters.band_edges[0], smooth.band_edges[0]);
}

// CreaseMeter on any field: a flat sheet whose half x > 0 is lifted into the ramp z = k x
// folds along the line x = 0 (where the ramp leaves the unmoved half) by exactly atan(k); the
// ramp's own edges and the flat half's stay at their rest angle (0), so that is the number.
TEST(Creases, ARampLiftedFromAFlatSheetFoldsByItsSlope) {
  const MeshData flat = MakeSurfaceMesh(41, 41, 100.f, 100.f, 0.f);  // x in steps of 2.5, x = 0 a column
  const CreaseMeter meter(flat.positions, flat.indices);
  for (const float k : {0.1f, 0.5f, 2.0f}) {
    std::vector<float3> lift(flat.vertex_count(), float3{0.f, 0.f, 0.f});
    size_t moved = 0;
    for (size_t v = 0; v < lift.size(); ++v)
      if (flat.positions[v].x > 1e-3f) lift[v].z = k * flat.positions[v].x, ++moved;
    ASSERT_EQ(moved, 20u * 41u);
    uint32_t band = 0;
    const double degrees = meter.Measure(lift, &band);
    EXPECT_NEAR(degrees, std::atan(double(k)) * 180.0 / 3.14159265358979323846, 1e-3) << "k " << k;
    EXPECT_GT(band, 40u);  // at least the 40 edges along x = 0
  }
  // Nothing moves: no band, no crease.
  uint32_t band = 1;
  EXPECT_EQ(meter.Measure(std::vector<float3>(flat.vertex_count(), float3{0.f, 0.f, 0.f}), &band), 0.0);
  EXPECT_EQ(band, 0u);
}

// Slivers are left out (kCreaseMinShape): a sliver ABC, 0.02 high over its 1-long edge AB,
// beside two well-shaped triangles ADB and BDE. Lifting C by 0.02 turns the sliver by
// atan(0.02 / 0.02) = 45 degrees about AB: measured with every edge (min_shape 0), not by the
// default meter, which measures only DB there (unmoved: 0). Lifting E by 1/sqrt(2), its
// distance from the line DB, folds BDE about DB by atan(1) = 45 degrees: a well-shaped
// triangle's fold is measured either way.
TEST(Creases, ASliverIsLeftOutAndAFoldBesideItIsNot) {
  const std::vector<float3> rest = {{0.f, 0.f, 0.f},    {1.f, 0.f, 0.f},  {0.5f, 0.02f, 0.f},
                                    {0.5f, -0.5f, 0.f}, {1.5f, -0.5f, 0.f}};
  const std::vector<uint32_t> tris = {0, 1, 2, 0, 3, 1, 1, 3, 4};
  const CreaseMeter every(rest, tris, 2, 0.0), meter(rest, tris);
  EXPECT_EQ(every.sliver_edges(), 0u);
  EXPECT_EQ(meter.sliver_edges(), 1u);
  std::vector<float3> lift_c(rest.size(), float3{0.f, 0.f, 0.f});
  lift_c[2].z = 0.02f;
  uint32_t band = 0;
  EXPECT_NEAR(every.Measure(lift_c, &band), 45.0, 1e-3);
  EXPECT_EQ(band, 2u);
  float3 at{};
  EXPECT_EQ(meter.Measure(lift_c, &band, &at), 0.0);
  EXPECT_EQ(band, 1u);
  std::vector<float3> lift_e(rest.size(), float3{0.f, 0.f, 0.f});
  lift_e[4].z = float(1.0 / std::sqrt(2.0));
  EXPECT_NEAR(meter.Measure(lift_e, &band, &at), 45.0, 1e-3);
  EXPECT_NEAR(every.Measure(lift_e), 45.0, 1e-3);
  // The worst edge is DB: its rest midpoint.
  EXPECT_FLOAT_EQ(at.x, 0.75f);
  EXPECT_FLOAT_EQ(at.y, -0.25f);
}

}  // namespace
}  // namespace mimetic
