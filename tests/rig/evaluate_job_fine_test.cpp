// EvaluateJob's fine-scale amplitudes (docs/model.md §23): M(s) of 000 eq. 5 at hand-computed
// points, a sheet compressed across field 1 and stretched across field 2, the builder's probes
// against the public DirectionalShrinkageJob, bit-identical splits, zero allocation and the
// job's checks.
#include <algorithm>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "content/procedural.h"
#include "geometry/topology.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "wrinkles/offline/wrinkle_builder.h"
#include "wrinkles/runtime/profiles.h"

#include "alloc_counter.h"
#include "rig/frame_helpers.h"

namespace mimetic {
namespace {

// (n + 1)^2 grid points with spacing 1; rest_points = map(x, y); the probes are built on the
// unmapped grid (its lengths are the rest lengths) with uv = (x, y) / n, so a frame with no
// muscle measures the strain of `map` against the unit grid.
template <class Map>
RigData FineGridRig(uint32_t n, const Map& map, float2 across1, float2 across2, float r) {
  RigData d;
  const uint32_t side = n + 1;
  std::vector<float3> unit;
  for (uint32_t y = 0; y < side; ++y)
    for (uint32_t x = 0; x < side; ++x) {
      d.rest_points.push_back(map(float(x), float(y)));
      unit.push_back({float(x), float(y), 0.f});
      d.vertex_uvs.push_back({float(x) / n, float(y) / n});
    }
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      const uint32_t a = y * side + x, b = a + 1, c = a + side, e = c + 1;
      d.triangles.insert(d.triangles.end(), {a, b, e, a, e, c});
    }
  const uint32_t points = d.point_count(), tris = d.triangle_count();
  const CsrTable pt = BuildPointTriangles(d.triangles, points);
  d.point_triangle_offsets = pt.offsets;
  d.point_triangles = pt.items;
  d.active = {points, points, tris};
  for (uint32_t p = 0; p < points; ++p) d.vertex_points.push_back(p);
  d.vertex_indices = d.triangles;
  d.muscles.offsets.assign(size_t(points) + 1, 0);
  std::vector<float2> corner_uvs;
  for (uint32_t v : d.triangles) corner_uvs.push_back(d.vertex_uvs[v]);
  d.fine_scale.rest_amplitude = r;
  for (uint32_t p = 0; p < points; ++p) {
    d.fine_scale.probes.push_back(BuildShrinkageProbe(p, across1, unit, d.triangles, corner_uvs, pt));
    d.fine_scale.probes.push_back(BuildShrinkageProbe(p, across2, unit, d.triangles, corner_uvs, pt));
  }
  return d;
}

bool RunFine(const Rig& rig, EvaluateContext* ctx, std::vector<float>* amps,
             std::vector<float>* positions, ParallelForFn pf = nullptr,
             span<const float> activations = {}) {
  positions->assign(3 * rig.vertex_count(), 0.f);
  amps->assign(2 * rig.vertex_count(), -1.f);
  EvaluateJob job;
  job.rig = &rig;
  job.context = ctx;
  job.activations = activations;
  job.out_positions = *positions;
  job.out_fine_amplitudes = *amps;
  job.parallel_for = pf;
  job.parallel_min_count = 1;
  return job.Run();
}

TEST(EvaluateJobFine, ModulationIsBando2002EquationFiveAtHandPoints) {
  // M(s) = (1 - r) s + r for s >= 0, r exp((1/r - 1) s) for s < 0.
  EXPECT_FLOAT_EQ(DirectionalModulation(0.f, 0.5f), 0.5f);
  EXPECT_FLOAT_EQ(DirectionalModulation(0.5f, 0.5f), 0.75f);
  EXPECT_FLOAT_EQ(DirectionalModulation(1.f, 0.5f), 1.f);
  EXPECT_NEAR(DirectionalModulation(-1.f, 0.5f), 0.5 * std::exp(-1.0), 1e-7);
  EXPECT_NEAR(DirectionalModulation(-0.5f, 0.25f), 0.25 * std::exp(3.0 * -0.5), 1e-7);
  EXPECT_FLOAT_EQ(DirectionalModulation(0.2f, 0.25f), 0.75f * 0.2f + 0.25f);
}

TEST(EvaluateJobFine, CompressedAcrossFieldOneAndStretchedAcrossFieldTwo) {
  // X = (0.8 x, 1.25 y, 0): field 1's furrows run along y (s measured across them, along x:
  // compressed, s1 = 1 - 0.8 = 0.2); field 2's along x (s across along y: stretched, s2 =
  // 1 - 1.25 = -0.25). Along a grid edge the probe's ray runs along that edge, so L'/L is the
  // edge's length ratio exactly. r = 0.5: M1 = 0.5 * 0.2 + 0.5 = 0.6, M2 = 0.5 e^-0.25.
  const auto map = [](float x, float y) { return float3{0.8f * x, 1.25f * y, 0.f}; };
  Rig rig;
  ASSERT_TRUE(Rig::Build(FineGridRig(6, map, {1.f, 0.f}, {0.f, 1.f}, 0.5f), &rig));
  EvaluateContext ctx(rig);
  std::vector<float> amps, pos;
  ASSERT_TRUE(RunFine(rig, &ctx, &amps, &pos));
  for (uint32_t v = 0; v < rig.vertex_count(); ++v) {
    EXPECT_NEAR(amps[2 * v], 0.6f, 1e-5f) << "vertex " << v;
    EXPECT_NEAR(amps[2 * v + 1], 0.5 * std::exp(-0.25), 1e-5) << "vertex " << v;
    EXPECT_GT(amps[2 * v], 0.5f);      // raised above the rest amplitude
    EXPECT_LT(amps[2 * v + 1], 0.5f);  // lowered
  }
  // At rest both are r.
  Rig rest;
  ASSERT_TRUE(Rig::Build(FineGridRig(4, [](float x, float y) { return float3{x, y, 0.f}; },
                                     {1.f, 0.f}, {0.f, 1.f}, 0.3f), &rest));
  EvaluateContext rctx(rest);
  ASSERT_TRUE(RunFine(rest, &rctx, &amps, &pos));
  for (float a : amps) EXPECT_FLOAT_EQ(a, 0.3f);
}

// The surface rig with a fine_scale block: field 1 along x, field 2 along y.
struct Surface {
  MeshData mesh;
  RigSpec spec;
  Rig rig;
};
Surface FineSurface(uint32_t side, uint32_t muscles, bool skin_layers = false) {
  Surface s;
  s.mesh = MakeSurfaceMesh(side, side, 100.f, 100.f, 10.f);
  s.spec = MakeSurfaceRigSpec(muscles, 100.f, 100.f, 10.f, 0.15f, 3.f);
  if (skin_layers) AddEverySkinLayer(&s.spec, 0.4f, 6.f);
  FineScaleSpec fs;
  fs.fields[0].name = "along_x";
  fs.fields[0].anchors = {{0, {0.5f, 0.f, 0.f}}, {side * side - 1, {0.7f, 0.f, 0.f}}};
  fs.fields[1].name = "along_y";
  fs.fields[1].anchors = {{0, {0.f, 0.5f, 0.f}}};
  fs.rest_amplitude = 0.4f;
  s.spec.fine_scale = fs;
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(s.spec, s.mesh, {}, &s.rig, &diag)) << diag.Format();
  return s;
}

using test::SomeActivations;
using test::TwoThreads;

// A frame of `rig` that asks for positions only (no fine-scale amplitudes).
EvaluateJob PositionsOnlyJob(const Rig& rig, EvaluateContext* ctx, const std::vector<float>& act,
                             std::vector<float>& positions) {
  EvaluateJob job;
  job.rig = &rig;
  job.context = ctx;
  job.activations = act;
  job.out_positions = positions;
  return job;
}

// Second method for a frame's amplitudes: X1 from a frame with the skin layers off,
// DirectionalShrinkageJob over the probes, DirectionalModulation (r = 0.4, FineSurface's).
// Returns how many amplitudes the strain moved away from r.
size_t ExpectPublicShrinkageAmplitudes(const Rig& rig, const std::vector<float>& act,
                                       const std::vector<float>& amps) {
  const RigFineScale& fs = rig.fine_scale();
  EvaluateContext ctx(rig);
  EXPECT_TRUE(test::RunPoseBeforeSkin(rig, act, &ctx));
  std::vector<float> sh(fs.probes.size());
  const DirectionalShrinkageJob job{.positions = ctx.points(),
                                    .probes = fs.probes,
                                    .end = fs.probes.size(),
                                    .out_shrinkage = sh};
  EXPECT_TRUE(job.Run());
  size_t moved = 0;
  for (uint32_t v = 0; v < rig.vertex_count(); ++v) {
    const uint32_t p = rig.vertex_points()[v];
    for (int k = 0; k < 2; ++k) {
      const float expect = p < fs.point_count() ? DirectionalModulation(sh[2 * p + k], 0.4f) : 0.4f;
      EXPECT_NEAR(amps[2 * v + k], expect, 1e-6f) << "vertex " << v << " field " << k;
      moved += std::fabs(amps[2 * v + k] - 0.4f) > 1e-3f;
    }
  }
  return moved;
}

TEST(EvaluateJobFine, BuilderProbesGiveThePublicShrinkageJobsAmplitudes) {
  const Surface s = FineSurface(30, 6);
  const RigFineScale& fs = s.rig.fine_scale();
  ASSERT_FALSE(fs.empty());
  EXPECT_EQ(fs.point_count(), s.rig.normal_point_count());
  EXPECT_FLOAT_EQ(fs.rest_amplitude, 0.4f);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext ctx(s.rig);
  std::vector<float> amps, pos;
  ASSERT_TRUE(RunFine(s.rig, &ctx, &amps, &pos, nullptr, act));
  EXPECT_GT(ExpectPublicShrinkageAmplitudes(s.rig, act, amps), 20u) << "the muscles strain the surface";
}

TEST(EvaluateJobFine, BitIdenticalSplitsZeroAllocationAndNoEffectOnPositions) {
  const Surface s = FineSurface(40, 8);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c2(s.rig), c3(s.rig);
  std::vector<float> a1, a2, p1, p2;
  ASSERT_TRUE(RunFine(s.rig, &c1, &a1, &p1, nullptr, act));
  ASSERT_TRUE(RunFine(s.rig, &c2, &a2, &p2, TwoThreads, act));
  EXPECT_EQ(std::memcmp(a1.data(), a2.data(), a1.size() * 4), 0);
  EXPECT_EQ(std::memcmp(p1.data(), p2.data(), p1.size() * 4), 0);
  // Positions are those of a frame without the output.
  std::vector<float> p3(p1.size());
  EvaluateJob job = PositionsOnlyJob(s.rig, &c3, act, p3);
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(std::memcmp(p1.data(), p3.data(), p1.size() * 4), 0);
  // Zero allocation per frame with the output on.
  job.out_fine_amplitudes = a1;
  const long before = g_allocations.load();
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(job.Run());
  EXPECT_EQ(g_allocations.load() - before, 0);
}

// With the wrinkle layers on, the strain and the probes share most edges: the probes read the
// strain's ids for those (each edge measured once a frame, by StageFineScale, and StageStrain
// skips its pass). The tables: every probe slot names the edge of its own corners, the probes'
// own edges are none of the strain's, and some probe edges are the strain's. The frame: the
// amplitudes are the public shrinkage job's on X1, and the positions (which the strain's
// lengths drive) are the bits of a frame without the output, on fresh contexts.
TEST(EvaluateJobFine, ProbesReadTheStrainsEdgesAndTheStrainStillSeesThem) {
  const Surface s = FineSurface(30, 6, true);
  const RigTables& t = s.rig.tables();
  const RigFineScale& fs = s.rig.fine_scale();
  const uint32_t E = t.edge_count(), F = t.fine_edge_count();
  ASSERT_GT(E, 0u);
  auto pair_of = [&](uint32_t id) {
    const uint32_t* p = id < E ? &t.edge_pairs[2 * id] : &t.fine_edge_pairs[2 * (id - E)];
    return std::pair<uint32_t, uint32_t>(std::min(p[0], p[1]), std::max(p[0], p[1]));
  };
  std::set<std::pair<uint32_t, uint32_t>> strain;
  for (uint32_t e = 0; e < E; ++e) strain.insert(pair_of(e));
  EXPECT_EQ(strain.size(), E);
  for (uint32_t k = 0; k < F; ++k) EXPECT_EQ(strain.count(pair_of(E + k)), 0u) << "fine edge " << k;
  constexpr uint32_t B = RigTables::kFineProbeBlock;
  size_t shared = 0, own = 0;
  for (size_t i = 0; i < fs.probes.size(); ++i) {
    const ShrinkageProbe& probe = fs.probes[i];
    const uint32_t* e = &t.fine_probe_edges[(i / B) * 4 * B + i % B];
    for (uint32_t side = 0; side < 2; ++side)
      for (uint32_t j = 0; j < 2; ++j) {
        const uint32_t id = e[(2 * side + j) * B];
        const float rest = side < probe.side_count
                               ? (j == 0 ? probe.sides[side].rest_length2 : probe.sides[side].rest_length3)
                               : 0.f;
        if (rest <= 0.f) {
          EXPECT_EQ(id, E + F) << "probe " << i << ": the length-1 slot";
          continue;
        }
        const uint32_t other = j == 0 ? probe.sides[side].v2 : probe.sides[side].v3;
        EXPECT_EQ(pair_of(id), std::make_pair(std::min(probe.point, other), std::max(probe.point, other)))
            << "probe " << i << " side " << side;
        (id < E ? shared : own)++;
      }
  }
  EXPECT_GT(shared, 100u);
  EXPECT_GT(own, 0u);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c3(s.rig);
  std::vector<float> amps, p1;
  ASSERT_TRUE(RunFine(s.rig, &c1, &amps, &p1, nullptr, act));
  std::vector<float> p3(p1.size());
  EvaluateJob job = PositionsOnlyJob(s.rig, &c3, act, p3);
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(std::memcmp(p1.data(), p3.data(), p1.size() * 4), 0);
  EXPECT_GT(ExpectPublicShrinkageAmplitudes(s.rig, act, amps), 20u);
}

// A scheduler that hands out ranges of 1, 2 and 3 items in turn, serially: the fine-scale
// probes then start at every alignment of their four-probe blocks, so most go through the
// scalar form and the rest through other lanes than in one whole range.
void RaggedRanges(void*, uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
  uint32_t step = 1;
  for (uint32_t b = 0; b < count; b += step, step = step % 3 + 1) task(data, b, std::min(count, b + step));
}

TEST(EvaluateJobFine, LanesAndScalarGiveTheSameBitsAtEveryAlignment) {
  const Surface s = FineSurface(40, 8);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c2(s.rig);
  std::vector<float> a1, a2, p1, p2;
  ASSERT_TRUE(RunFine(s.rig, &c1, &a1, &p1, nullptr, act));
  ASSERT_TRUE(RunFine(s.rig, &c2, &a2, &p2, RaggedRanges, act));
  size_t stretched = 0, compressed = 0;
  for (size_t i = 0; i < a1.size(); ++i) {
    ASSERT_EQ(std::memcmp(&a1[i], &a2[i], 4), 0) << "amplitude " << i << ": " << a1[i] << " vs " << a2[i];
    stretched += a1[i] < 0.4f - 1e-4f;
    compressed += a1[i] > 0.4f + 1e-4f;
  }
  // Both sides of M(s) (the exponential and the line) were exercised.
  EXPECT_GT(stretched, 10u);
  EXPECT_GT(compressed, 10u);
}

// BuildOptions::fine_scale_probes = false (what `mimetic texture` builds): no probes, so no
// amplitudes (0, as a rig without the block), and everything else the same: the points, the
// triangles and a posed frame's positions to the bit.
TEST(EvaluateJobFine, ABuildWithoutProbesKeepsEverythingButTheAmplitudes) {
  const Surface s = FineSurface(30, 6, true);
  BuildOptions options;
  options.fine_scale_probes = false;
  Rig bare;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(s.spec, s.mesh, options, &bare, &diag)) << diag.Format();
  ASSERT_FALSE(s.rig.fine_scale().empty());
  EXPECT_TRUE(bare.fine_scale().empty());
  EXPECT_EQ(bare.tables().fine_edge_count(), 0u);
  ASSERT_EQ(bare.point_count(), s.rig.point_count());
  EXPECT_EQ(std::memcmp(bare.rest_points().data(), s.rig.rest_points().data(),
                        sizeof(float3) * bare.point_count()), 0);
  EXPECT_EQ(bare.data().triangles, s.rig.data().triangles);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c2(bare);
  std::vector<float> a1, a2, p1, p2;
  ASSERT_TRUE(RunFine(s.rig, &c1, &a1, &p1, nullptr, act));
  ASSERT_TRUE(RunFine(bare, &c2, &a2, &p2, nullptr, act));
  EXPECT_EQ(std::memcmp(p1.data(), p2.data(), p1.size() * 4), 0);
  for (float a : a2) ASSERT_EQ(a, 0.f);
  EXPECT_GT(ExpectPublicShrinkageAmplitudes(s.rig, act, a1), 20u);
}

TEST(EvaluateJobFine, TheJobRefusesShortOrMisalignedOutputsAndARigWithoutMapsGivesZero) {
  const Surface s = FineSurface(12, 2);
  EvaluateContext ctx(s.rig);
  std::vector<float> pos(3 * s.rig.vertex_count()), amps(2 * s.rig.vertex_count());
  const std::vector<float> act(s.rig.muscle_count(), 0.f);
  EvaluateJob job;
  job.rig = &s.rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = pos;
  job.out_fine_amplitudes = span<float>(amps).first(amps.size() - 1);
  EXPECT_FALSE(job.Validate());
  job.out_fine_amplitudes = amps;
  job.out_fine_amplitudes_stride = 6;
  EXPECT_FALSE(job.Validate());
  job.out_fine_amplitudes_stride = 4;
  EXPECT_FALSE(job.Validate());
  job.out_fine_amplitudes_stride = 8;
  EXPECT_TRUE(job.Run());
  for (float a : amps) EXPECT_FLOAT_EQ(a, 0.4f);  // at rest: r
  // A strided layout: amplitudes at floats 1-2 of 4 per vertex.
  std::vector<float> wide(4 * s.rig.vertex_count(), -7.f);
  job.out_fine_amplitudes = span<float>(wide).subspan(1);
  job.out_fine_amplitudes_stride = 16;
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(wide[0], -7.f);
  EXPECT_FLOAT_EQ(wide[1], 0.4f);
  EXPECT_FLOAT_EQ(wide[2], 0.4f);
  EXPECT_EQ(wide[3], -7.f);
  // Without a fine_scale block: 0.
  RigSpec plain = s.spec;
  plain.fine_scale.reset();
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(plain, s.mesh, {}, &rig, &diag));
  EvaluateContext pctx(rig);
  job.rig = &rig;
  job.context = &pctx;
  job.out_fine_amplitudes = amps;
  job.out_fine_amplitudes_stride = 8;
  ASSERT_TRUE(job.Run());
  for (float a : amps) EXPECT_EQ(a, 0.f);
}

TEST(EvaluateJobFine, RigBuildRefusesMalformedProbes) {
  const auto map = [](float x, float y) { return float3{x, y, 0.f}; };
  RigData d = FineGridRig(3, map, {1.f, 0.f}, {0.f, 1.f}, 0.5f);
  Rig rig;
  RigData bad = d;
  bad.fine_scale.probes.pop_back();  // odd count
  EXPECT_FALSE(Rig::Build(bad, &rig));
  bad = d;
  bad.fine_scale.probes[3].point = 0;  // not its row's point
  EXPECT_FALSE(Rig::Build(bad, &rig));
  bad = d;
  bad.fine_scale.probes[2].sides[0].v2 = 9999;
  EXPECT_FALSE(Rig::Build(bad, &rig));
  bad = d;
  bad.fine_scale.rest_amplitude = 1.5f;
  EXPECT_FALSE(Rig::Build(bad, &rig));
  bad = d;
  bad.fine_scale.probes.resize(4);  // fewer points than can change
  EXPECT_FALSE(Rig::Build(bad, &rig));
  EXPECT_TRUE(Rig::Build(d, &rig));
}

}  // namespace
}  // namespace mimetic
