// EvaluateJob's tension outputs (docs/tension.md, docs/model.md §19): the area ratio of an
// affinely mapped sheet against its closed form, a region weight computed by hand on a small
// mesh, the muscle-wrinkle compression against the rig's own eps rows, bit-identical splits,
// zero allocation, and the job's and the rig's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <thread>
#include <vector>

#include "content/procedural.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"

#include "alloc_counter.h"
#include "rig/frame_helpers.h"

namespace mimetic {
namespace {

// A grid of (n + 1) x (n + 1) points with spacing 1 in the plane z = 0, two triangles per
// cell (counter-clockwise), every point active and no muscle: X1 is the rest pose as given.
// rest_points = map(grid point); rest_triangle_areas = the areas of the unmapped grid (1/2).
// So a frame measures the strain of `map` against the unit grid.
template <class Map>
RigData GridRig(uint32_t n, const Map& map) {
  RigData d;
  const uint32_t side = n + 1;
  for (uint32_t y = 0; y < side; ++y)
    for (uint32_t x = 0; x < side; ++x) d.rest_points.push_back(map(float(x), float(y)));
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      const uint32_t a = y * side + x, b = a + 1, c = a + side, e = c + 1;
      d.triangles.insert(d.triangles.end(), {a, b, e, a, e, c});
    }
  const uint32_t points = d.point_count(), tris = d.triangle_count();
  std::vector<std::vector<uint32_t>> around(points);
  for (uint32_t t = 0; t < tris; ++t)
    for (int k = 0; k < 3; ++k) around[d.triangles[3 * t + k]].push_back(t);
  d.point_triangle_offsets.push_back(0);
  for (const auto& list : around) {
    d.point_triangles.insert(d.point_triangles.end(), list.begin(), list.end());
    d.point_triangle_offsets.push_back(uint32_t(d.point_triangles.size()));
  }
  d.active = {points, points, tris};
  for (uint32_t p = 0; p < points; ++p) d.vertex_points.push_back(p);
  d.vertex_indices = d.triangles;
  d.point_thickness.assign(points, 0.f);
  d.rest_triangle_areas.assign(tris, 0.5f);
  d.muscles.offsets.assign(size_t(points) + 1, 0);
  return d;
}

struct Outputs {
  std::vector<float> positions, tension, regions;
};

bool RunTension(const Rig& rig, EvaluateContext* ctx, Outputs* out, ParallelForFn pf = nullptr,
                span<const float> activations = {}) {
  out->positions.assign(3 * rig.vertex_count(), 0.f);
  out->tension.assign(2 * rig.vertex_count(), -1.f);
  out->regions.assign(rig.tension_region_count(), -1.f);
  EvaluateJob job;
  job.rig = &rig;
  job.context = ctx;
  job.activations = activations;
  job.out_positions = out->positions;
  job.out_tension = out->tension;
  job.out_region_weights = out->regions;
  job.parallel_for = pf;
  job.parallel_min_count = 1;
  return job.Run();
}

TEST(EvaluateJobTension, AffineSheetHasTheDeterminantAsAreaRatioEverywhere) {
  // X = A (x, y, 0) + t with the columns a1 = (0.8, 0.1, 0.3), a2 = (0.25, 0.9, -0.2): every
  // triangle's area scales by |a1 x a2| (by hand: a1 x a2 = (0.1 * -0.2 - 0.3 * 0.9,
  // 0.3 * 0.25 - 0.8 * -0.2, 0.8 * 0.9 - 0.1 * 0.25) = (-0.29, 0.235, 0.695)).
  const auto map = [](float x, float y) {
    return float3{0.8f * x + 0.25f * y + 3.f, 0.1f * x + 0.9f * y - 1.f, 0.3f * x - 0.2f * y};
  };
  const double expected = std::sqrt(0.29 * 0.29 + 0.235 * 0.235 + 0.695 * 0.695);
  Rig rig;
  ASSERT_TRUE(Rig::Build(GridRig(6, map), &rig));
  EvaluateContext ctx(rig);
  Outputs out;
  ASSERT_TRUE(RunTension(rig, &ctx, &out));
  for (uint32_t v = 0; v < rig.vertex_count(); ++v) {
    EXPECT_NEAR(out.tension[2 * v], expected, 1e-5) << "vertex " << v;
    EXPECT_EQ(out.tension[2 * v + 1], 0.f) << "no muscle-wrinkle rows: eps = 0";
  }
  // The positions are X1 itself (nothing moves for the measurement).
  for (uint32_t p = 0; p < rig.point_count(); ++p) {
    const float3 x = map(float(p % 7), float(p / 7));
    EXPECT_EQ(out.positions[3 * p], x.x);
    EXPECT_EQ(out.positions[3 * p + 2], x.z);
  }
}

// Twice the signed area of (a, b, c) in the plane, shoelace formula, in double.
double Shoelace(double ax, double ay, double bx, double by, double cx, double cy) {
  return (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
}

TEST(EvaluateJobTension, RegionWeightMatchesAHandComputation) {
  // 2 x 2 cells; the centre point 4 moved from (1, 1) to (1.4, 1.2).
  const auto map = [](float x, float y) {
    return x == 1.f && y == 1.f ? float3{1.4f, 1.2f, 0.f} : float3{x, y, 0.f};
  };
  RigData d = GridRig(2, map);
  // Region "a": points 0 (w 0.5), 4 (w 1), 5 (w 0.25), reference 0.1; region "b": point 8
  // (w 0.8), reference 0.3.
  d.tension_regions.names = {"a", "b"};
  d.tension_regions.references = {0.1f, 0.3f};
  d.tension_regions.offsets = {0, 3, 4};
  d.tension_regions.points = {0, 4, 5, 8};
  d.tension_regions.weights = {0.5f, 1.f, 0.25f, 0.8f};
  // By hand: each triangle's ratio = its shoelace area over 1/2; each point's r = the mean
  // over the triangles that have it as a corner.
  std::vector<double> px, py;
  for (uint32_t p = 0; p < 9; ++p) {
    px.push_back(p == 4 ? 1.4 : double(p % 3));
    py.push_back(p == 4 ? 1.2 : double(p / 3));
  }
  std::vector<double> sum(9, 0.0);
  std::vector<int> count(9, 0);
  for (uint32_t t = 0; t < d.triangle_count(); ++t) {
    const uint32_t* c = &d.triangles[3 * t];
    const double ratio =
        0.5 * Shoelace(px[c[0]], py[c[0]], px[c[1]], py[c[1]], px[c[2]], py[c[2]]) / 0.5;
    for (int k = 0; k < 3; ++k) sum[c[k]] += ratio, ++count[c[k]];
  }
  std::vector<double> r(9);
  for (int p = 0; p < 9; ++p) r[p] = sum[p] / count[p];
  // Point 0 touches triangles (0,1,4) and (0,4,3): (0,1,4) has area 0.6, (0,4,3) 0.7, r = 1.3;
  // the formula counts only compression.
  EXPECT_NEAR(r[0], 1.3, 1e-12);
  auto comp = [&](int p) { return std::max(0.0, 1.0 - r[p]); };
  const double mean_a = (0.5 * comp(0) + 1.0 * comp(4) + 0.25 * comp(5)) / 1.75;
  const double weight_a = 1.0 - std::exp(-mean_a / 0.1);
  const double weight_b = 1.0 - std::exp(-comp(8) / 0.3);
  ASSERT_GT(mean_a, 0.0);  // point 5 is compressed (its triangles lose area)

  Rig rig;
  ASSERT_TRUE(Rig::Build(std::move(d), &rig));
  EvaluateContext ctx(rig);
  Outputs out;
  ASSERT_TRUE(RunTension(rig, &ctx, &out));
  for (int p = 0; p < 9; ++p) EXPECT_NEAR(out.tension[2 * p], r[p], 1e-6) << "point " << p;
  EXPECT_NEAR(out.regions[0], weight_a, 1e-6);
  EXPECT_NEAR(out.regions[1], weight_b, 1e-6);
  EXPECT_GE(out.regions[0], 0.f);
  EXPECT_LE(out.regions[0], 1.f);
}

// A surface rig with muscle wrinkles and two tension regions (weights from the rest x).
struct Surface {
  MeshData mesh;
  RigSpec spec;
  Rig rig;
};

Surface MakeSurfaceWithRegions(uint32_t side, uint32_t muscles) {
  Surface s;
  s.mesh = MakeSurfaceMesh(side, side, 100.f, 100.f, 10.f);
  s.spec = MakeSurfaceRigSpec(muscles, 100.f, 100.f, 10.f, 0.15f, 3.f);
  s.spec.thickness.value = 1.f;
  s.spec.muscle_wrinkles.resize(s.spec.muscles.size());
  for (size_t m = 0; m < s.spec.muscles.size(); ++m) {
    MuscleWrinkleSpec w;
    w.lambda_w = 0.3f;
    w.count = 3;
    w.depth = 0.5f;
    w.shape = 0.5f;
    w.phi_c = s.spec.muscles[m].type == MuscleType::kLinear ? 0.2f : 0.f;
    w.h_c = s.spec.muscles[m].type == MuscleType::kSheet ? 0.1f * s.spec.muscles[m].sheet.width : 0.f;
    s.spec.muscle_wrinkles[m] = w;
  }
  TensionRegionSpec left{"left", 0.05f, {}}, right{"right", kDefaultTensionReference, {}};
  for (const float3& p : s.mesh.positions) {
    const float u = std::min(std::max((p.x + 50.f) / 100.f, 0.f), 1.f);
    left.weights.push_back(1.f - u);
    right.weights.push_back(u);
  }
  s.spec.tension_regions = {left, right};
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(s.spec, s.mesh, {}, &s.rig, &diag)) << diag.Format();
  return s;
}

using test::SomeActivations;
using test::TwoThreads;

TEST(EvaluateJobTension, RegionsComeThroughTheBuilderAndCompressionIsTheLargestEpsRow) {
  const Surface s = MakeSurfaceWithRegions(40, 6);
  const RigTensionRegions& g = s.rig.tension_regions();
  ASSERT_EQ(g.region_count(), 2u);
  EXPECT_EQ(g.names[0], "left");
  EXPECT_FLOAT_EQ(g.references[0], 0.05f);
  for (float w : g.weights) {
    EXPECT_GT(w, 0.f);
    EXPECT_LE(w, 1.f);
  }
  ASSERT_FALSE(s.rig.muscle_wrinkles().empty()) << "the surface rig has wrinkled muscles";
  const std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext ctx(s.rig);
  Outputs out;
  ASSERT_TRUE(RunTension(s.rig, &ctx, &out, nullptr, act));
  // eps by a second method: EdgeCompressionJob over each wrinkled muscle's rows on X1 (the
  // pose before the skin layers: the same rig with the layers off gives X1 as its output).
  EvaluateContext ctx1(s.rig);
  ASSERT_TRUE(test::RunPoseBeforeSkin(s.rig, act, &ctx1));
  const span<const float3> points = ctx1.points();
  std::vector<float> best(s.rig.point_count(), 0.f);
  std::vector<uint8_t> seen(s.rig.point_count(), 0);
  size_t compressed = 0;
  for (const RigMuscleWrinkles& w : s.rig.muscle_wrinkles()) {
    std::vector<float> eps(w.row_count());
    const EdgeCompressionJob job{.positions = points,
                                 .points = w.points,
                                 .offsets = w.edge_offsets,
                                 .neighbors = w.edge_neighbors,
                                 .rest_lengths = w.edge_rest_lengths,
                                 .weights = w.edge_weights,
                                 .end = w.row_count(),
                                 .out_compression = eps};
    ASSERT_TRUE(job.Run());
    for (uint32_t i = 0; i < w.row_count(); ++i) {
      const uint32_t p = w.points[i];
      best[p] = seen[p] ? std::max(best[p], eps[i]) : eps[i];
      seen[p] = 1;
    }
  }
  for (uint32_t v = 0; v < s.rig.vertex_count(); ++v) {
    const uint32_t p = s.rig.vertex_points()[v];
    EXPECT_NEAR(out.tension[2 * v + 1], best[p], 1e-5f) << "vertex " << v;
    compressed += best[p] > 1e-3f;
  }
  EXPECT_GT(compressed, 10u) << "the activations compress some wrinkle rows";
  // Region weights from the builder's own point weights and the context's ratios, in double.
  for (uint32_t i = 0; i < 2; ++i) {
    double num = 0.0, den = 0.0;
    for (uint32_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k) {
      num += g.weights[k] * std::max(0.0, 1.0 - double(ctx.area_ratios()[g.points[k]]));
      den += g.weights[k];
    }
    EXPECT_NEAR(out.regions[i], 1.0 - std::exp(-(num / den) / g.references[i]), 1e-6);
  }
}

// The rig file's sparse form (TensionRegionSpec::vertices) builds the same regions as the dense
// weights it lists; a bad index list or a weight count that does not match is an error.
TEST(EvaluateJobTension, SparseRegionsBuildTheSameRigAsDenseOnes) {
  const Surface s = MakeSurfaceWithRegions(20, 2);
  RigSpec sparse = s.spec;
  for (TensionRegionSpec& g : sparse.tension_regions) {
    std::vector<float> w;
    for (uint32_t v = 0; v < g.weights.size(); ++v)
      if (g.weights[v] != 0.f) {
        g.vertices.push_back(v);
        w.push_back(g.weights[v]);
      }
    g.weights = w;
    g.sparse = true;
  }
  ASSERT_LT(sparse.tension_regions[0].vertices.size(), s.mesh.vertex_count());
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(sparse, s.mesh, {}, &rig, &diag)) << diag.Format();
  const RigTensionRegions& a = rig.tension_regions();
  const RigTensionRegions& b = s.rig.tension_regions();
  EXPECT_EQ(a.names, b.names);
  EXPECT_EQ(a.references, b.references);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.weights, b.weights);
  RigSpec bad = sparse;
  bad.tension_regions[0].weights.pop_back();
  Diagnostics count;
  EXPECT_FALSE(BuildRig(bad, s.mesh, {}, &rig, &count));
  EXPECT_TRUE(count.Contains("tension_regions[0] (left).weights")) << count.Format();
  EXPECT_TRUE(count.Contains("expected one value per entry of vertices")) << count.Format();
  bad = sparse;
  std::swap(bad.tension_regions[1].vertices[0], bad.tension_regions[1].vertices[1]);
  Diagnostics order;
  EXPECT_FALSE(BuildRig(bad, s.mesh, {}, &rig, &order));
  EXPECT_TRUE(order.Contains("tension_regions[1] (right).vertices[1]")) << order.Format();
  bad = sparse;
  bad.tension_regions[1].vertices.back() = uint32_t(s.mesh.vertex_count());
  Diagnostics range;
  EXPECT_FALSE(BuildRig(bad, s.mesh, {}, &rig, &range));
  EXPECT_TRUE(range.Contains("expected ascending vertex indices below the mesh's")) << range.Format();
}

TEST(EvaluateJobTension, BitIdenticalSplitsZeroAllocationAndNoEffectOnPositions) {
  const Surface s = MakeSurfaceWithRegions(50, 8);
  std::vector<float> act = SomeActivations(s.rig);
  EvaluateContext c1(s.rig), c2(s.rig), c3(s.rig);
  Outputs serial, split;
  ASSERT_TRUE(RunTension(s.rig, &c1, &serial, nullptr, act));
  ASSERT_TRUE(RunTension(s.rig, &c2, &split, TwoThreads, act));
  EXPECT_EQ(std::memcmp(serial.tension.data(), split.tension.data(), serial.tension.size() * 4), 0);
  EXPECT_EQ(std::memcmp(serial.regions.data(), split.regions.data(), serial.regions.size() * 4), 0);
  EXPECT_EQ(std::memcmp(serial.positions.data(), split.positions.data(),
                        serial.positions.size() * 4), 0);
  // Without the tension outputs: the same positions, bit for bit.
  std::vector<float> plain(3 * s.rig.vertex_count());
  EvaluateJob job;
  job.rig = &s.rig;
  job.context = &c3;
  job.activations = act;
  job.out_positions = plain;
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(std::memcmp(plain.data(), serial.positions.data(), plain.size() * 4), 0);
  // Zero allocation per frame with both outputs on (and with the skin layers off).
  job.out_tension = serial.tension;
  job.out_region_weights = serial.regions;
  ASSERT_TRUE(job.Run());
  const long before = g_allocations.load();
  for (int i = 0; i < 50; ++i) {
    act[i % act.size()] = float(i % 10) / 10.f;
    job.layers = SkinLayers{i % 2 == 0, i % 3 == 0, true};
    ASSERT_TRUE(job.Run());
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

TEST(EvaluateJobTension, JobAndRigChecks) {
  const Surface s = MakeSurfaceWithRegions(20, 4);
  EvaluateContext ctx(s.rig);
  const std::vector<float> act = SomeActivations(s.rig);
  const uint32_t nv = s.rig.vertex_count();
  std::vector<float> pos(3 * nv), ten(2 * nv), reg(2);
  EvaluateJob good;
  good.rig = &s.rig;
  good.context = &ctx;
  good.activations = act;
  good.out_positions = pos;
  good.out_tension = ten;
  good.out_region_weights = reg;
  EXPECT_TRUE(good.Validate());
  EvaluateJob j = good;
  j.out_tension = span<float>(ten).first(2 * nv - 1);
  EXPECT_FALSE(j.Validate()) << "tension one float short";
  j = good;
  j.out_tension_stride = 6;
  EXPECT_FALSE(j.Validate()) << "tension stride not a multiple of 4";
  j = good;
  j.out_tension_stride = 4;
  EXPECT_FALSE(j.Validate()) << "tension stride below 8";
  j = good;
  j.out_region_weights = span<float>(reg).first(1);
  EXPECT_FALSE(j.Validate()) << "region weights one short";

  // Rig::Build refuses malformed regions.
  auto refuses = [&](auto edit, const char* what) {
    RigData d = s.rig.data();
    edit(d.tension_regions);
    Rig bad;
    EXPECT_FALSE(Rig::Build(std::move(d), &bad)) << what;
  };
  refuses([](RigTensionRegions& g) { g.weights[0] = 1.5f; }, "weight above 1");
  refuses([](RigTensionRegions& g) { g.weights[0] = 0.f; }, "weight 0 (not listed)");
  refuses([](RigTensionRegions& g) { g.points[0] = 1u << 30; }, "point out of range");
  refuses([](RigTensionRegions& g) { g.names[1] = g.names[0]; }, "repeated name");
  refuses([](RigTensionRegions& g) { g.references[0] = 0.f; }, "reference 0");
  refuses([](RigTensionRegions& g) { g.offsets[1] = g.offsets[2] + 1; }, "offsets decrease");
  refuses([](RigTensionRegions& g) { std::swap(g.points[0], g.points[1]); }, "not ascending");

  // The builder names what is wrong in the spec.
  RigSpec spec = s.spec;
  spec.tension_regions[1].weights.pop_back();
  Rig rig;
  Diagnostics diag;
  EXPECT_FALSE(BuildRig(spec, s.mesh, {}, &rig, &diag));
  EXPECT_NE(diag.Format().find("tension_regions[1] (right).weights"), std::string::npos)
      << diag.Format();
  EXPECT_NE(diag.Format().find("expected one value per mesh vertex"), std::string::npos);
  spec = s.spec;
  spec.tension_regions[0].weights[3] = std::nanf("");
  diag = Diagnostics();
  EXPECT_FALSE(BuildRig(spec, s.mesh, {}, &rig, &diag));
  EXPECT_NE(diag.Format().find("tension_regions[0] (left).weights[3]"), std::string::npos)
      << diag.Format();
}

}  // namespace
}  // namespace mimetic
