// EvaluateJob: validity, zero allocation, determinism (rerun and 2-thread split), seams,
// strides, and normals/positions against hand-computed values.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "muscles/offline/waters.h"
#include "content/procedural.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/face_kernels.h"

// Global allocation counter for the zero-allocation test.
#include "alloc_counter.h"

namespace mimetic {
namespace {

Rig BuildOrDie(const RigSpec& spec, const MeshData& mesh) {
  Rig rig;
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  return rig;
}

struct Surface {
  MeshData mesh;
  RigSpec spec;
  Rig rig;
};

Surface MakeSurface(uint32_t side = 60, uint32_t muscles = 6) {
  Surface s;
  s.mesh = MakeSurfaceMesh(side, side, 100.f, 100.f, 10.f);
  s.spec = MakeSurfaceRigSpec(muscles, 100.f, 100.f, 10.f, 0.15f, 3.f);
  s.rig = BuildOrDie(s.spec, s.mesh);
  return s;
}

std::vector<float> SomeActivations(const Rig& rig) {
  std::vector<float> a(rig.muscle_count());
  for (size_t m = 0; m < a.size(); ++m) a[m] = 0.2f + 0.13f * float(m % 6);
  return a;
}

EvaluateJob MakeJob(const Rig& rig, EvaluateContext* ctx, span<const float> act,
                    std::vector<float>* pos, std::vector<float>* nrm) {
  pos->assign(3 * rig.vertex_count(), 0.f);
  nrm->assign(3 * rig.vertex_count(), 0.f);
  EvaluateJob job;
  job.rig = &rig;
  job.context = ctx;
  job.activations = act;
  job.out_positions = *pos;
  job.out_normals = *nrm;
  return job;
}

TEST(EvaluateJob, ValidityTable) {
  const Surface s = MakeSurface(20, 4);
  const Surface other = MakeSurface(20, 4);  // same sizes, different rig
  EvaluateContext ctx(s.rig), other_ctx(other.rig);
  const std::vector<float> act = SomeActivations(s.rig);
  std::vector<float> pos, nrm;
  const EvaluateJob good = MakeJob(s.rig, &ctx, act, &pos, &nrm);
  EXPECT_TRUE(good.Validate());
  const size_t n3 = 3 * s.rig.vertex_count();

  EvaluateJob j = good;
  j.rig = nullptr;
  EXPECT_FALSE(j.Validate()) << "null rig";
  j = good;
  j.context = nullptr;
  EXPECT_FALSE(j.Validate()) << "null context";
  j = good;
  j.context = &other_ctx;
  EXPECT_FALSE(j.Validate()) << "context sized for another rig";
  EvaluateContext empty_ctx;
  j = good;
  j.context = &empty_ctx;
  EXPECT_FALSE(j.Validate()) << "context never sized";
  j = good;
  j.activations = good.activations.first(act.size() - 1);
  EXPECT_FALSE(j.Validate()) << "activations one short";
  j = good;
  j.out_positions = good.out_positions.first(n3 - 1);
  EXPECT_FALSE(j.Validate()) << "positions one float short";
  j = good;
  j.out_normals = good.out_normals.first(n3 - 1);
  EXPECT_FALSE(j.Validate()) << "normals one float short";
  j = good;
  j.out_normals = {};
  EXPECT_TRUE(j.Validate()) << "normals are optional";
  j = good;
  j.out_positions_stride = 8;
  EXPECT_FALSE(j.Validate()) << "stride below 12";
  j = good;
  j.out_normals_stride = 14;
  EXPECT_FALSE(j.Validate()) << "stride not a multiple of 4";
  j = good;
  j.out_positions_stride = 16;
  EXPECT_FALSE(j.Validate()) << "stride 16 needs more room";

  // Invalid jobs leave the outputs untouched.
  std::fill(pos.begin(), pos.end(), 42.f);
  j = good;
  j.activations = good.activations.first(act.size() - 1);
  EXPECT_FALSE(j.Run());
  for (float f : pos) ASSERT_EQ(f, 42.f);
}

TEST(EvaluateJob, NoAllocationOver100Runs) {
  const Surface s = MakeSurface(40, 6);
  EvaluateContext ctx(s.rig);
  std::vector<float> act = SomeActivations(s.rig);
  std::vector<float> pos, nrm;
  const EvaluateJob job = MakeJob(s.rig, &ctx, act, &pos, &nrm);
  ASSERT_TRUE(job.Run());
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) {
    act[i % act.size()] = float(i % 10) / 10.f;
    ASSERT_TRUE(job.Run());
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

TEST(EvaluateJob, BitIdenticalOnRerun) {
  const Surface s = MakeSurface(50, 8);
  EvaluateContext ctx(s.rig);
  const std::vector<float> act = SomeActivations(s.rig);
  std::vector<float> pos1, nrm1, pos2, nrm2;
  ASSERT_TRUE(MakeJob(s.rig, &ctx, act, &pos1, &nrm1).Run());
  EvaluateContext ctx2(s.rig);
  ASSERT_TRUE(MakeJob(s.rig, &ctx2, act, &pos2, &nrm2).Run());
  EXPECT_EQ(std::memcmp(pos1.data(), pos2.data(), pos1.size() * 4), 0);
  EXPECT_EQ(std::memcmp(nrm1.data(), nrm2.data(), nrm1.size() * 4), 0);
}

// Splits every stage into two halves run on two threads.
void TwoThreads(void*, uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
  const uint32_t mid = count / 2 + 7 < count ? count / 2 + 7 : count / 2;  // uneven on purpose
  std::thread t([&] { task(data, 0, mid); });
  task(data, mid, count);
  t.join();
}

TEST(EvaluateJob, BitIdenticalWhenSplitAcrossTwoThreads) {
  const Surface s = MakeSurface(70, 10);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c2(s.rig);
  std::vector<float> pos1, nrm1, pos2, nrm2;
  ASSERT_TRUE(MakeJob(s.rig, &c1, act, &pos1, &nrm1).Run());
  EvaluateJob threaded = MakeJob(s.rig, &c2, act, &pos2, &nrm2);
  threaded.parallel_for = TwoThreads;
  threaded.parallel_min_count = 1;  // split every loop, however short
  ASSERT_TRUE(threaded.Run());
  EXPECT_EQ(std::memcmp(pos1.data(), pos2.data(), pos1.size() * 4), 0);
  EXPECT_EQ(std::memcmp(nrm1.data(), nrm2.data(), nrm1.size() * 4), 0);
}

// A scheduler that records the loop sizes it is handed, then splits like TwoThreads.
struct CountingScheduler {
  std::vector<uint32_t> counts;
  static void Run(void* user, uint32_t count, void (*task)(void*, uint32_t, uint32_t),
                  void* data) {
    static_cast<CountingScheduler*>(user)->counts.push_back(count);
    TwoThreads(nullptr, count, task, data);
  }
};

TEST(EvaluateJob, ShortLoopsStayOnTheCallingThreadWithTheSameBits) {
  const Surface s = MakeSurface(100, 10);  // 10,000 points: some loops above the minimum
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c2(s.rig);
  std::vector<float> pos1, nrm1, pos2, nrm2;
  ASSERT_TRUE(MakeJob(s.rig, &c1, act, &pos1, &nrm1).Run());
  EvaluateJob threaded = MakeJob(s.rig, &c2, act, &pos2, &nrm2);
  CountingScheduler scheduler;
  threaded.parallel_for = &CountingScheduler::Run;
  threaded.parallel_for_user = &scheduler;
  ASSERT_EQ(threaded.parallel_min_count, kParallelMinCount);
  ASSERT_TRUE(threaded.Run());
  ASSERT_FALSE(scheduler.counts.empty());  // the vertex scatter alone has 10,000 items
  for (uint32_t n : scheduler.counts) EXPECT_GE(n, kParallelMinCount);
  EXPECT_EQ(std::memcmp(pos1.data(), pos2.data(), pos1.size() * 4), 0);
  EXPECT_EQ(std::memcmp(nrm1.data(), nrm2.data(), nrm1.size() * 4), 0);
}

TEST(EvaluateJob, ZeroActivationReturnsRestPositionsBitForBit) {
  const Surface s = MakeSurface(30, 6);
  EvaluateContext ctx(s.rig);
  const std::vector<float> zero(s.rig.muscle_count(), 0.f);
  std::vector<float> pos, nrm;
  ASSERT_TRUE(MakeJob(s.rig, &ctx, zero, &pos, &nrm).Run());
  EXPECT_EQ(std::memcmp(pos.data(), s.mesh.positions.data(), pos.size() * 4), 0);
}

TEST(EvaluateJob, PositionsMatchDirectMuscleFormulas) {
  const Surface s = MakeSurface(45, 6);
  EvaluateContext ctx(s.rig);
  const std::vector<float> act = SomeActivations(s.rig);
  std::vector<float> pos, nrm;
  EvaluateJob job = MakeJob(s.rig, &ctx, act, &pos, &nrm);
  job.layers = {false, false, false};  // muscles only (docs/model.md §1 step 1)
  ASSERT_TRUE(job.Run());
  size_t moved = 0;
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
    float3 expect = s.mesh.positions[v];
    for (size_t m = 0; m < s.spec.muscles.size(); ++m)
      expect += MuscleDisplacement(s.spec.muscles[m], s.mesh.positions[v],
                                   act[m] * s.spec.muscles[m].strength);
    ASSERT_NEAR(pos[3 * v], expect.x, 1e-5f);
    ASSERT_NEAR(pos[3 * v + 1], expect.y, 1e-5f);
    ASSERT_NEAR(pos[3 * v + 2], expect.z, 1e-5f);
    moved += Length(expect - s.mesh.positions[v]) > 1e-3f;
  }
  EXPECT_GT(moved, s.mesh.vertex_count() / 10);
}

// Two triangles sharing edge AB, hand-computed area-weighted normals:
//   ABC: (B-A) x (C-A) = (1,0,0) x (0,1,0) = (0,0,1)
//   ADB: (D-A) x (B-A) = (0,-2,2) x (1,0,0) = (0,2,2)
// A and B: (0,2,3)/sqrt(13); C: (0,0,1); D: (0,1,1)/sqrt(2).
TEST(EvaluateJob, AreaWeightedNormalsByHand) {
  MeshData mesh;
  mesh.source = "two triangles";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -2, 2}};
  mesh.indices = {0, 1, 2, 0, 3, 1};
  RigSpec spec;
  spec.units = "mm";
  const Rig rig = BuildOrDie(spec, mesh);
  EvaluateContext ctx(rig);
  std::vector<float> pos, nrm;
  ASSERT_TRUE(MakeJob(rig, &ctx, {}, &pos, &nrm).Run());
  const double s13 = std::sqrt(13.0), s2 = std::sqrt(2.0);
  const double expect[4][3] = {{0, 2 / s13, 3 / s13}, {0, 2 / s13, 3 / s13}, {0, 0, 1}, {0, 1 / s2, 1 / s2}};
  for (int v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(nrm[3 * v + c], expect[v][c], 1e-6) << v << "," << c;
}

// A strip split at a UV seam: the duplicated vertices must come out identical (no crack),
// and an interleaved output (stride 32 bytes) leaves the other floats alone.
TEST(EvaluateJob, SeamVerticesStayTogetherAndStridesAreHonoured) {
  Surface s = MakeSurface(21, 4);
  // Duplicate column 10 of the grid as a seam: triangles right of it use the copies.
  const uint32_t side = 21;
  MeshData mesh = s.mesh;
  std::vector<uint32_t> copy_of(mesh.vertex_count(), UINT32_MAX);
  for (uint32_t j = 0; j < side; ++j) {
    const uint32_t v = j * side + 10;
    copy_of[v] = uint32_t(mesh.positions.size());
    mesh.positions.push_back(mesh.positions[v]);
    mesh.uvs.push_back({1.f, mesh.uvs[v].y});
  }
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    uint32_t* tri = &mesh.indices[3 * t];
    const float cx = (mesh.positions[tri[0]].x + mesh.positions[tri[1]].x + mesh.positions[tri[2]].x) / 3;
    if (cx > mesh.positions[10].x)
      for (int k = 0; k < 3; ++k)
        if (copy_of[tri[k]] != UINT32_MAX) tri[k] = copy_of[tri[k]];
  }
  const Rig rig = BuildOrDie(s.spec, mesh);
  ASSERT_EQ(rig.vertex_count(), side * side + side);
  ASSERT_EQ(rig.point_count(), side * side);
  EvaluateContext ctx(rig);
  const std::vector<float> act = SomeActivations(rig);
  std::vector<float> inter(8 * rig.vertex_count(), -7.f);  // pos(3) normal(3) uv(2)
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = span<float>(inter);
  job.out_positions_stride = 32;
  job.out_normals = span<float>(inter).subspan(3);
  job.out_normals_stride = 32;
  ASSERT_TRUE(job.Run());
  for (uint32_t j = 0; j < side; ++j) {
    const uint32_t a = j * side + 10, b = copy_of[a];
    EXPECT_EQ(std::memcmp(&inter[8 * a], &inter[8 * b], 6 * sizeof(float)), 0) << "row " << j;
  }
  for (uint32_t v = 0; v < rig.vertex_count(); ++v) {
    ASSERT_EQ(inter[8 * v + 6], -7.f);
    ASSERT_EQ(inter[8 * v + 7], -7.f);
  }
}

// ---------------------------------------------------------------------------------------------
// The eyeballs the lids slide on (docs/model.md §24).

// A sphere under the surface, off to one side (so the muscles' motion along the surface changes
// the points' distance from its centre): its surface 1 unit below the nearest surface point,
// so the band [2, 12] holds a patch of points fully and fades out around it.
struct EyeSurface {
  Surface plain;  // the same spec without eyes
  Surface eyes;
  float3 center;
  float radius = 0.f;
  float band[2] = {2.f, 12.f};
};

EyeSurface MakeEyeSurface(bool skin = false, uint32_t side = 40) {
  EyeSurface e;
  e.plain.mesh = MakeSurfaceMesh(side, side, 100.f, 100.f, 10.f);
  e.plain.spec = MakeSurfaceRigSpec(6, 100.f, 100.f, 10.f, 0.4f, 3.f);
  if (skin) AddEverySkinLayer(&e.plain.spec);
  e.plain.rig = BuildOrDie(e.plain.spec, e.plain.mesh);
  e.center = {25.f, 0.f, -25.f};
  float nearest = std::numeric_limits<float>::infinity();
  for (const float3& p : e.plain.mesh.positions) nearest = std::min(nearest, Length(p - e.center));
  e.radius = nearest - 1.f;
  e.eyes.mesh = e.plain.mesh;
  e.eyes.spec = e.plain.spec;
  EyesSpec eyes;
  eyes.spheres = {{e.center, e.radius}};
  eyes.band[0] = e.band[0];
  eyes.band[1] = e.band[1];
  e.eyes.spec.eyes = eyes;
  e.eyes.rig = BuildOrDie(e.eyes.spec, e.eyes.mesh);
  return e;
}

// The band's weight from docs/model.md §24, in double: 1 within b0, 0 beyond b1, the
// smoothstep 3t^2 - 2t^3 of t = (b1 - d) / (b1 - b0) between.
double SlideWeight(double d, double b0, double b1) {
  if (d <= b0) return 1.0;
  if (d >= b1) return 0.0;
  const double t = (b1 - d) / (b1 - b0);
  return t * t * (3.0 - 2.0 * t);
}

TEST(EvaluateJobEyes, MovedPointsInTheBandKeepTheirWeightedRestDistanceFromTheEyeball) {
  const EyeSurface e = MakeEyeSurface();
  ASSERT_FALSE(e.eyes.rig.eyes().empty());
  const std::vector<float> act = SomeActivations(e.plain.rig);
  EvaluateContext c1(e.plain.rig), c2(e.eyes.rig);
  std::vector<float> plain, slid, n1, n2;
  EvaluateJob a = MakeJob(e.plain.rig, &c1, act, &plain, &n1);
  a.layers = {false, false, false};
  ASSERT_TRUE(a.Run());
  EvaluateJob b = MakeJob(e.eyes.rig, &c2, act, &slid, &n2);
  b.layers = {false, false, false};
  ASSERT_TRUE(b.Run());
  size_t full = 0, partial = 0, outside = 0;
  for (size_t v = 0; v < e.plain.mesh.vertex_count(); ++v) {
    const float3 x0 = e.plain.mesh.positions[v];
    const float3 x{plain[3 * v], plain[3 * v + 1], plain[3 * v + 2]};
    const float3 got{slid[3 * v], slid[3 * v + 1], slid[3 * v + 2]};
    const double r0 = Length(x0 - e.center);
    const double w = SlideWeight(r0 - e.radius, e.band[0], e.band[1]);
    const bool moved = std::memcmp(&x, &x0, sizeof x) != 0;
    if (w == 0.0 || !moved) {  // the muscles' own position, bit for bit
      ASSERT_EQ(std::memcmp(&got, &x, sizeof x), 0) << v;
      ++outside;
      continue;
    }
    // x + w (c + (x - c) r0 / |x - c| - x), in double.
    const double d[3] = {double(x.x) - e.center.x, double(x.y) - e.center.y,
                         double(x.z) - e.center.z};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double want[3] = {x.x + w * (d[0] * r0 / len - d[0]), x.y + w * (d[1] * r0 / len - d[1]),
                            x.z + w * (d[2] * r0 / len - d[2])};
    ASSERT_NEAR(got.x, want[0], 1e-3) << v;
    ASSERT_NEAR(got.y, want[1], 1e-3) << v;
    ASSERT_NEAR(got.z, want[2], 1e-3) << v;
    if (w == 1.0) {
      ASSERT_NEAR(Length(got - e.center), r0, 1e-3) << v;  // on its rest sphere
      if (std::fabs(len - r0) > 0.05) ++full;  // and the muscles had moved it off it
    } else {
      ++partial;
    }
  }
  EXPECT_GT(full, 5u) << partial << " partly held, " << outside << " untouched";
  EXPECT_GT(partial, 20u) << full;
  EXPECT_GT(outside, e.plain.mesh.vertex_count() / 2);
}

TEST(EvaluateJobEyes, RestStaysBitForBitAndSplitsAndRerunsGiveTheSameBitsWithoutAllocating) {
  const EyeSurface e = MakeEyeSurface(true);
  ASSERT_FALSE(e.eyes.rig.eyes().empty());
  const std::vector<float> zero(e.eyes.rig.muscle_count(), 0.f);
  EvaluateContext c0(e.eyes.rig), cp(e.plain.rig);
  std::vector<float> rest, n0, plain, np;
  EvaluateJob still = MakeJob(e.eyes.rig, &c0, zero, &rest, &n0);
  still.layers = {false, false, false};
  ASSERT_TRUE(still.Run());
  for (size_t v = 0; v < e.eyes.mesh.vertex_count(); ++v)
    ASSERT_EQ(std::memcmp(&rest[3 * v], &e.eyes.mesh.positions[v], 12), 0) << v;
  // Every layer on (the curve wrinkles' rest amplitude moves the surface): the same bits as
  // the rig without eyes (at rest r = 1, so the thinned thickness changes nothing either).
  ASSERT_TRUE(MakeJob(e.eyes.rig, &c0, zero, &rest, &n0).Run());
  ASSERT_TRUE(MakeJob(e.plain.rig, &cp, zero, &plain, &np).Run());
  EXPECT_EQ(std::memcmp(rest.data(), plain.data(), rest.size() * 4), 0);
  EXPECT_EQ(std::memcmp(n0.data(), np.data(), n0.size() * 4), 0);
  const std::vector<float> act = SomeActivations(e.eyes.rig);
  EvaluateContext c1(e.eyes.rig), c2(e.eyes.rig);
  std::vector<float> pos1, nrm1, pos2, nrm2;
  EvaluateJob serial = MakeJob(e.eyes.rig, &c1, act, &pos1, &nrm1);
  ASSERT_TRUE(serial.Run());
  EvaluateJob threaded = MakeJob(e.eyes.rig, &c2, act, &pos2, &nrm2);
  threaded.parallel_for = TwoThreads;
  threaded.parallel_min_count = 1;
  ASSERT_TRUE(threaded.Run());
  EXPECT_EQ(std::memcmp(pos1.data(), pos2.data(), pos1.size() * 4), 0);
  EXPECT_EQ(std::memcmp(nrm1.data(), nrm2.data(), nrm1.size() * 4), 0);
  const long before = g_allocations.load();
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(serial.Run());
  EXPECT_EQ(g_allocations.load() - before, 0);
}

TEST(EvaluateJobEyes, TheBuilderListsMovedPointsOfTheBandAndThinsTheirThickness) {
  const EyeSurface e = MakeEyeSurface(true);
  const Rig& rig = e.eyes.rig;
  const RigEyes& eyes = rig.eyes();
  ASSERT_EQ(eyes.centers.size(), 1u);
  EXPECT_EQ(std::memcmp(&eyes.centers[0], &e.center, sizeof e.center), 0);
  // Same spec but for the eyes: the same points in the same order.
  ASSERT_EQ(rig.point_count(), e.plain.rig.point_count());
  size_t listed = 0;
  for (uint32_t p = 0; p < rig.point_count(); ++p) {
    const float3 x = rig.rest_points()[p];
    const double r0 = Length(x - e.center);
    const double w = SlideWeight(r0 - e.radius, e.band[0], e.band[1]);
    const auto it = std::lower_bound(eyes.points.begin(), eyes.points.end(), p);
    const bool in = it != eyes.points.end() && *it == p;
    const bool moved = rig.muscles().offsets[p + 1] > rig.muscles().offsets[p];
    ASSERT_EQ(in, moved && w > 0.0) << p;
    const float h = e.plain.rig.point_thickness()[p];
    if (!in) {
      ASSERT_EQ(rig.point_thickness()[p], h) << p;
      continue;
    }
    const size_t i = size_t(it - eyes.points.begin());
    ASSERT_NEAR(eyes.weights[i], w, 1e-5) << p;
    ASSERT_NEAR(eyes.radii[i], r0, 1e-4) << p;
    ASSERT_NEAR(rig.point_thickness()[p], h * (1.0 - w), 1e-5) << p;
    ++listed;
  }
  EXPECT_GT(listed, 30u);
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

// One muscle reaching a corner of the sheet: the rig orders points so that a frame only
// touches what can move. Every output vertex, moved or not, must still equal an independent
// full computation: rest + the direct Waters formula, and area-weighted normals summed here in
// double over every triangle.
TEST(EvaluateJob, PartialCoverageMatchesAFullIndependentComputation) {
  const MeshData mesh = MakeSurfaceMesh(40, 40, 100.f, 100.f, 10.f);
  RigSpec spec;
  spec.units = "mm";
  MuscleSpec m;
  m.name = "corner";
  m.type = MuscleType::kLinear;
  m.strength = 6.f;
  m.linear.attachment = {45.f, 45.f, -2.f};
  m.linear.insertion = {20.f, 20.f, 5.f};
  m.linear.zone_angle = 0.5f;
  m.linear.falloff_start = 15.f;
  m.linear.falloff_end = 35.f;
  spec.muscles.push_back(m);
  const Rig rig = BuildOrDie(spec, mesh);
  ASSERT_GT(rig.active_point_count(), 0u);
  ASSERT_LT(rig.normal_point_count(), rig.point_count() / 2) << "most of the sheet is static";
  EvaluateContext ctx(rig);
  const std::vector<float> act = {0.9f};
  std::vector<float> pos, nrm;
  ASSERT_TRUE(MakeJob(rig, &ctx, act, &pos, &nrm).Run());

  const size_t nv = mesh.vertex_count();
  std::vector<float3> expect(nv);
  for (size_t v = 0; v < nv; ++v)
    expect[v] = mesh.positions[v] + MuscleDisplacement(m, mesh.positions[v], 0.9f * m.strength);
  std::vector<double> n(3 * nv, 0.0);
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t* i = &mesh.indices[3 * t];
    const double ax = expect[i[1]].x - expect[i[0]].x, ay = expect[i[1]].y - expect[i[0]].y,
                 az = expect[i[1]].z - expect[i[0]].z;
    const double bx = expect[i[2]].x - expect[i[0]].x, by = expect[i[2]].y - expect[i[0]].y,
                 bz = expect[i[2]].z - expect[i[0]].z;
    const double c[3] = {ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) n[3 * i[k] + d] += c[d];
  }
  size_t moved = 0;
  for (size_t v = 0; v < nv; ++v) {
    const double len = std::sqrt(n[3 * v] * n[3 * v] + n[3 * v + 1] * n[3 * v + 1] + n[3 * v + 2] * n[3 * v + 2]);
    for (int d = 0; d < 3; ++d) {
      ASSERT_NEAR(pos[3 * v + d], (&expect[v].x)[d], 1e-5) << "vertex " << v;
      ASSERT_NEAR(nrm[3 * v + d], n[3 * v + d] / len, 2e-5) << "vertex " << v;
    }
    moved += Length(expect[v] - mesh.positions[v]) > 1e-3f;
  }
  EXPECT_GT(moved, 20u);
  // A second frame at rest gives the rest pose back exactly (the moved range is rewritten).
  const std::vector<float> zero = {0.f};
  ASSERT_TRUE(MakeJob(rig, &ctx, zero, &pos, &nrm).Run());
  EXPECT_EQ(std::memcmp(pos.data(), mesh.positions.data(), pos.size() * 4), 0);
}

template <class T>
size_t VectorBytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// Rig::ByteSize and EvaluateContext::ByteSize against sums written out here member by member.
TEST(EvaluateJob, ByteSizeCountsEveryOwnedVector) {
  const Surface s = MakeSurface(12, 3);
  const Rig& rig = s.rig;
  ASSERT_TRUE(rig.tables_checked());
  size_t expect = sizeof(Rig);
  const RigData& d = rig.data();
  expect += VectorBytes(d.rest_points) + VectorBytes(d.triangles) +
            VectorBytes(d.point_triangle_offsets) + VectorBytes(d.point_triangles) +
            VectorBytes(d.vertex_points) + VectorBytes(d.vertex_indices) +
            VectorBytes(d.vertex_uvs) + VectorBytes(d.point_thickness) +
            VectorBytes(d.rest_triangle_areas) + VectorBytes(d.muscle_names) +
            VectorBytes(d.muscles.offsets) + VectorBytes(d.muscles.entries) +
            VectorBytes(d.muscle_wrinkles);
  for (const RigMuscleWrinkles& w : d.muscle_wrinkles)
    expect += VectorBytes(w.points) + VectorBytes(w.phase) + VectorBytes(w.attenuation) +
              VectorBytes(w.profile) + VectorBytes(w.edge_offsets) +
              VectorBytes(w.edge_neighbors) + VectorBytes(w.edge_rest_lengths) +
              VectorBytes(w.edge_weights);
  const RigCurveWrinkles& c = d.curve_wrinkles;
  expect += VectorBytes(c.names) + VectorBytes(c.wrinkles) + VectorBytes(c.points) +
            VectorBytes(c.offsets) + VectorBytes(c.entries) + VectorBytes(c.probes);
  expect += VectorBytes(d.fine_scale.probes);
  const RigTables& t = rig.tables();
  expect += VectorBytes(t.rest_faces) + VectorBytes(t.rest_point_normals) +
            VectorBytes(t.edge_pairs) + VectorBytes(t.row_offsets) + VectorBytes(t.entry_edges) +
            VectorBytes(t.entry_rest) + VectorBytes(t.entry_coeffs) +
            VectorBytes(t.row_profiles) + VectorBytes(t.row_muscles) + VectorBytes(t.probe_edges) +
            VectorBytes(t.point_row_offsets) + VectorBytes(t.point_curve_offsets) +
            VectorBytes(t.point_curve_rows) + VectorBytes(t.wrinkle_points) +
            VectorBytes(t.point_neighbor_offsets) + VectorBytes(t.point_neighbors) +
            VectorBytes(t.point_neighbor_edges) + VectorBytes(t.neighbor_edge_pairs) +
            VectorBytes(t.fine_edge_pairs) + VectorBytes(t.fine_probe_edges) +
            VectorBytes(t.fine_probe_params);
  EXPECT_EQ(rig.ByteSize(), expect);
  // One neighbour slot per edge end at an active point (edges counted from the triangles).
  EXPECT_EQ(t.point_neighbor_offsets.size(), size_t(rig.active_point_count()) + 1);
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (uint32_t k = 0; k < rig.triangle_count(); ++k)
    for (int j = 0; j < 3; ++j) {
      const uint32_t a = d.triangles[3 * k + j], b = d.triangles[3 * k + (j + 1) % 3];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  size_t ends = 0;
  for (const auto& [a, b] : edges) ends += (a < rig.active_point_count()) + (b < rig.active_point_count());
  EXPECT_EQ(t.point_neighbors.size(), ends);
  EXPECT_EQ(t.point_neighbors.size(), size_t(t.point_neighbor_offsets.back()));
  // The limiter's edges: each edge with an active end once, and each slot names its own edge.
  size_t active_edges = 0;
  for (const auto& [a, b] : edges) active_edges += a < rig.active_point_count() || b < rig.active_point_count();
  EXPECT_EQ(t.neighbor_edge_count(), active_edges);
  ASSERT_EQ(t.point_neighbor_edges.size(), t.point_neighbors.size());
  std::set<std::pair<uint32_t, uint32_t>> named;
  for (uint32_t p = 0; p < rig.active_point_count(); ++p)
    for (uint32_t k = t.point_neighbor_offsets[p]; k < t.point_neighbor_offsets[p + 1]; ++k) {
      const uint32_t e = t.point_neighbor_edges[k], q = t.point_neighbors[k];
      ASSERT_LT(e, t.neighbor_edge_count());
      const uint32_t a = t.neighbor_edge_pairs[2 * e], b = t.neighbor_edge_pairs[2 * e + 1];
      EXPECT_EQ(std::min(a, b), std::min(p, q)) << "point " << p << " slot " << k;
      EXPECT_EQ(std::max(a, b), std::max(p, q)) << "point " << p << " slot " << k;
      named.insert({std::min(a, b), std::max(a, b)});
    }
  EXPECT_EQ(named.size(), active_edges) << "every edge named by a slot";
  EXPECT_GE(rig.ByteSize(), sizeof(Rig) + 12 * rig.point_count() + 16 * rig.triangle_count());

  // The context: per-frame scratch only, sized from the rig's counts.
  const EvaluateContext ctx(rig);
  const size_t P = rig.point_count(), T = rig.triangle_count(), M = rig.muscle_count();
  const size_t E = t.edge_count(), NE = t.neighbor_edge_count();
  // activations, the muscles' wrinkle gates, points (+1 pad), faces, ratios, compressions, fine-scale amplitudes (2 per
  // point), fine-scale edge lengths (+1: the length-1 slot), sums, edge lengths, wrinkle offsets; the fold
  // limiter's two offset buffers (+1 each), X1 and X3 copies, levels, per-triangle limits,
  // flags, the smallest slope bound per point, the one-rings' edge lengths; its worklists over the active points (three
  // lists, marks) and triangles (list, marks, verdicts)
  const size_t A = rig.active_point_count(), AT = rig.active_triangle_count();
  EXPECT_EQ(ctx.ByteSize(), sizeof(EvaluateContext) + 4 * M + 4 * M + 12 * (P + 1) + 16 * T + 4 * P + 4 * P +
                                8 * P + 4 * (t.fine_edge_count() + 1) + 16 * P + 4 * E + 4 * P + 2 * 4 * (P + 1) + 2 * 12 * P + P +
                                4 * T + P + 4 * P + 4 * NE + 3 * 4 * A + A + 4 * AT + AT + AT);
}

// The limiter measures each one-ring edge once (RigTables::neighbor_edge_pairs, EdgeLengths)
// and reads the length from both ends; its shortcuts and slope bound rely on that length being
// the bits of sqrt((x^2 + y^2) + z^2) of X1q - X1p taken from either end, as the full scan
// computes it. Checked on a moved, irregular surface, slot by slot.
TEST(EvaluateJob, NeighborEdgeLengthsAreEachEndsBits) {
  const Surface s = MakeSurface(12, 3);
  const Rig& rig = s.rig;
  const RigTables& t = rig.tables();
  ASSERT_GT(t.neighbor_edge_count(), 0u);
  std::vector<float3> x(rig.point_count() + 1);  // padded (kPointPadFloats)
  uint32_t seed = 12345;
  auto jitter = [&]() {
    seed = seed * 1664525u + 1013904223u;
    return (float(seed >> 8) / float(1u << 24) - 0.5f) * 0.37f;
  };
  for (uint32_t p = 0; p < rig.point_count(); ++p) {
    const float3 r = rig.rest_points()[p];
    x[p] = float3{r.x * 1.7f + jitter(), r.y * 0.61f + jitter(), r.z * 3.3f + jitter()};
  }
  std::vector<float> lengths(t.neighbor_edge_count());
  EdgeLengths(x.data(), t.neighbor_edge_pairs.data(), 0, t.neighbor_edge_count(), lengths.data());
  size_t slots = 0;
  for (uint32_t p = 0; p < rig.active_point_count(); ++p)
    for (uint32_t k = t.point_neighbor_offsets[p]; k < t.point_neighbor_offsets[p + 1]; ++k) {
      const float3 e = x[t.point_neighbors[k]] - x[p];
      const float by_hand = std::sqrt((e.x * e.x + e.y * e.y) + e.z * e.z);
      const float read = lengths[t.point_neighbor_edges[k]];
      uint32_t a, b;
      std::memcpy(&a, &by_hand, 4);
      std::memcpy(&b, &read, 4);
      EXPECT_EQ(a, b) << "point " << p << ", neighbour " << t.point_neighbors[k];
      ++slots;
    }
  EXPECT_EQ(slots, t.point_neighbors.size());
}

// A Rig cannot be copied; an edited rig is a new rig (new uid, checked again), and a context
// sized for the original refuses it. Corrupt data fails the check: no context accepts it.
TEST(EvaluateJob, EditedRigIsANewRig) {
  static_assert(!std::is_copy_constructible_v<Rig> && !std::is_copy_assignable_v<Rig>);
  static_assert(std::is_nothrow_move_constructible_v<Rig>);
  Surface s = MakeSurface(12, 3);
  const uint64_t uid = s.rig.uid();
  EXPECT_NE(uid, 0u);
  EvaluateContext ctx(s.rig);
  EXPECT_TRUE(ctx.IsFor(s.rig));
  Rig moved = std::move(s.rig);
  EXPECT_EQ(moved.uid(), uid) << "the uid moves with the rig";
  EXPECT_TRUE(ctx.IsFor(moved));
  EXPECT_FALSE(ctx.IsFor(s.rig)) << "moved-from";

  RigData edited = moved.data();
  edited.rest_points[0].z += 1.f;
  Rig again;
  ASSERT_TRUE(Rig::Build(edited, &again));
  EXPECT_NE(again.uid(), uid);
  EXPECT_FALSE(ctx.IsFor(again)) << "a context of the original refuses the edited copy";

  RigData corrupt = moved.data();
  corrupt.triangles[0] = moved.point_count();  // out of range
  Rig bad;
  EXPECT_FALSE(Rig::Build(corrupt, &bad));
  EXPECT_FALSE(bad.tables_checked());
  EvaluateContext bad_ctx(bad);
  EXPECT_FALSE(bad_ctx.IsFor(bad));
  const std::vector<float> act = SomeActivations(bad);
  std::vector<float> pos, nrm;
  EXPECT_FALSE(MakeJob(bad, &bad_ctx, act, &pos, &nrm).Validate());
}

// RigTables::point_triangles_exact (the fold limiter's worklist relies on it, docs/model.md
// §16): true for the builder's adjacency; false when an active point's list is out of order,
// repeats a triangle, or names one without the point; the rig still builds.
TEST(EvaluateJob, PointTrianglesExactOnlyForTheTrueAdjacency) {
  const Surface s = MakeSurface(12, 3);
  ASSERT_GT(s.rig.active_point_count(), 0u);
  EXPECT_TRUE(s.rig.tables().point_triangles_exact);
  // An active point with at least two triangles, and a triangle that does not have it.
  const RigData& d = s.rig.data();
  uint32_t p = 0;
  while (d.point_triangle_offsets[p + 1] - d.point_triangle_offsets[p] < 2) ++p;
  ASSERT_LT(p, s.rig.active_point_count());
  const uint32_t lo = d.point_triangle_offsets[p], hi = d.point_triangle_offsets[p + 1];
  uint32_t other = 0;
  while (d.triangles[3 * other] == p || d.triangles[3 * other + 1] == p ||
         d.triangles[3 * other + 2] == p)
    ++other;
  for (int edit = 0; edit < 3; ++edit) {
    RigData e = d;
    if (edit == 0) std::swap(e.point_triangles[lo], e.point_triangles[lo + 1]);  // order
    if (edit == 1) e.point_triangles[lo + 1] = e.point_triangles[lo];            // repeat
    if (edit == 2) e.point_triangles[hi - 1] = other;                             // a stranger
    Rig r;
    ASSERT_TRUE(Rig::Build(e, &r)) << "edit " << edit;
    EXPECT_FALSE(r.tables().point_triangles_exact) << "edit " << edit;
  }
}

// --- the jaw (docs/model.md §18) --------------------------------------------------------------

// The surface with a jaw: hinge along +x (right condyle at -x) behind and above the sheet;
// explicit weights 1 below y = -10, 0 above y = 10, a smoothstep between.
constexpr double kJawRangeDeg = 20.0;
float SurfaceJawWeight(float3 p) {
  const float t = std::fmin(std::fmax((10.f - p.y) / 20.f, 0.f), 1.f);
  return t * t * (3.f - 2.f * t);
}
// `tilted`: the hinge leans out of +x (every component of the axis non-zero, so each term of
// the rotation contributes on every axis).
// `tilted`: the hinge is tilted and the jaw glides too (the lane-form test).
Surface MakeJawSurface(uint32_t side = 40, uint32_t muscles = 6, bool tilted = false) {
  Surface s;
  s.mesh = MakeSurfaceMesh(side, side, 100.f, 100.f, 10.f);
  s.spec = MakeSurfaceRigSpec(muscles, 100.f, 100.f, 10.f, 0.15f, 3.f);
  JawSpec jaw;
  jaw.condyles[0] = tilted ? float3{-60.f, 22.f, -47.f} : float3{-60.f, 30.f, -40.f};
  jaw.condyles[1] = tilted ? float3{60.f, 37.f, -33.f} : float3{60.f, 30.f, -40.f};
  jaw.range_deg = float(kJawRangeDeg);
  if (tilted) jaw.translation = float3{0.7f, -1.3f, 2.1f};  // and gliding
  for (const float3& p : s.mesh.positions) jaw.weights.push_back(SurfaceJawWeight(p));
  s.spec.jaw = jaw;
  s.rig = BuildOrDie(s.spec, s.mesh);
  return s;
}

// Rodrigues' rotation of x about the line through c along unit k by `angle` radians, in double.
float3 RotateAbout(float3 x, float3 c, float3 k, double angle) {
  const double v[3] = {double(x.x) - c.x, double(x.y) - c.y, double(x.z) - c.z};
  const double kk[3] = {k.x, k.y, k.z};
  const double cs = std::cos(angle), sn = std::sin(angle);
  const double kv[3] = {kk[1] * v[2] - kk[2] * v[1], kk[2] * v[0] - kk[0] * v[2],
                        kk[0] * v[1] - kk[1] * v[0]};
  const double kd = kk[0] * v[0] + kk[1] * v[1] + kk[2] * v[2];
  double r[3];
  for (int i = 0; i < 3; ++i) r[i] = v[i] * cs + kv[i] * sn + kk[i] * kd * (1 - cs);
  return {float(r[0] + c.x), float(r[1] + c.y), float(r[2] + c.z)};
}

TEST(EvaluateJobJaw, FullyWeightedPointsTurnByTheExactRotationZeroWeightedOnesStay) {
  const Surface s = MakeJawSurface();
  ASSERT_FALSE(s.rig.jaw().empty());
  EvaluateContext ctx(s.rig);
  const std::vector<float> zero(s.rig.muscle_count(), 0.f);
  std::vector<float> pos, nrm;
  EvaluateJob job = MakeJob(s.rig, &ctx, zero, &pos, &nrm);
  job.layers = {false, false, false};
  job.jaw = 0.75f;
  ASSERT_TRUE(job.Run());
  const float3 c{0.f, 30.f, -40.f}, k{1.f, 0.f, 0.f};
  const double angle = 0.75 * kJawRangeDeg * std::acos(-1.0) / 180.0;
  size_t full = 0, none = 0;
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
    const float3 x0 = s.mesh.positions[v];
    const float3 got{pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]};
    const float w = SurfaceJawWeight(x0);
    if (w == 1.f) {
      const float3 want = RotateAbout(x0, c, k, angle);
      ASSERT_NEAR(got.x, want.x, 1e-3f) << v;
      ASSERT_NEAR(got.y, want.y, 1e-3f) << v;
      ASSERT_NEAR(got.z, want.z, 1e-3f) << v;
      ++full;
    } else if (w == 0.f) {
      ASSERT_EQ(std::memcmp(&got, &x0, sizeof got), 0) << "zero weight moved: vertex " << v;
      ++none;
    } else {  // partly carried: its own weighted angle
      const float3 want = RotateAbout(x0, c, k, double(w) * angle);
      ASSERT_NEAR(Length(got - want), 0.f, 1e-3f) << v;
    }
  }
  EXPECT_GT(full, s.mesh.vertex_count() / 4);
  EXPECT_GT(none, s.mesh.vertex_count() / 4);
  // Opening (a positive angle about right -> left) moves the chin side down and back.
  const float3 chin{0.f, -50.f, 10.f};
  const float3 turned = RotateAbout(chin, c, k, angle);
  EXPECT_LT(turned.y, chin.y);
  EXPECT_LT(turned.z, chin.z);
}

// The glide (docs/model.md §18): X' = c + R(w jaw range)(X - c) + w jaw T, T the rig's
// translation; computed here in double from the equation.
TEST(EvaluateJobJaw, TheGlideMovesEachPointByItsWeightTimesTheJawTimesTheTranslation) {
  Surface s;
  s.mesh = MakeSurfaceMesh(30, 30, 100.f, 100.f, 10.f);
  s.spec = MakeSurfaceRigSpec(4, 100.f, 100.f, 10.f, 0.15f, 3.f);
  JawSpec jaw;
  jaw.condyles[0] = {-60.f, 30.f, -40.f};
  jaw.condyles[1] = {60.f, 30.f, -40.f};
  jaw.range_deg = float(kJawRangeDeg);
  jaw.translation = {0.5f, -6.f, 3.f};
  for (const float3& p : s.mesh.positions) jaw.weights.push_back(SurfaceJawWeight(p));
  s.spec.jaw = jaw;
  s.rig = BuildOrDie(s.spec, s.mesh);
  EvaluateContext ctx(s.rig);
  const std::vector<float> zero(s.rig.muscle_count(), 0.f);
  std::vector<float> pos, nrm;
  EvaluateJob job = MakeJob(s.rig, &ctx, zero, &pos, &nrm);
  job.layers = {false, false, false};
  job.jaw = 0.6f;
  ASSERT_TRUE(job.Run());
  const float3 c{0.f, 30.f, -40.f}, k{1.f, 0.f, 0.f};
  const double range = kJawRangeDeg * std::acos(-1.0) / 180.0;
  size_t full = 0, part = 0;
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
    const float3 x0 = s.mesh.positions[v];
    const double w = SurfaceJawWeight(x0);
    const float3 r = RotateAbout(x0, c, k, w * 0.6 * range);
    const float3 want{float(r.x + w * 0.6 * 0.5), float(r.y + w * 0.6 * -6.0),
                      float(r.z + w * 0.6 * 3.0)};
    const float3 got{pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]};
    ASSERT_NEAR(Length(got - want), 0.f, 1e-3f) << v;
    full += w == 1.0;
    part += w > 0.0 && w < 1.0;
  }
  EXPECT_GT(full, 0u);
  EXPECT_GT(part, 0u);
}

// The builder's jaw checks name the key and the expectation: a glide longer than the
// hinge-to-mouth distance (here |mouth - pivot| without its axis part: sqrt(30^2 + 50^2)), and
// explicit weights that are not one per vertex.
TEST(EvaluateJobJaw, TooLongAGlideAndAWrongWeightCountAreBuildErrors) {
  const MeshData mesh = MakeSurfaceMesh(8, 8, 100.f, 100.f, 10.f);
  RigSpec spec = MakeSurfaceRigSpec(2, 100.f, 100.f, 10.f, 0.15f, 3.f);
  JawSpec jaw;
  jaw.condyles[0] = {-60.f, 30.f, -40.f};
  jaw.condyles[1] = {60.f, 30.f, -40.f};
  jaw.range_deg = 20.f;
  jaw.mouth = {0.f, 0.f, 10.f};
  jaw.mouth_width = 40.f;
  const float reach = std::sqrt(30.f * 30.f + 50.f * 50.f);
  jaw.translation = {0.f, -reach * 1.01f, 0.f};
  spec.jaw = jaw;
  Rig rig;
  Diagnostics diag;
  EXPECT_FALSE(BuildRig(spec, mesh, {}, &rig, &diag));
  EXPECT_TRUE(diag.Contains("jaw.translation")) << diag.Format();
  EXPECT_TRUE(diag.Contains("expected a glide no longer than the hinge-to-mouth distance (58.3"))
      << diag.Format();
  spec.jaw->translation = {0.f, -reach * 0.99f, 0.f};
  Diagnostics ok;
  EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &ok)) << ok.Format();
  spec.jaw->weights = {0.f, 1.f};
  Diagnostics count;
  EXPECT_FALSE(BuildRig(spec, mesh, {}, &rig, &count));
  EXPECT_TRUE(count.Contains("jaw.weights")) << count.Format();
  EXPECT_TRUE(count.Contains("expected one value per mesh vertex (" +
                             std::to_string(mesh.vertex_count()) + "), got 2"))
      << count.Format();
  // Rig::Build refuses a range past 90 degrees (the jaw stage's series hold up to pi/2), as a
  // hostile .mrig could give it; 90 degrees itself is accepted.
  spec.jaw->weights.clear();
  Rig good;
  Diagnostics built;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &good, &built)) << built.Format();
  RigData edited = good.data();
  edited.jaw.range = float(std::acos(-1.0) / 2);
  Rig ninety;
  EXPECT_TRUE(Rig::Build(edited, &ninety));
  edited.jaw.range = 1.6f;
  EXPECT_FALSE(Rig::Build(edited, &ninety));
}

// The jaw stage's sine and cosine (a series, not libm) against std::sin/cos in double over the
// whole range of angles a rig can have, [0, pi/2]: within 2e-7 (a few float ulp).
TEST(EvaluateJobJaw, EveryOpeningUpToNinetyDegreesTurnsByTheExactAngle) {
  const Surface s = MakeJawSurface();
  for (double deg : {1.0, 20.0, 45.0, 89.0, 90.0}) {
    RigData d = s.rig.data();
    d.jaw.range = float(deg * std::acos(-1.0) / 180.0);
    Rig rig;
    ASSERT_TRUE(Rig::Build(d, &rig)) << deg;
    EvaluateContext ctx(rig);
    const std::vector<float> zero(rig.muscle_count(), 0.f);
    std::vector<float> pos, nrm;
    EvaluateJob job = MakeJob(rig, &ctx, zero, &pos, &nrm);
    job.layers = {false, false, false};
    job.jaw = 1.f;
    ASSERT_TRUE(job.Run());
    const float3 c{0.f, 30.f, -40.f}, k{1.f, 0.f, 0.f};
    double worst = 0;
    for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
      const float w = SurfaceJawWeight(s.mesh.positions[v]);
      if (w == 0.f) continue;
      const float3 want = RotateAbout(s.mesh.positions[v], c, k, double(w) * double(d.jaw.range));
      const float3 got{pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]};
      worst = std::max(worst, double(Length(got - want)) /
                                  double(Length(s.mesh.positions[v] - c)));
    }
    EXPECT_LT(worst, 1e-6) << deg << " degrees";
  }
}

// The region weight's lip side and neck fade (docs/model.md §18), from its formula: on the lip
// line between the corners a point facing up joins the jaw, one facing down stays, one facing
// forward gets one half; below the lip line the weight fades out between -n0 and -n1.
TEST(EvaluateJobJaw, RegionWeightTakesTheLipSideFromTheNormalAndFadesTowardTheNeck) {
  JawSpec jaw;
  jaw.condyles[0] = {-60.f, 0.f, 0.f};
  jaw.condyles[1] = {60.f, 0.f, 0.f};
  jaw.range_deg = 20.f;
  jaw.mouth = {0.f, 0.f, 100.f};  // forward = +z, up = forward x axis = +y
  jaw.mouth_width = 40.f;
  jaw.lip_blend_deg = 2.f;
  jaw.back[0] = -1.f, jaw.back[1] = -0.5f;  // no fade from the back in front of the hinge
  jaw.neck_deg[0] = 30.f, jaw.neck_deg[1] = 60.f;
  JawFrame f;
  ASSERT_TRUE(MakeJawFrame(jaw, &f));
  EXPECT_NEAR(f.up.y, 1.f, 1e-6f);
  const float3 lip{0.f, 0.f, 100.f};
  EXPECT_NEAR(JawRegionWeight(jaw, f, lip), 0.5f, 1e-6f);
  EXPECT_NEAR(JawRegionWeight(jaw, f, lip, {0.f, 0.f, 1.f}), 0.5f, 1e-6f);
  EXPECT_NEAR(JawRegionWeight(jaw, f, lip, {0.f, 1.f, 0.f}), 1.f, 1e-6f);   // the lower lip's top
  EXPECT_NEAR(JawRegionWeight(jaw, f, lip, {0.f, -1.f, 0.f}), 0.f, 1e-6f);  // the upper's underside
  // A quarter of the way up the normal's clamp: phi moved by beta / 2 = 1 degree.
  const double t = 0.75, sm = t * t * (3 - 2 * t);  // 1 - smoothstep(-1, 3, 0): t = 1 - 1/4
  EXPECT_NEAR(JawRegionWeight(jaw, f, lip, {0.f, 0.25f, 0.968246f}), float(sm), 1e-5f);
  auto at = [](double deg) {
    const double a = deg * std::acos(-1.0) / 180.0;
    return float3{0.f, float(100 * std::sin(a)), float(100 * std::cos(a))};
  };
  EXPECT_NEAR(JawRegionWeight(jaw, f, at(-20)), 1.f, 1e-6f);
  EXPECT_NEAR(JawRegionWeight(jaw, f, at(-45)), 0.5f, 1e-5f);  // halfway through the fade
  EXPECT_NEAR(JawRegionWeight(jaw, f, at(-70)), 0.f, 1e-6f);
  const double u = (-40.0 + 60.0) / 30.0;  // phi = -40: smoothstep(-60, -30, -40)
  EXPECT_NEAR(JawRegionWeight(jaw, f, at(-40)), float(u * u * (3 - 2 * u)), 1e-5f);
}

// The side term fades out toward the mouth corners (docs/model.md §18, corner_fade): with the
// mouth 40 wide and corner_fade 0.2 it is whole up to |x| = 12 and gone at the corner, x = 20,
// where the slit ends; halfway (x = 16, smoothstep 1/2) an upward-facing point on the lip line
// is moved by beta / 2: w = 1 - smoothstep(-1, 3, 0) = 1 - smoothstep(1/4).
TEST(EvaluateJobJaw, RegionWeightsLipSideFadesOutTowardTheCorners) {
  JawSpec jaw;
  jaw.condyles[0] = {-60.f, 0.f, 0.f};
  jaw.condyles[1] = {60.f, 0.f, 0.f};
  jaw.range_deg = 20.f;
  jaw.mouth = {0.f, 0.f, 100.f};
  jaw.mouth_width = 40.f;
  jaw.lip_blend_deg = 2.f;
  jaw.corner_fade = 0.2f;
  jaw.back[0] = -1.f, jaw.back[1] = -0.5f;
  JawFrame f;
  ASSERT_TRUE(MakeJawFrame(jaw, &f));
  const float3 up{0.f, 1.f, 0.f}, down{0.f, -1.f, 0.f};
  for (float x : {0.f, 12.f, -12.f}) {
    EXPECT_NEAR(JawRegionWeight(jaw, f, {x, 0.f, 100.f}, up), 1.f, 1e-6f) << x;
    EXPECT_NEAR(JawRegionWeight(jaw, f, {x, 0.f, 100.f}, down), 0.f, 1e-6f) << x;
  }
  const double t = 0.25, ss = t * t * (3 - 2 * t);
  EXPECT_NEAR(JawRegionWeight(jaw, f, {16.f, 0.f, 100.f}, up), float(1 - ss), 1e-5f);
  EXPECT_NEAR(JawRegionWeight(jaw, f, {-16.f, 0.f, 100.f}, down), float(ss), 1e-5f);
  for (float x : {20.f, -20.f}) {  // at the corner the normal no longer matters
    EXPECT_NEAR(JawRegionWeight(jaw, f, {x, 0.f, 100.f}, up), 0.5f, 1e-6f) << x;
    EXPECT_NEAR(JawRegionWeight(jaw, f, {x, 0.f, 100.f}, down), 0.5f, 1e-6f) << x;
  }
  jaw.corner_fade = 0.f;  // no fade: the side term stops at the corners
  EXPECT_NEAR(JawRegionWeight(jaw, f, {19.9f, 0.f, 100.f}, up), 1.f, 1e-6f);
  EXPECT_NEAR(JawRegionWeight(jaw, f, {20.f, 0.f, 100.f}, up), 0.5f, 1e-6f);
}

TEST(EvaluateJobJaw, MuscleDisplacementAtACarriedPointTurnsWithTheJaw) {
  const Surface s = MakeJawSurface();
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext ctx(s.rig);
  std::vector<float> still, open, nrm;
  EvaluateJob job = MakeJob(s.rig, &ctx, act, &still, &nrm);
  job.layers = {false, false, false};
  ASSERT_TRUE(job.Run());
  job = MakeJob(s.rig, &ctx, act, &open, &nrm);
  job.layers = {false, false, false};
  job.jaw = 1.f;
  ASSERT_TRUE(job.Run());
  const float3 c{0.f, 30.f, -40.f}, k{1.f, 0.f, 0.f};
  const double range = kJawRangeDeg * std::acos(-1.0) / 180.0;
  size_t checked = 0;
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
    const float3 x0 = s.mesh.positions[v];
    const float3 u{still[3 * v] - x0.x, still[3 * v + 1] - x0.y, still[3 * v + 2] - x0.z};
    const double angle = double(SurfaceJawWeight(x0)) * range;
    // The rotated no-jaw displacement, added to the jaw pose J(X0).
    const float3 ru = RotateAbout(u, {0.f, 0.f, 0.f}, k, angle);
    const float3 want = RotateAbout(x0, c, k, angle) + ru;
    const float3 got{open[3 * v], open[3 * v + 1], open[3 * v + 2]};
    ASSERT_NEAR(Length(got - want), 0.f, 1e-3f) << v;
    if (SurfaceJawWeight(x0) == 1.f && Length(ru - u) > 0.05f) {
      // and not the unturned one: it differs by |R u - u|
      EXPECT_NEAR(Length(got - (RotateAbout(x0, c, k, angle) + u)), Length(ru - u), 1e-3f) << v;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10u);
}

TEST(EvaluateJobJaw, JawInputIsSanitisedLikeAnActivation) {
  const Surface s = MakeJawSurface(24, 4);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext ctx(s.rig);
  auto run = [&](float jaw) {
    std::vector<float> pos, nrm;
    EvaluateJob job = MakeJob(s.rig, &ctx, act, &pos, &nrm);
    job.jaw = jaw;
    EXPECT_TRUE(job.Validate());
    EXPECT_TRUE(job.Run());
    return pos;
  };
  const std::vector<float> at0 = run(0.f), at1 = run(1.f);
  EXPECT_EQ(run(std::nanf("")), at0);
  EXPECT_EQ(ctx.jaw(), 0.f);
  EXPECT_EQ(run(-3.f), at0);
  EXPECT_EQ(run(7.f), at1);
  EXPECT_EQ(ctx.jaw(), 1.f);
  EXPECT_EQ(run(std::numeric_limits<float>::infinity()), at1);
  EXPECT_NE(at0, at1);
}

TEST(EvaluateJobJaw, NoJawRigIgnoresTheInputBitForBit) {
  const Surface s = MakeSurface(30, 6);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext ctx(s.rig);
  std::vector<float> a, b, na, nb;
  ASSERT_TRUE(MakeJob(s.rig, &ctx, act, &a, &na).Run());
  EvaluateJob job = MakeJob(s.rig, &ctx, act, &b, &nb);
  job.jaw = 0.8f;
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * 4), 0);
  EXPECT_EQ(std::memcmp(na.data(), nb.data(), na.size() * 4), 0);
}

TEST(EvaluateJobJaw, BitIdenticalWhenSplitAcrossTwoThreadsAndAllocationFree) {
  const Surface s = MakeJawSurface(60, 8);
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c2(s.rig);
  std::vector<float> pos1, nrm1, pos2, nrm2;
  EvaluateJob serial = MakeJob(s.rig, &c1, act, &pos1, &nrm1);
  serial.jaw = 0.6f;
  ASSERT_TRUE(serial.Run());
  EvaluateJob threaded = MakeJob(s.rig, &c2, act, &pos2, &nrm2);
  threaded.jaw = 0.6f;
  threaded.parallel_for = TwoThreads;
  threaded.parallel_min_count = 1;  // split every loop, however short
  ASSERT_TRUE(threaded.Run());
  EXPECT_EQ(std::memcmp(pos1.data(), pos2.data(), pos1.size() * 4), 0);
  EXPECT_EQ(std::memcmp(nrm1.data(), nrm2.data(), nrm1.size() * 4), 0);
  const long before = g_allocations.load();
  for (int i = 0; i < 50; ++i) {
    serial.jaw = float(i % 11) / 10.f;
    ASSERT_TRUE(serial.Run());
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

// Chunks of 1, 2 and 3 items in turn (one thread): no chunk holds four, so every jaw angle's sine
// and cosine, and every carried point's rotation, comes from the scalar form here; with chunks
// of 4 to 7 items, none holds eight, so they come from the four-lane (SSE2) form and the scalar
// tail. A serial run takes eight at a time where the CPU has AVX (JawBlockAvx), then four: the
// bits must agree across all three.
void TinyChunks(void*, uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
  for (uint32_t b = 0, k = 0; b < count; ++k) {
    const uint32_t e = std::min(count, b + 1 + k % 3);
    task(data, b, e);
    b = e;
  }
}
void FourLaneChunks(void*, uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
  for (uint32_t b = 0, k = 0; b < count; ++k) {
    const uint32_t e = std::min(count, b + 4 + k % 4);
    task(data, b, e);
    b = e;
  }
}

TEST(EvaluateJobJaw, LaneFormsGiveTheScalarBits) {
  const Surface s = MakeJawSurface(60, 8, true);
  ASSERT_GT(s.rig.jaw().points.size(), 64u);  // more than one block of angles
  const std::vector<float> act = SomeActivations(s.rig);
  for (float jaw : {0.3f, 0.77f, 1.f}) {
    EvaluateContext c1(s.rig), c2(s.rig), c3(s.rig);
    std::vector<float> pos1, nrm1, pos2, nrm2, pos3, nrm3;
    EvaluateJob serial = MakeJob(s.rig, &c1, act, &pos1, &nrm1);
    serial.jaw = jaw;
    ASSERT_TRUE(serial.Run());
    EvaluateJob tiny = MakeJob(s.rig, &c2, act, &pos2, &nrm2);
    tiny.jaw = jaw;
    tiny.parallel_for = TinyChunks;
    tiny.parallel_min_count = 1;
    ASSERT_TRUE(tiny.Run());
    EvaluateJob four = MakeJob(s.rig, &c3, act, &pos3, &nrm3);
    four.jaw = jaw;
    four.parallel_for = FourLaneChunks;
    four.parallel_min_count = 1;
    ASSERT_TRUE(four.Run());
    EXPECT_EQ(std::memcmp(pos1.data(), pos2.data(), pos1.size() * 4), 0) << jaw;
    EXPECT_EQ(std::memcmp(nrm1.data(), nrm2.data(), nrm1.size() * 4), 0) << jaw;
    EXPECT_EQ(std::memcmp(pos1.data(), pos3.data(), pos1.size() * 4), 0) << jaw;
    EXPECT_EQ(std::memcmp(nrm1.data(), nrm3.data(), nrm1.size() * 4), 0) << jaw;
  }
}

}  // namespace
}  // namespace mimetic
