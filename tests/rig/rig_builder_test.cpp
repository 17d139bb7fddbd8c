// BuildRig's checks of the mesh against the rig (issue 11): inconsistent triangle winding is
// turned round with a warning, and per-vertex or texture-space data made for another vertex
// layout (mesh.fingerprint) is refused with how to refit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "content/procedural.h"
#include "geometry/fingerprint.h"
#include "muscles/offline/waters.h"
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

// The surface's vertices in reverse order (the same head re-exported by another tool), its
// indices remapped: the same shape, every per-vertex value now on another vertex.
MeshData Reordered(const MeshData& m) {
  MeshData r = m;
  const uint32_t n = uint32_t(m.vertex_count());
  for (uint32_t v = 0; v < n; ++v) {
    r.positions[v] = m.positions[n - 1 - v];
    r.uvs[v] = m.uvs[n - 1 - v];
  }
  for (uint32_t& i : r.indices) i = n - 1 - i;
  return r;
}

RigSpec PerVertexSpec(const MeshData& mesh) {
  RigSpec spec = Spec();
  spec.thickness.kind = ThicknessSpec::Kind::kPerVertex;
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    spec.thickness.per_vertex.push_back(float(v % kSide) * 0.1f);  // varies across x
  spec.mesh_fingerprint = ComputeMeshFingerprint(mesh);
  return spec;
}

TEST(BuildRigFingerprint, PerVertexThicknessOnAReorderedMeshIsRefusedWithHowToRefit) {
  const MeshData mesh = Surface();
  const RigSpec spec = PerVertexSpec(mesh);
  Rig rig;
  Diagnostics ok;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &ok)) << ok.Format();
  Diagnostics diag;
  EXPECT_FALSE(BuildRig(spec, Reordered(mesh), {}, &rig, &diag));
  ASSERT_EQ(diag.ErrorCount(), 1u) << diag.Format();
  EXPECT_EQ(diag.items()[0].where, "mesh.fingerprint");
  const std::string& what = diag.items()[0].what;
  EXPECT_EQ(what.rfind("'surface.obj' is not the mesh this rig's per-vertex thickness (one value "
                       "per vertex) was made for: its triangles use other vertices",
                       0),
            0u)
      << what;
  EXPECT_NE(what.find("refit the rig on this mesh (mimetic fit TEMPLATE --mesh surface.obj "
                      "--landmarks LANDMARKS --out RIG"),
            std::string::npos)
      << what;
  // A rig written before fingerprints (none stored) is bound by the vertex count only, as it
  // was: it builds.
  RigSpec old = spec;
  old.mesh_fingerprint = {};
  Diagnostics quiet;
  EXPECT_TRUE(BuildRig(old, Reordered(mesh), {}, &rig, &quiet)) << quiet.Format();
}

TEST(BuildRigFingerprint, MovedVertexAndOtherCountsAreNamed) {
  const MeshData mesh = Surface();
  const RigSpec spec = PerVertexSpec(mesh);
  Rig rig;
  {
    // Same indices, vertex 0 somewhere else (the first sample).
    MeshData moved = mesh;
    moved.positions[0] = moved.positions[0] + float3{0.f, 0.f, 5.f};
    Diagnostics diag;
    EXPECT_FALSE(BuildRig(spec, moved, {}, &rig, &diag));
    EXPECT_TRUE(diag.Contains("vertex 0 is at (-50, 50, 5) where the rig has (-50, 50, 0)"))
        << diag.Format();
  }
  {
    // A vertex in the middle of the range but not sampled moves: the data stays on the right
    // vertices (a sculpted shape), nothing to say.
    MeshData sculpted = mesh;
    const std::vector<uint64_t> sampled = FingerprintSampleVertices(mesh.vertex_count(), 16);
    uint32_t v = 5;
    while (std::find(sampled.begin(), sampled.end(), v) != sampled.end()) ++v;
    sculpted.positions[v].z += 1.f;
    Diagnostics diag;
    EXPECT_TRUE(BuildRig(spec, sculpted, {}, &rig, &diag)) << diag.Format();
  }
}

TEST(BuildRigFingerprint, ImageThicknessOnFlippedVIsRefused) {
  const MeshData mesh = Surface();
  RigSpec spec = Spec();
  spec.thickness.kind = ThicknessSpec::Kind::kImage;
  spec.thickness.image.width = spec.thickness.image.height = 4;
  spec.thickness.image.pixels = std::vector<uint8_t>(16, 128);
  spec.thickness.image_path = "t.png";
  spec.thickness.min = 0.f;
  spec.thickness.max = 2.f;
  spec.mesh_fingerprint = ComputeMeshFingerprint(mesh);
  MeshData flipped = mesh;
  for (float2& uv : flipped.uvs) uv.y = 1.f - uv.y;
  Rig rig;
  Diagnostics ok;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &ok)) << ok.Format();
  Diagnostics diag;
  EXPECT_FALSE(BuildRig(spec, flipped, {}, &rig, &diag));
  ASSERT_EQ(diag.ErrorCount(), 1u) << diag.Format();
  EXPECT_TRUE(diag.Contains("is not the mesh this rig's thickness image (texture space) was "
                            "made for: vertex 0 has texture coordinates (0, 1) where the rig has "
                            "(0, 0) (v flipped: v -> 1 - v)"))
      << diag.Format();
  // Per-vertex data does not care about texture coordinates: flipped v builds.
  Diagnostics quiet;
  EXPECT_TRUE(BuildRig(PerVertexSpec(mesh), flipped, {}, &rig, &quiet)) << quiet.Format();
}

// Refinement that would grow the mesh past kMaxRefinementGrowth (16x) is an error naming the
// key, found before refining (issue 11: legal but tiny values took tens of seconds).
RigSpec CurveSpec(float width) {
  RigSpec spec = Spec();
  NamedCurveWrinkle c;
  c.name = "fold";
  c.spec.control[0] = {0.3f, 0.5f};
  c.spec.control[1] = {0.4f, 0.5f};
  c.spec.control[2] = {0.6f, 0.5f};
  c.spec.control[3] = {0.7f, 0.5f};
  c.spec.depth = 1.f;
  c.spec.width = width;
  spec.curve_wrinkles.push_back(c);
  return spec;
}

TEST(BuildRigRefinement, TinyValuesAreRefusedBeforeRefiningNamingTheKey) {
  const MeshData mesh = Surface();  // 800 triangles: the limit is 1,000,000 (16x would be 12,800)
  Rig rig;
  {
    // A sensible curve (width 3, edges 0.75 on a 5 mm grid) refines and builds.
    Diagnostics diag;
    ASSERT_TRUE(BuildRig(CurveSpec(3.f), mesh, {}, &rig, &diag)) << diag.Format();
    EXPECT_GT(rig.triangle_count(), 800u);
    EXPECT_EQ(rig.triangle_count(), 29512u);  // 37x: more than 16x, allowed on a small mesh
  }
  {
    Diagnostics diag;
    EXPECT_FALSE(BuildRig(CurveSpec(0.01f), mesh, {}, &rig, &diag));
    ASSERT_EQ(diag.ErrorCount(), 1u) << diag.Format();
    EXPECT_EQ(diag.items()[0].where, "curve_wrinkles[0].width");
    EXPECT_EQ(diag.items()[0].what.rfind("refinement where wrinkles act would grow the mesh "
                                         "from 800 to about ", 0), 0u) << diag.Format();
    EXPECT_TRUE(diag.Contains("more than the limit of 1e+06 (16x the mesh's triangles, at least "
                              "1e+06, at most 4e+06; docs/model.md §11): curve_wrinkles[0] (fold, "
                              "width 0.01) is refined to edges of 0.0025"))
        << diag.Format();
  }
  {
    RigSpec spec = CurveSpec(3.f);
    spec.refinement.edge_fraction = 1e-30f;
    Diagnostics diag;
    EXPECT_FALSE(BuildRig(spec, mesh, {}, &rig, &diag));
    ASSERT_EQ(diag.ErrorCount(), 1u) << diag.Format();
    EXPECT_EQ(diag.items()[0].where, "refinement.edge_fraction");
    EXPECT_TRUE(diag.Contains("refinement.edge_fraction 1e-30 asks for edges that short; the "
                              "default 0.25 would stay within the limit"))
        << diag.Format();
  }
  {
    RigSpec spec = Spec();
    MuscleWrinkleSpec w;
    w.count = 2147483647;
    w.depth = 1.f;
    spec.muscle_wrinkles.assign(spec.muscles.size(), std::nullopt);
    spec.muscle_wrinkles[1] = w;
    Diagnostics diag;
    EXPECT_FALSE(BuildRig(spec, mesh, {}, &rig, &diag));
    ASSERT_EQ(diag.ErrorCount(), 1u) << diag.Format();
    EXPECT_EQ(diag.items()[0].where, "muscles[1].wrinkles.count");
    EXPECT_TRUE(diag.Contains("muscles[1].wrinkles (muscle_01, count 2147483647) makes furrows"))
        << diag.Format();
    // Refinement off: the same rig builds (no refinement to bound).
    spec.refinement.enabled = false;
    Diagnostics off;
    EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &off)) << off.Format();
  }
}

// docs/model.md §11: refinement.falloff_error refines where the muscles' fall-offs bend, so that
// every edge of the built rig is at most sqrt(8 E / MuscleFalloffCurvature) long at its
// midpoint (the largest curvature over the muscles); 0 leaves the mesh as it is; the input's
// slivers are left whole.
TEST(BuildRigRefinement, FalloffErrorBoundsEveryEdgeByTheCurvature) {
  const MeshData mesh = Surface();  // 5 mm grid, no wrinkles in Spec()
  RigSpec spec = Spec();
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  EXPECT_EQ(rig.triangle_count(), 800u);
  constexpr double kError = 0.002;
  spec.refinement.falloff_error = float(kError);
  Diagnostics refined;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &refined)) << refined.Format();
  EXPECT_TRUE(refined.items().empty()) << refined.Format();  // every edge met its target
  ASSERT_GT(rig.triangle_count(), 800u);
  auto bend_at = [&](float3 p) {
    double bend = 0;
    for (const MuscleSpec& m : spec.muscles) bend = std::max(bend, MuscleFalloffCurvature(m, p));
    return bend;
  };
  const MeshData rest = RestMesh(rig);
  size_t constrained = 0;
  for (size_t t = 0; t < rest.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const float3 a = rest.positions[rest.indices[3 * t + k]];
      const float3 b = rest.positions[rest.indices[3 * t + (k + 1) % 3]];
      const double bend = bend_at(0.5f * (a + b));
      if (!(bend > 0)) continue;
      ++constrained;
      EXPECT_LE(Length(b - a), std::sqrt(8 * kError / bend) * (1 + 1e-5))
          << "triangle " << t << " edge " << k;
    }
  EXPECT_GT(constrained, 1000u);

  // A row of slivers (row 10 moved to 0.02 mm from row 11: triangles 5 mm long, 0.02 high)
  // where the curvature asks for edges shorter than 5 mm: the mesh around them is refined, the
  // slivers are not (no new point on one: within 0.05 mm, in sum of distances, of the segment
  // of its longest edge, which holds the whole sliver).
  MeshData pinched = mesh;
  for (uint32_t i = 0; i < kSide; ++i)
    pinched.positions[10 * kSide + i].y = pinched.positions[11 * kSide + i].y - 0.02f;
  struct Sliver {
    float3 a, b;  // its longest edge
  };
  std::vector<Sliver> slivers;
  size_t asked = 0;
  for (size_t t = 0; t < pinched.triangle_count(); ++t) {
    float3 q[3];
    for (int k = 0; k < 3; ++k) q[k] = pinched.positions[pinched.indices[3 * t + k]];
    int longest = 0;
    for (int k = 1; k < 3; ++k)
      if (Length(q[(k + 1) % 3] - q[k]) > Length(q[(longest + 1) % 3] - q[longest])) longest = k;
    const float3 a = q[longest], b = q[(longest + 1) % 3];
    const float l = Length(b - a);
    if (!(Length(Cross(q[1] - q[0], q[2] - q[0])) / (l * l) < 0.05f)) continue;
    slivers.push_back({a, b});
    asked += std::sqrt(8 * kError / bend_at((q[0] + q[1] + q[2]) * (1.f / 3))) < l;
  }
  ASSERT_EQ(slivers.size(), 2u * (kSide - 1));
  EXPECT_GT(asked, 0u);
  Rig pinched_rig;
  Diagnostics pd;
  ASSERT_TRUE(BuildRig(spec, pinched, {}, &pinched_rig, &pd)) << pd.Format();
  const MeshData pinched_rest = RestMesh(pinched_rig);
  EXPECT_GT(pinched_rest.positions.size(), pinched.positions.size());
  size_t on_sliver = 0;
  for (size_t v = pinched.positions.size(); v < pinched_rest.positions.size(); ++v)
    for (const Sliver& q : slivers)
      on_sliver += Length(pinched_rest.positions[v] - q.a) + Length(pinched_rest.positions[v] - q.b) <=
                   Length(q.b - q.a) + 0.05f;
  EXPECT_EQ(on_sliver, 0u);

  // Refinement by the fall-offs alone that would pass the growth limit names the key.
  spec.refinement.falloff_error = 1e-12f;
  Diagnostics tiny;
  EXPECT_FALSE(BuildRig(spec, mesh, {}, &rig, &tiny));
  ASSERT_EQ(tiny.ErrorCount(), 1u) << tiny.Format();
  EXPECT_EQ(tiny.items()[0].where, "refinement.falloff_error");
  EXPECT_EQ(tiny.items()[0].what.rfind("refinement where wrinkles act and fall-offs bend would "
                                       "grow the mesh from 800 to about ", 0), 0u)
      << tiny.Format();
  EXPECT_TRUE(tiny.Contains("refinement.falloff_error 1e-12 (where the muscles' fall-offs bend) "
                            "alone would give about "))
      << tiny.Format();
}

// Finite but absurd values are errors naming the key, against the mesh's size (the surface is
// 100 x 100 with a 10 bulge: bounding-box diagonal sqrt(100^2 + 100^2 + 10^2) = 141.8).
TEST(BuildRigMagnitudes, AbsurdValuesAreRefusedNamingTheKey) {
  const MeshData mesh = Surface();
  Rig rig;
  auto refused = [&](const RigSpec& spec, const MeshData& m, const std::string& where,
                     const std::string& what) {
    Diagnostics diag;
    EXPECT_FALSE(BuildRig(spec, m, {}, &rig, &diag)) << where;
    ASSERT_EQ(diag.ErrorCount(), 1u) << diag.Format();
    EXPECT_EQ(diag.items()[0].where, where) << diag.Format();
    EXPECT_NE(diag.items()[0].what.find(what), std::string::npos) << diag.Format();
  };
  {
    RigSpec spec = Spec();
    spec.thickness.value = 3e38f;
    refused(spec, mesh, "thickness.value",
            "is 3e+38 mm, more than 10 times the mesh's size (bounding-box diagonal 142 mm); "
            "expected a length at most 1.42e+03 mm");
  }
  {
    RigSpec spec = Spec();
    spec.muscles[2].strength = 1500.f;  // just over 10 x 141.8
    refused(spec, mesh, "muscles[2].strength", "is 1.5e+03 mm, more than 10 times");
  }
  {
    RigSpec spec = Spec();
    spec.muscles[0].linear.attachment = {1e38f, 0.f, 0.f};
    refused(spec, mesh, "muscles[0].attachment",
            "(1e+38, 0, 0) is 1e+38 mm from the mesh's centre, more than 10 times");
  }
  {
    RigSpec spec = Spec();
    MuscleWrinkleSpec w;
    w.depth = 3e38f;
    spec.muscle_wrinkles.assign(spec.muscles.size(), std::nullopt);
    spec.muscle_wrinkles[1] = w;
    refused(spec, mesh, "muscles[1].wrinkles.depth", "is 3e+38 mm");
  }
  {
    RigSpec spec = Spec();
    spec.units = "cm";  // 1e6 mm = 1e5 cm
    MeshData far = mesh;
    far.positions[7].x = 1e38f;
    refused(spec, far, "surface.obj",
            "1 vertices have a coordinate beyond 1e+05 cm (1 km; first: vertex 7 at (1e+38, ");
  }
  {
    // At the limits, fine.
    RigSpec spec = Spec();
    spec.thickness.value = 1400.f;
    Diagnostics diag;
    EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  }
}

// The offline guard on an evaluation's output, on rigs built without the magnitude checks
// whose skin layers overflow: since the fold limiter (docs/model.md §16) the overflow no longer
// reaches the output (before it, these rigs evaluated to inf and the guard named the key).
TEST(CheckPosedFinite, OverflowingSkinLayersNeverReachTheOutput) {
  const MeshData mesh = Surface();
  BuildOptions unchecked;
  unchecked.check_magnitudes = false;
  Rig rig;
  {
    RigSpec spec = Spec();
    spec.muscles[3].strength = 3e38f;
    Diagnostics diag;
    ASSERT_TRUE(BuildRig(spec, mesh, unchecked, &rig, &diag)) << diag.Format();
    std::vector<float> act(rig.muscle_count(), 0.f);
    act[1] = 0.5f;
    act[3] = 1.f;
    MeshData posed;
    ASSERT_TRUE(PosedMesh(rig, act, {}, &posed));
    // The muscles move the skin by ~1e38 (finite); the skin layers' normals and offsets of
    // such a surface overflow, and the fold limiter (docs/model.md §16) moves every point whose
    // triangles then have no usable normal back toward the muscles' pose: the output is
    // finite, no larger than the muscles' own, and the guard has nothing to say.
    MeshData muscles_only;
    ASSERT_TRUE(PosedMesh(rig, act, {false, false, false}, &muscles_only));
    float largest = 0.f;
    for (const float3& p : muscles_only.positions)
      largest = std::max({largest, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    EXPECT_GT(largest, 1e37f);
    ASSERT_EQ(posed.positions.size(), muscles_only.positions.size());
    for (const float3& p : posed.positions) {
      ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
      ASSERT_LE(std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}), largest * 1.001f);
    }
    Diagnostics bad;
    EXPECT_TRUE(CheckPosedFinite(rig, spec, act, {}, posed, &bad)) << bad.Format();
    EXPECT_TRUE(bad.empty()) << bad.Format();
    // At rest the same rig is finite: nothing to say.
    const std::vector<float> rest(rig.muscle_count(), 0.f);
    ASSERT_TRUE(PosedMesh(rig, rest, {}, &posed));
    Diagnostics quiet;
    EXPECT_TRUE(CheckPosedFinite(rig, spec, rest, {}, posed, &quiet));
    EXPECT_TRUE(quiet.empty());
  }
  {
    // Strong muscles (40 mm, area ratios well below 1/2) under a thickness of 3e38: the
    // muscles' motion is finite and sensible; (1/r - 1) h overflows, and the offsets'
    // curvature and slope bounds with the fold limiter (docs/model.md §16) keep the output
    // within a quarter of the surface's size of the muscles' (it is 100 mm across).
    RigSpec spec = MakeSurfaceRigSpec(4, 100.f, 100.f, 10.f, 0.3f, 40.f);
    spec.thickness.value = 3e38f;
    Diagnostics diag;
    ASSERT_TRUE(BuildRig(spec, mesh, unchecked, &rig, &diag)) << diag.Format();
    const std::vector<float> act(rig.muscle_count(), 1.f);
    MeshData posed, muscles_only;
    ASSERT_TRUE(PosedMesh(rig, act, {}, &posed));
    ASSERT_TRUE(PosedMesh(rig, act, {false, false, false}, &muscles_only));
    ASSERT_EQ(posed.positions.size(), muscles_only.positions.size());
    float worst = 0.f;
    for (size_t v = 0; v < posed.positions.size(); ++v)
      worst = std::max(worst, Length(posed.positions[v] - muscles_only.positions[v]));
    std::printf("thickness 3e38: largest skin offset %g mm\n", worst);
    EXPECT_TRUE(std::isfinite(worst));
    EXPECT_LT(worst, 25.f);  // a quarter of the surface, where the raw term is ~1e38
    Diagnostics bad;
    EXPECT_TRUE(CheckPosedFinite(rig, spec, act, {}, posed, &bad)) << bad.Format();
    EXPECT_TRUE(bad.empty()) << bad.Format();
  }
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

// BuildOptions::progress: called once per stage in the order BuildRig runs them, with shares
// that never go back, from 0 (the checks) to 1 (done); the rig is the same with or without it.
TEST(BuildRig, ReportsItsStagesInOrderFromZeroToOne) {
  RigSpec spec = Spec();
  spec.refinement.enabled = false;
  std::vector<std::pair<float, std::string>> calls;
  BuildOptions options;
  options.progress = [&](float done, const char* stage) { calls.emplace_back(done, stage); };
  Rig with, without;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, Surface(), options, &with, &diag)) << diag.Format();
  ASSERT_TRUE(BuildRig(spec, Surface(), BuildOptions{}, &without, &diag)) << diag.Format();
  const std::vector<std::string> want = {"checks", "welding", "muscles", "ordering",
                                         "muscles (ordered)", "fine scale", "tables", "done"};
  ASSERT_EQ(calls.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(calls[i].second, want[i]) << i;
    if (i > 0) {
      EXPECT_GE(calls[i].first, calls[i - 1].first) << want[i];
    }
  }
  EXPECT_EQ(calls.front().first, 0.f);
  EXPECT_EQ(calls.back().first, 1.f);
  EXPECT_LT(calls[calls.size() - 2].first, 1.f);  // the tables are not free
  EXPECT_EQ(with.vertex_count(), without.vertex_count());
  ASSERT_EQ(with.point_count(), without.point_count());
  for (uint32_t p = 0; p < with.point_count(); ++p)
    ASSERT_EQ(with.rest_points()[p], without.rest_points()[p]) << p;
}

// --- the lips carry no fat (docs/model.md §18, the mouth's free edge) -------------------------

// A flat 100 x 100 sheet (z = 0, points 2.5 apart) with a slit between the lips along y = 0 from
// x = -20 to 20: the cells above the slit use copies of its inner points raised by 0.01 (so the
// weld keeps them apart), the corners x = +-20 are shared. `slit` false: one closed sheet.
MeshData SlitSheet(bool slit) {
  constexpr int n = 41;
  MeshData m;
  m.source = slit ? "slit.obj" : "sheet.obj";
  auto at = [](int i, int j) { return float3{-50.f + 2.5f * float(i), -50.f + 2.5f * float(j), 0.f}; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.positions.push_back(at(i, j));
  std::vector<uint32_t> upper(n, 0);
  for (int i = 13; i <= 27 && slit; ++i) {  // x = -17.5 .. 17.5 on the row y = 0 (j = 20)
    upper[i] = uint32_t(m.positions.size());
    m.positions.push_back(at(i, 20) + float3{0.f, 0.01f, 0.f});
  }
  auto id = [&](int i, int j) {
    return (slit && j == 20 && upper[i] != 0) ? upper[i] : uint32_t(j * n + i);
  };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      // The cell's bottom row is the slit's upper side when the cell lies above it (j = 20).
      auto lo = [&](int ii) { return j == 20 ? id(ii, 20) : uint32_t(j * n + ii); };
      const uint32_t a = lo(i), b = lo(i + 1), c = uint32_t((j + 1) * n + i + 1),
                     d = uint32_t((j + 1) * n + i);
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  return m;
}

RigSpec SlitSpec(float thickness_fade, float3 mouth = {0.f, 0.005f, 0.f}) {
  RigSpec spec = MakeSurfaceRigSpec(4, 100.f, 100.f, 0.f, 0.3f, 3.f);
  spec.refinement.enabled = false;
  spec.thickness.value = 3.f;
  JawSpec jaw;
  jaw.condyles[0] = {-60.f, 20.f, -60.f};
  jaw.condyles[1] = {60.f, 20.f, -60.f};
  jaw.range_deg = 20.f;
  jaw.mouth = mouth;
  jaw.mouth_width = 40.f;
  jaw.thickness_fade = thickness_fade;
  spec.jaw = jaw;
  return spec;
}

// Distance from the segment x in [-20, 20], y = z = 0: the slit's lower side exactly, its
// upper side within 0.01.
float SlitDistance(float3 p) {
  const float dx = std::max(std::fabs(p.x) - 20.f, 0.f);
  return std::sqrt(dx * dx + p.y * p.y + p.z * p.z);
}

TEST(BuildRigLips, ThicknessFadesInFromTheSlitsEdgeBySmoothstepOfTheDistance) {
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(SlitSpec(0.3f), SlitSheet(true), BuildOptions{}, &rig, &diag)) << diag.Format();
  const float fade = 0.3f * 40.f;  // f W
  size_t zero = 0, partial = 0, full = 0;
  for (uint32_t p = 0; p < rig.point_count(); ++p) {
    const float d = SlitDistance(rig.rest_points()[p]);
    const float t = std::min(d / fade, 1.f);
    const float want = 3.f * t * t * (3.f - 2.f * t);
    // The upper side's 0.01 offset moves d by at most 0.01: h * 1.5 / (f W) * 0.01 in h.
    ASSERT_NEAR(rig.point_thickness()[p], want, 4e-3f) << "point " << p << " at distance " << d;
    zero += rig.point_thickness()[p] == 0.f;
    full += rig.point_thickness()[p] == 3.f;
    partial += rig.point_thickness()[p] > 0.f && rig.point_thickness()[p] < 3.f;
  }
  EXPECT_EQ(zero, 17u + 15u);  // the lower side's 17 points with the corners, the upper side's 15
  EXPECT_GT(partial, 100u);
  EXPECT_GT(full, rig.point_count() / 2);
}

TEST(BuildRigLips, AClosedLipLineAMouthFarFromTheSlitOrFadeZeroKeepTheThickness) {
  struct Case {
    const char* what;
    bool slit;
    RigSpec spec;
    bool faded;
  };
  const Case cases[] = {
      {"closed sheet", false, SlitSpec(0.3f), false},
      {"thickness_fade 0", true, SlitSpec(0.f), false},
      {"mouth 11 from the slit (more than W/4)", true, SlitSpec(0.3f, {0.f, -11.f, 0.f}), false},
      {"mouth 9 from the slit", true, SlitSpec(0.3f, {0.f, -9.f, 0.f}), true},
  };
  for (const Case& c : cases) {
    Rig rig;
    Diagnostics diag;
    ASSERT_TRUE(BuildRig(c.spec, SlitSheet(c.slit), BuildOptions{}, &rig, &diag)) << c.what << diag.Format();
    const float least = *std::min_element(rig.point_thickness().begin(), rig.point_thickness().end());
    EXPECT_EQ(least, c.faded ? 0.f : 3.f) << c.what;
  }
}

TEST(MouthEdgeDistances, PicksTheLoopNearestTheMouthNotTheSheetsRim) {
  const MeshData m = SlitSheet(true);
  JawSpec jaw = SlitSpec(0.3f).jaw.value();
  // Every vertex's distance (nothing welds here: all positions differ) from the slit alone,
  // not from the sheet's rim 30 beyond it.
  const std::vector<float> d = MouthEdgeDistances(jaw, m.positions, m.indices);
  ASSERT_EQ(d.size(), m.positions.size());
  for (size_t v = 0; v < d.size(); ++v)
    ASSERT_NEAR(d[v], SlitDistance(m.positions[v]), 0.0101f) << v;
  // A mouth beside the rim picks the rim: (50, 0) is 0 from it.
  jaw.mouth = {49.f, 30.f, 0.f};
  const std::vector<float> rim = MouthEdgeDistances(jaw, m.positions, m.indices);
  ASSERT_EQ(rim.size(), m.positions.size());
  EXPECT_NEAR(rim[20 * 41 + 40], 0.f, 1e-6f);
  EXPECT_NEAR(rim[20 * 41 + 20], 50.f, 1e-4f);
}

// `beyond` changes nothing below it: the same floats there, and at or past it a distance that
// is either measured or infinity. Points far off the slit's box exist (the rim is 30 beyond it),
// so some are skipped, and their measured distance is indeed past the cap.
TEST(MouthEdgeDistances, BeyondKeepsEveryDistanceBelowIt) {
  const MeshData m = SlitSheet(true);
  const JawSpec jaw = SlitSpec(0.3f).jaw.value();
  const std::vector<float> all = MouthEdgeDistances(jaw, m.positions, m.indices);
  for (float beyond : {0.f, 2.5f, 7.f}) {
    const std::vector<float> capped = MouthEdgeDistances(jaw, m.positions, m.indices, beyond);
    ASSERT_EQ(capped.size(), all.size());
    size_t skipped = 0;
    for (size_t v = 0; v < all.size(); ++v) {
      if (all[v] < beyond) {
        EXPECT_EQ(capped[v], all[v]) << v;
      } else if (capped[v] != all[v]) {
        EXPECT_EQ(capped[v], std::numeric_limits<float>::infinity()) << v;
        ++skipped;
      }
    }
    EXPECT_GT(skipped, all.size() / 4) << beyond;
  }
}

// A stray vertex no triangle uses (scans carry them) inside a muscle's reach: the muscle moves
// it, so the build makes it active like any moved point (it used to be left in the static range
// with muscle entries, and Rig::Build refused the tables as an internal error). Every other
// vertex poses exactly as without it; the stray one moves, and no skin layer touches it.
TEST(BuildRig, AStrayVertexAMuscleReachesMovesAndChangesNothingElse) {
  RigSpec spec = SlitSpec(0.f);
  spec.jaw.reset();
  const MeshData plain = SlitSheet(false);
  MeshData stray = plain;
  stray.positions.push_back({1.25f, 1.25f, 0.5f});  // inside the sheet's muscles' reach
  Rig with, without;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, plain, BuildOptions{}, &without, &diag)) << diag.Format();
  ASSERT_TRUE(BuildRig(spec, stray, BuildOptions{}, &with, &diag)) << diag.Format();
  ASSERT_EQ(with.vertex_count(), without.vertex_count() + 1);
  const std::vector<float> a(with.muscle_count(), 0.8f);
  MeshData posed_with, posed_without, bare;
  ASSERT_TRUE(PosedMesh(with, a, SkinLayers{}, &posed_with));
  ASSERT_TRUE(PosedMesh(without, a, SkinLayers{}, &posed_without));
  ASSERT_TRUE(PosedMesh(with, a, SkinLayers{false, false, false}, &bare));
  for (size_t v = 0; v < plain.vertex_count(); ++v)
    ASSERT_EQ(posed_with.positions[v], posed_without.positions[v]) << v;
  const size_t s = plain.vertex_count();
  EXPECT_GT(Length(posed_with.positions[s] - stray.positions[s]), 0.1f);
  EXPECT_EQ(posed_with.positions[s], bare.positions[s]);
}

}  // namespace
}  // namespace mimetic
