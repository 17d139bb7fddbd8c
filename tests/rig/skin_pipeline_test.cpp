// The whole per-frame pipeline with skin layers (docs/model.md §1): the 002 Fig. 3/5 set-up,
// finiteness under collapse, zero allocation and thread-split determinism with every layer on.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "content/procedural.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/normals_job.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

#include "alloc_counter.h"

namespace mimetic {
namespace {

// 002 §5 / Fig. 3, 5: a flat square of side 450, thickness 60, one straight wrinkle with
// k_d = 70, k_w = 50, k_r = 0 (area modulation), compressed across the wrinkle by a sheet
// muscle whose fibres run along +x (the wrinkle runs along y through x = 0).
struct Fig3 {
  MeshData mesh;
  RigSpec spec;
  Rig rig;
  Fig3() {
    mesh = MakeSurfaceMesh(91, 91, 450.f, 450.f, 0.f);  // 5-unit spacing, uv = x/450 + 0.5
    spec.units = "mm";
    spec.thickness.kind = ThicknessSpec::Kind::kConstant;
    spec.thickness.value = 60.f;
    MuscleSpec m;
    m.name = "sheet";
    m.type = MuscleType::kSheet;
    m.strength = 40.f;
    m.sheet.attachment[0] = {-200.f, -220.f, 0.f};
    m.sheet.attachment[1] = {-200.f, 220.f, 0.f};
    m.sheet.insertion[0] = {150.f, -220.f, 0.f};
    m.sheet.insertion[1] = {150.f, 220.f, 0.f};
    m.sheet.length = 350.f;
    m.sheet.width = 440.f;
    m.sheet.falloff_start = 300.f;  // Fl rises over x in [-200, 100]: compression at x = 0
    spec.muscles.push_back(m);
    NamedCurveWrinkle w;
    w.name = "fig3";
    w.spec.control[0] = {0.5f, 0.1f};
    w.spec.control[1] = {0.5f, 0.1f + 0.8f / 3};
    w.spec.control[2] = {0.5f, 0.1f + 1.6f / 3};
    w.spec.control[3] = {0.5f, 0.9f};
    w.spec.depth = 70.f;
    w.spec.width = 50.f;
    w.spec.modulation = CurveWrinkleModulation::kArea;
    w.spec.rest_amplitude = 0.f;
    w.spec.profile = CurveWrinkleProfile::kBando;
    spec.curve_wrinkles.push_back(w);
    spec.refinement.enabled = false;  // the 5-unit grid already resolves k_w = 50
    Diagnostics diag;
    EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  }
};

std::vector<float> Evaluate(const Rig& rig, span<const float> act, SkinLayers layers,
                            std::vector<float>* normals = nullptr,
                            std::vector<float>* area_ratios = nullptr, bool limit_folds = false) {
  EvaluateContext ctx(rig);
  std::vector<float> pos(3 * rig.vertex_count()), nrm(3 * rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = pos;
  job.out_normals = nrm;
  job.layers = layers;
  // The stage jobs chain the papers' layers as written; the fold limiter (docs/model.md §16)
  // departs from them on purpose where an offset would fold the skin, and is tested in
  // tests/fitting/foldover_test.cpp.
  job.limit_folds = limit_folds;
  EXPECT_TRUE(job.Run());
  if (normals) *normals = nrm;
  if (area_ratios) area_ratios->assign(ctx.area_ratios().begin(), ctx.area_ratios().end());
  return pos;
}

TEST(SkinPipeline, Bando2003Fig3WrinkleMatchesSTimesC) {
  const Fig3 f;
  ASSERT_TRUE(f.rig.layers().thickness);
  ASSERT_TRUE(f.rig.layers().curve_wrinkles);
  const std::vector<float> act = {1.f};
  // X1 (muscles only) gives the strain; the wrinkle is the difference of the runs with and
  // without the curve-wrinkle layer: S(l) C(r) N1 (docs/model.md §7, 002 eq. 4-6).
  const std::vector<float> x1 = Evaluate(f.rig, act, {false, false, false});
  const std::vector<float> on = Evaluate(f.rig, act, {true, true, true});
  const std::vector<float> off = Evaluate(f.rig, act, {true, true, false});

  // Area ratio r per vertex, computed here from X1 and the rest mesh (002 eq. 1).
  const size_t nv = f.mesh.vertex_count();
  std::vector<double> sum(nv, 0.0);
  std::vector<int> count(nv, 0);
  for (size_t t = 0; t < f.mesh.triangle_count(); ++t) {
    const uint32_t* i = &f.mesh.indices[3 * t];
    auto area = [&](auto p) {
      const double ax = p(i[1], 0) - p(i[0], 0), ay = p(i[1], 1) - p(i[0], 1), az = p(i[1], 2) - p(i[0], 2);
      const double bx = p(i[2], 0) - p(i[0], 0), by = p(i[2], 1) - p(i[0], 1), bz = p(i[2], 2) - p(i[0], 2);
      const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
      return 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
    };
    const double rest = area([&](uint32_t v, int c) { return double((&f.mesh.positions[v].x)[c]); });
    const double now = area([&](uint32_t v, int c) { return double(x1[3 * v + c]); });
    for (int k = 0; k < 3; ++k) sum[i[k]] += now / rest, ++count[i[k]];
  }

  const double kd = 70, kw = 50, kr = 0;
  int checked = 0, compressed = 0;
  for (size_t v = 0; v < nv; ++v) {
    const float3 p = f.mesh.positions[v];
    if (std::fabs(p.x) > 150.f || std::fabs(p.y) > 100.f) continue;  // away from the curve's ends
    const double l = std::fabs(p.x);          // distance to the furrow line, mesh units
    const double r = sum[v] / count[v];
    const double S = kd * (l / kw - 1.0) * std::exp(-l / kw);          // 000 eq. 2
    const double C = r <= 1.0 ? (kr - 1.0) * r + 1.0 : kr * std::exp((1.0 - 1.0 / kr) * (r - 1.0));
    const double dz = double(on[3 * v + 2]) - double(off[3 * v + 2]);
    EXPECT_NEAR(dz, S * C, 0.01 * kd) << "vertex " << v << " at x = " << p.x << ", r = " << r;
    // The flat sheet stays flat under an in-plane muscle: N1 = +Z, no in-plane wrinkle motion.
    EXPECT_NEAR(on[3 * v], off[3 * v], 1e-3);
    EXPECT_NEAR(on[3 * v + 1], off[3 * v + 1], 1e-3);
    ++checked;
    compressed += r < 0.95;
  }
  EXPECT_GT(checked, 300);
  EXPECT_GT(compressed, 50) << "the muscle must compress the skin across the wrinkle";
}

// Every activation in [0, 1], including strengths that collapse triangles to points: all
// outputs finite (accept g).
TEST(SkinPipeline, NoNaNOrInfinityEvenWhenTrianglesCollapse) {
  MeshData mesh = MakeSurfaceMesh(41, 41, 100.f, 100.f, 10.f);
  RigSpec spec = MakeSurfaceRigSpec(8, 100.f, 100.f, 10.f, 0.3f, 200.f);  // absurdly strong
  spec.thickness.value = 5.f;
  spec.muscle_wrinkles.resize(spec.muscles.size());
  for (size_t m = 0; m < spec.muscles.size(); ++m) {
    MuscleWrinkleSpec w;
    w.lambda_w = 0.3f;
    w.count = 3;
    w.depth = 2.f;
    w.shape = 0.5f;
    w.phi_c = spec.muscles[m].type == MuscleType::kLinear ? 0.2f : 0.f;
    w.h_c = spec.muscles[m].type == MuscleType::kSheet ? 0.1f * spec.muscles[m].sheet.width : 0.f;
    spec.muscle_wrinkles[m] = w;
  }
  for (int k = 0; k < 3; ++k) {
    NamedCurveWrinkle c;
    c.name = "c" + std::to_string(k);
    c.spec.control[0] = {0.2f, 0.2f + 0.3f * k};
    c.spec.control[1] = {0.4f, 0.25f + 0.3f * k};
    c.spec.control[2] = {0.6f, 0.15f + 0.3f * k};
    c.spec.control[3] = {0.8f, 0.2f + 0.3f * k};
    c.spec.depth = 2.f;
    c.spec.width = 3.f;
    c.spec.modulation = k == 1 ? CurveWrinkleModulation::kArea : CurveWrinkleModulation::kDirectional;
    c.spec.profile = CurveWrinkleProfile(k);
    c.spec.rest_amplitude = 0.2f;
    spec.curve_wrinkles.push_back(c);
  }
  spec.refinement.enabled = false;
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  ASSERT_TRUE(rig.layers().thickness && rig.layers().muscle_wrinkles && rig.layers().curve_wrinkles);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<float> act(rig.muscle_count());
  for (int frame = 0; frame < 40; ++frame) {
    for (float& a : act) a = frame % 4 == 0 ? 1.f : u(rng);
    std::vector<float> nrm;
    const std::vector<float> pos = Evaluate(rig, act, {}, &nrm);
    for (size_t i = 0; i < pos.size(); ++i) {
      ASSERT_TRUE(std::isfinite(pos[i])) << "frame " << frame << " float " << i;
      ASSERT_TRUE(std::isfinite(nrm[i])) << "frame " << frame << " float " << i;
    }
  }
}

// The test surface's rig spec (side 100, height 10, muscles reaching 0.2 at strength 4) with
// one muscle-wrinkle table, lambda_w and depth 0.5, on muscle `m`.
RigSpec WrinkledSpec(int muscles, size_t m, float lambda_w) {
  RigSpec spec = MakeSurfaceRigSpec(muscles, 100.f, 100.f, 10.f, 0.2f, 4.f);
  spec.muscle_wrinkles.resize(spec.muscles.size());
  MuscleWrinkleSpec w;
  w.lambda_w = lambda_w;
  w.depth = 0.5f;
  spec.muscle_wrinkles[m] = w;
  return spec;
}

Rig WrinkledSurface() {
  MeshData mesh = MakeSurfaceMesh(61, 61, 100.f, 100.f, 10.f);
  RigSpec spec = WrinkledSpec(6, 1, 0.3f);  // muscle 1: a sheet
  NamedCurveWrinkle c;
  c.name = "c";
  c.spec.control[0] = {0.2f, 0.5f};
  c.spec.control[1] = {0.4f, 0.45f};
  c.spec.control[2] = {0.6f, 0.55f};
  c.spec.control[3] = {0.8f, 0.5f};
  c.spec.depth = 1.f;
  c.spec.width = 2.f;
  spec.curve_wrinkles.push_back(c);
  spec.refinement.enabled = false;
  Rig rig;
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  EXPECT_TRUE(rig.layers().thickness && rig.layers().muscle_wrinkles && rig.layers().curve_wrinkles);
  return rig;
}

TEST(SkinPipeline, NoAllocationWithEveryLayerOn) {
  const Rig rig = WrinkledSurface();
  EvaluateContext ctx(rig);
  std::vector<float> act(rig.muscle_count(), 0.7f);
  std::vector<float> pos(3 * rig.vertex_count()), nrm(3 * rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = pos;
  job.out_normals = nrm;
  ASSERT_TRUE(job.Run());
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) {
    act[i % act.size()] = float(i % 10) / 10.f;
    ASSERT_TRUE(job.Run());
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

void TwoThreads(void*, uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
  const uint32_t mid = count / 3;
  std::thread t([&] { task(data, 0, mid); });
  task(data, mid, count);
  t.join();
}

TEST(SkinPipeline, BitIdenticalWhenSplitAcrossTwoThreads) {
  const Rig rig = WrinkledSurface();
  std::vector<float> act(rig.muscle_count());
  for (size_t m = 0; m < act.size(); ++m) act[m] = 0.3f + 0.1f * float(m);
  std::vector<float> n1;
  const std::vector<float> serial = Evaluate(rig, act, {}, &n1, nullptr, /*limit_folds=*/true);
  EvaluateContext ctx(rig);
  std::vector<float> pos(3 * rig.vertex_count()), nrm(3 * rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = pos;
  job.out_normals = nrm;
  job.parallel_for = TwoThreads;
  job.parallel_min_count = 1;  // split every loop, however short
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(std::memcmp(serial.data(), pos.data(), pos.size() * 4), 0);
  EXPECT_EQ(std::memcmp(n1.data(), nrm.data(), nrm.size() * 4), 0);
  // And the layers did something.
  const std::vector<float> bare = Evaluate(rig, act, {false, false, false});
  EXPECT_NE(std::memcmp(serial.data(), bare.data(), bare.size() * 4), 0);
}

TEST(SkinPipeline, RestPoseComesBackBitForBitWithEveryLayerOn) {
  const Rig rig = WrinkledSurface();  // its curve wrinkle has rest amplitude 0
  const std::vector<float> zero(rig.muscle_count(), 0.f);
  const std::vector<float> pos = Evaluate(rig, zero, {});
  const MeshData rest = RestMesh(rig);
  EXPECT_EQ(std::memcmp(pos.data(), rest.positions.data(), pos.size() * 4), 0);
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

// Accept f at the rig level: BuildRig refines inside a curve wrinkle's support until edges are
// at most width/4 (the default fraction), and the triangles far from it are the file's own.
TEST(SkinPipeline, BuildRigRefinesOnlyInsideWrinkleSupports) {
  const MeshData mesh = MakeSurfaceMesh(21, 21, 100.f, 100.f, 0.f);  // 5 mm edges
  RigSpec spec;
  spec.units = "mm";
  NamedCurveWrinkle c;
  c.name = "line";
  // A straight furrow along x at y = 0 (uv v = 0.5), from x = -30 to x = 30.
  c.spec.control[0] = {0.2f, 0.5f};
  c.spec.control[1] = {0.4f, 0.5f};
  c.spec.control[2] = {0.6f, 0.5f};
  c.spec.control[3] = {0.8f, 0.5f};
  c.spec.depth = 1.f;
  c.spec.width = 2.f;  // target edge: 0.5 mm; Bando support 8 w = 16 mm
  spec.curve_wrinkles.push_back(c);
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  ASSERT_GT(rig.vertex_count(), mesh.vertex_count());
  // The first #V output vertices are the file's, unchanged.
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    ASSERT_EQ(rig.rest_points()[rig.vertex_points()[v]], mesh.positions[v]);
  size_t near = 0, far_kept = 0, far = 0;
  const MeshData rest = RestMesh(rig);  // the output layout: file order
  for (uint32_t t = 0; t < rig.triangle_count(); ++t) {
    const float3 a = rest.positions[rest.indices[3 * t]], b = rest.positions[rest.indices[3 * t + 1]],
                 d = rest.positions[rest.indices[3 * t + 2]];
    const float3 centroid = (a + b + d) / 3.f;
    const float longest = std::max({Length(b - a), Length(d - b), Length(a - d)});
    // Within the Bando support (8 w = 16 mm) of the segment, away from its ends.
    if (std::fabs(centroid.x) < 25.f && std::fabs(centroid.y) < 14.f) {
      EXPECT_LE(longest, 0.5f + 1e-4f) << "triangle " << t;
      ++near;
    }
    // Farther than the support, widened by the longest input edge (7.07 mm) and by two more
    // for the bisection's closure: the file's 5 mm triangles, untouched.
    if (std::fabs(centroid.y) > 16.f + 3 * 7.08f) {
      ++far;
      far_kept += rig.vertex_indices()[3 * t] < mesh.vertex_count() &&
                  rig.vertex_indices()[3 * t + 1] < mesh.vertex_count() &&
                  rig.vertex_indices()[3 * t + 2] < mesh.vertex_count() && longest > 5.f;
    }
  }
  EXPECT_GT(near, 1000u);
  EXPECT_GT(far, 0u);
  EXPECT_EQ(far_kept, far);
  // Switching refinement off keeps the file's layout exactly.
  spec.refinement.enabled = false;
  Rig plain;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &plain, &diag)) << diag.Format();
  EXPECT_EQ(plain.vertex_count(), mesh.vertex_count());
  EXPECT_EQ(plain.vertex_indices(), mesh.indices);
}

// EvaluateJob fuses the stages (face_kernels.h, edge lengths once per edge, one displacement
// per point). A second method: the public stage jobs chained one after another over every
// point, as an engine running the stages itself would. Ratios must agree to the bit (the same
// expressions), positions and normals to rounding.
void ExpectFusedMatchesChainedStageJobs(const Rig& rig, span<const float> act) {
  const uint32_t P = rig.point_count(), T = rig.triangle_count();
  std::vector<float3> x(P), faces(T), n1(P), n3(P);
  std::vector<float> tri_ratio(T), ratio(P);
  ASSERT_TRUE((MuscleDeformJob{.table = &rig.muscles(),
                               .activations = act,
                               .rest_points = rig.rest_points(),
                               .out_points = x,
                               .begin = 0,
                               .end = P}.Run()));
  FaceNormalsJob fj{.points = x,
                    .triangles = rig.triangles(),
                    .out_face_normals = faces,
                    .begin = 0,
                    .end = T,
                    .rest_areas = rig.rest_triangle_areas(),
                    .out_area_ratios = tri_ratio};
  ASSERT_TRUE(fj.Run());
  PointNormalsJob pj{.face_normals = faces,
                     .point_triangle_offsets = rig.point_triangle_offsets(),
                     .point_triangles = rig.point_triangles(),
                     .out_normals = n1,
                     .begin = 0,
                     .end = P,
                     .triangle_ratios = tri_ratio,
                     .out_ratios = ratio};
  ASSERT_TRUE(pj.Run());
  std::vector<std::vector<float>> eps;
  for (const RigMuscleWrinkles& w : rig.muscle_wrinkles()) {
    eps.emplace_back(w.row_count());
    ASSERT_TRUE((EdgeCompressionJob{.positions = x,
                                    .points = w.points,
                                    .offsets = w.edge_offsets,
                                    .neighbors = w.edge_neighbors,
                                    .rest_lengths = w.edge_rest_lengths,
                                    .weights = w.edge_weights,
                                    .begin = 0,
                                    .end = w.row_count(),
                                    .out_compression = eps.back()}.Run()));
  }
  const RigCurveWrinkles& c = rig.curve_wrinkles();
  std::vector<float> shrink(c.probes.size());
  ASSERT_TRUE((DirectionalShrinkageJob{.positions = x,
                                       .probes = c.probes,
                                       .begin = 0,
                                       .end = c.probes.size(),
                                       .out_shrinkage = shrink}.Run()));
  ThicknessJob th;
  th.positions = x;
  th.normals = n1;
  th.area_ratios = ratio;
  th.thickness = rig.point_thickness();
  th.min_area_ratio = rig.min_area_ratio();
  th.end = P;
  th.out_positions = x;
  ASSERT_TRUE(th.Run());
  for (size_t t = 0; t < rig.muscle_wrinkles().size(); ++t) {
    const RigMuscleWrinkles& w = rig.muscle_wrinkles()[t];
    MuscleWrinkleJob mj{.normals = n1,
                        .points = w.points,
                        .phase = w.phase,
                        .attenuation = w.attenuation,
                        .compression = eps[t],
                        .half_cycle = w.half_cycle,
                        .furrow_depth = w.furrow_depth,
                        .shape = w.shape,
                        .begin = 0,
                        .end = w.row_count(),
                        .positions = x,
                        .out_amplitudes = {},
                        .profile = {},
                        .gate = WrinkleGate(act[w.muscle], w.gate)};
    ASSERT_TRUE(mj.Run());
  }
  CurveWrinkleJob cj{.normals = n1,
                     .wrinkles = c.wrinkles,
                     .points = c.points,
                     .offsets = c.offsets,
                     .entries = c.entries,
                     .entry_shrinkage = shrink,
                     .area_ratios = ratio,
                     .begin = 0,
                     .end = c.row_count(),
                     .positions = x,
                     .out_amplitudes = {}};
  ASSERT_TRUE(cj.Run());
  ASSERT_TRUE((FaceNormalsJob{.points = x,
                              .triangles = rig.triangles(),
                              .out_face_normals = faces,
                              .begin = 0,
                              .end = T,
                              .rest_areas = {},
                              .out_area_ratios = {}}.Run()));
  ASSERT_TRUE((PointNormalsJob{.face_normals = faces,
                               .point_triangle_offsets = rig.point_triangle_offsets(),
                               .point_triangles = rig.point_triangles(),
                               .out_normals = n3,
                               .begin = 0,
                               .end = P,
                               .triangle_ratios = {},
                               .out_ratios = {}}.Run()));

  std::vector<float> nrm, fused_ratios;
  const std::vector<float> pos = Evaluate(rig, act, {}, &nrm, &fused_ratios);
  double moved = 0.0;
  for (uint32_t v = 0; v < rig.vertex_count(); ++v) {
    const uint32_t p = rig.vertex_points()[v];
    ASSERT_EQ(fused_ratios[p], ratio[p]) << "point " << p;
    for (int d = 0; d < 3; ++d) {
      ASSERT_NEAR(pos[3 * v + d], (&x[p].x)[d], 2e-5f * (1.f + std::fabs((&x[p].x)[d])))
          << "vertex " << v;
      ASSERT_NEAR(nrm[3 * v + d], (&n3[p].x)[d], 1e-5f) << "vertex " << v;
    }
    moved = std::max(moved, double(Length(x[p] - rig.rest_points()[p])));
  }
  EXPECT_GT(moved, 0.1);  // the comparison saw real displacement
}

TEST(SkinPipeline, FusedEvaluationMatchesTheStageJobsChained) {
  const Rig rig = WrinkledSurface();
  std::vector<float> act(rig.muscle_count());
  for (size_t m = 0; m < act.size(); ++m) act[m] = 0.35f + 0.1f * float(m);
  ExpectFusedMatchesChainedStageJobs(rig, act);
  // Every muscle full on: triangles near the attachments collapse (r clamps to r_min).
  std::vector<float> full(rig.muscle_count(), 1.f);
  ExpectFusedMatchesChainedStageJobs(rig, full);
}

TEST(SkinPipeline, FusedEvaluationMatchesTheStageJobsWithBothModulations) {
  // Curve wrinkles of both modulations (directional s and area r) and a Yang-Zhang profile.
  MeshData mesh = MakeSurfaceMesh(51, 51, 100.f, 100.f, 10.f);
  RigSpec spec = WrinkledSpec(8, 0, 0.6f);
  // One gated table beside an ungated one (docs/model.md §6).
  spec.muscle_wrinkles[3] = spec.muscle_wrinkles[0];
  spec.muscle_wrinkles[3]->gate = 0.9f;
  for (int k = 0; k < 3; ++k) {
    NamedCurveWrinkle c;
    c.name = "c" + std::to_string(k);
    const float v = 0.25f + 0.25f * float(k);
    c.spec.control[0] = {0.2f, v};
    c.spec.control[1] = {0.4f, v + 0.05f};
    c.spec.control[2] = {0.6f, v - 0.05f};
    c.spec.control[3] = {0.8f, v};
    c.spec.depth = 1.f;
    c.spec.width = 3.f;
    c.spec.rest_amplitude = 0.2f;
    c.spec.modulation = k == 1 ? CurveWrinkleModulation::kArea : CurveWrinkleModulation::kDirectional;
    if (k == 2) c.spec.profile = CurveWrinkleProfile::kYangZhang;
    spec.curve_wrinkles.push_back(c);
  }
  spec.refinement.enabled = false;
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  ASSERT_EQ(rig.muscle_wrinkles().size(), 2u);
  EXPECT_EQ(rig.muscle_wrinkles()[1].gate, 0.9f);
  std::vector<float> act(rig.muscle_count());
  for (size_t m = 0; m < act.size(); ++m) act[m] = 0.2f + 0.09f * float(m);
  ExpectFusedMatchesChainedStageJobs(rig, act);
}

// docs/model.md §6, the gate: with the muscle wrinkles the only layer and no limiter, X3 = X1 +
// W N1 and N1 does not see the wrinkles, so a gated table's displacement is G times the
// ungated one's, G = smoothstep(0, gate, a) of its own muscle's activation, by hand; another
// muscle's activation does not open it.
TEST(SkinPipeline, TheGateScalesAMusclesWrinklesByItsOwnActivation) {
  MeshData mesh = MakeSurfaceMesh(51, 51, 100.f, 100.f, 10.f);
  RigSpec spec = WrinkledSpec(6, 1, 0.3f);
  spec.refinement.enabled = false;
  Rig open, gated;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &open, &diag)) << diag.Format();
  spec.muscle_wrinkles[1]->gate = 0.8f;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &gated, &diag)) << diag.Format();
  ASSERT_EQ(gated.muscle_wrinkles().size(), 1u);
  const SkinLayers off{false, false, false}, wrinkles{false, true, false};
  for (const float a1 : {0.f, 0.2f, 0.4f, 0.8f, 1.f}) {
    std::vector<float> act(open.muscle_count(), 0.6f);  // the others compress its region too
    act[1] = a1;
    const double x = std::min(a1 / 0.8, 1.0), G = x * x * (3.0 - 2.0 * x);
    const std::vector<float> x1 = Evaluate(open, act, off);
    const std::vector<float> full = Evaluate(open, act, wrinkles);
    const std::vector<float> part = Evaluate(gated, act, wrinkles);
    double largest = 0.0;
    for (size_t i = 0; i < x1.size(); ++i) {
      const double d = double(full[i]) - x1[i];
      largest = std::max(largest, std::fabs(d));
      ASSERT_NEAR(double(part[i]) - x1[i], G * d, 5e-7 * (1.0 + std::fabs(x1[i])) + 1e-6) << i;
    }
    EXPECT_GT(largest, 0.003) << "a1 " << a1;  // the region is compressed: there are wrinkles
  }
}

}  // namespace
}  // namespace mimetic
