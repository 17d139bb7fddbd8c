// rig/runtime/face_kernels.h: the SIMD kernels give the same bits as the scalar expressions of
// the public stage jobs (FaceNormalsJob, TriangleAreaRatioJob, PointNormalsJob, Length,
// MuscleDeformJob), on random meshes and tables with degenerate triangles, zero and NaN rest
// areas, and odd range ends.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "muscles/runtime/muscle_table.h"
#include "rig/runtime/face_kernels.h"
#include "rig/runtime/normals_job.h"
#include "wrinkles/runtime/strain_jobs.h"

namespace mimetic {
namespace {

struct Soup {
  std::vector<float3> points;  // padded
  std::vector<uint32_t> triangles;
  std::vector<float> rest;
  uint32_t point_count = 0, triangle_count = 0;
};

Soup MakeSoup(uint32_t points, uint32_t triangles) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10.f, 10.f);
  std::uniform_int_distribution<uint32_t> pick(0, points - 1);
  Soup s;
  s.point_count = points;
  s.triangle_count = triangles;
  s.points.resize(points + 1);
  for (uint32_t p = 0; p < points; ++p) s.points[p] = {u(rng), u(rng), u(rng)};
  s.points[points] = {std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f};  // padding is junk
  for (uint32_t t = 0; t < triangles; ++t) {
    uint32_t a = pick(rng), b = pick(rng), c = pick(rng);
    if (t % 17 == 0) b = a;                   // collapsed: zero normal
    if (t % 23 == 0) a = b = c = points - 1;  // the last point, all three corners
    s.triangles.insert(s.triangles.end(), {a, b, c});
    const float area = TriangleRestArea(s.points[a], s.points[b], s.points[c]);
    s.rest.push_back(t % 13 == 0 ? 0.f : t % 29 == 0 ? std::nanf("") : area * (0.5f + 0.01f * float(t % 50)));
  }
  return s;
}

bool SameBits(float a, float b) { return std::memcmp(&a, &b, 4) == 0; }

TEST(FaceKernels, FaceNormalsAndRatiosAreTheStageJobsBits) {
  const Soup s = MakeSoup(301, 1003);
  const span<const float3> pts = span<const float3>(s.points).first(s.point_count);
  std::vector<float3> normals(s.triangle_count);
  std::vector<float> ratios(s.triangle_count);
  ASSERT_TRUE((FaceNormalsJob{.points = pts,
                              .triangles = s.triangles,
                              .out_face_normals = normals,
                              .begin = 0,
                              .end = s.triangle_count,
                              .rest_areas = s.rest,
                              .out_area_ratios = ratios}.Run()));
  for (const bool with_ratios : {true, false}) {
    for (const uint32_t begin : {0u, 3u}) {
      for (const uint32_t end : {s.triangle_count, s.triangle_count - 2}) {
        std::vector<float4> simd(s.triangle_count), scalar(s.triangle_count);
        const float* rest = with_ratios ? s.rest.data() : nullptr;
        FaceNormals4(s.points.data(), s.triangles.data(), begin, end, rest, simd.data());
        FaceNormals4Scalar(s.points.data(), s.triangles.data(), begin, end, rest, scalar.data());
        for (uint32_t t = begin; t < end; ++t) {
          ASSERT_TRUE(SameBits(simd[t].x, normals[t].x) && SameBits(simd[t].y, normals[t].y) &&
                      SameBits(simd[t].z, normals[t].z))
              << "triangle " << t;
          ASSERT_EQ(std::memcmp(&simd[t], &scalar[t], 16), 0) << "triangle " << t;
          ASSERT_TRUE(SameBits(simd[t].w, with_ratios ? ratios[t] : 0.f)) << "triangle " << t;
        }
      }
    }
  }
  // The listed variant writes only the listed slots, with the same normals.
  std::vector<float4> listed(s.triangle_count, float4{9.f, 9.f, 9.f, 9.f});
  const std::vector<uint32_t> list = {5, 0, 1002, 17};
  FaceNormals4Listed(s.points.data(), s.triangles.data(), list.data(), list.size(), listed.data());
  for (uint32_t t : list)
    EXPECT_TRUE(SameBits(listed[t].x, normals[t].x) && SameBits(listed[t].z, normals[t].z));
  EXPECT_EQ(listed[2].x, 9.f);
}

TEST(FaceKernels, GatheredNormalsAndRatiosAreThePointNormalsJobsBits) {
  // A closed strip: every point in some triangles, except the last one (no triangle: +Z, r=1).
  const uint32_t n = 40;
  std::vector<float3> pts(n + 1);
  for (uint32_t i = 0; i + 1 < n; ++i)
    pts[i] = {float(i / 2), float(i % 2), 0.1f * float((i * 7) % 5)};
  std::vector<uint32_t> tris;
  for (uint32_t i = 0; i + 3 < n; ++i) tris.insert(tris.end(), {i, i + 1, i + 2});
  const uint32_t T = uint32_t(tris.size() / 3);
  std::vector<float> rest(T);
  for (uint32_t t = 0; t < T; ++t) rest[t] = 0.3f + 0.01f * float(t);
  std::vector<uint32_t> offsets(n + 1, 0), items;
  for (uint32_t p = 0; p < n; ++p) {
    for (uint32_t t = 0; t < T; ++t)
      if (tris[3 * t] == p || tris[3 * t + 1] == p || tris[3 * t + 2] == p) items.push_back(t);
    offsets[p + 1] = uint32_t(items.size());
  }
  std::vector<float3> faces(T), normals(n);
  std::vector<float> tri_ratios(T), ratios(n);
  const span<const float3> points = span<const float3>(pts).first(n);
  ASSERT_TRUE((FaceNormalsJob{.points = points,
                              .triangles = tris,
                              .out_face_normals = faces,
                              .begin = 0,
                              .end = T,
                              .rest_areas = rest,
                              .out_area_ratios = tri_ratios}.Run()));
  ASSERT_TRUE((PointNormalsJob{.face_normals = faces,
                               .point_triangle_offsets = offsets,
                               .point_triangles = items,
                               .out_normals = normals,
                               .begin = 0,
                               .end = n,
                               .triangle_ratios = tri_ratios,
                               .out_ratios = ratios}.Run()));
  std::vector<float4> slots(T);
  FaceNormals4(pts.data(), tris.data(), 0, T, rest.data(), slots.data());
  for (uint32_t p = 0; p < n; ++p) {
    const float4 sum = GatherFaces4(offsets.data(), items.data(), slots.data(), p);
    const float3 u = UnitNormal(sum);
    EXPECT_TRUE(SameBits(u.x, normals[p].x) && SameBits(u.y, normals[p].y) &&
                SameBits(u.z, normals[p].z))
        << "point " << p;
    const uint32_t count = offsets[p + 1] - offsets[p];
    EXPECT_TRUE(SameBits(count ? sum.w / float(count) : 1.f, ratios[p])) << "point " << p;
  }
  EXPECT_EQ(UnitNormal(GatherFaces4(offsets.data(), items.data(), slots.data(), n - 1)).z, 1.f);
}

TEST(FaceKernels, EdgeLengthsAreLengthsBits) {
  const Soup s = MakeSoup(97, 10);
  std::mt19937 rng(3);
  std::uniform_int_distribution<uint32_t> pick(0, s.point_count - 1);
  std::vector<uint32_t> pairs;
  for (int e = 0; e < 203; ++e) pairs.insert(pairs.end(), {pick(rng), pick(rng)});
  pairs.insert(pairs.end(), {s.point_count - 1, 0u, 4u, 4u});  // last point; zero length
  const uint32_t E = uint32_t(pairs.size() / 2);
  std::vector<float> simd(E, -1.f), scalar(E, -1.f);
  EdgeLengths(s.points.data(), pairs.data(), 1, E, simd.data());
  EdgeLengthsScalar(s.points.data(), pairs.data(), 1, E, scalar.data());
  EXPECT_EQ(simd[0], -1.f);  // outside the range
  for (uint32_t e = 1; e < E; ++e) {
    const float expect = Length(s.points[pairs[2 * e]] - s.points[pairs[2 * e + 1]]);
    ASSERT_TRUE(SameBits(simd[e], expect)) << "edge " << e;
    ASSERT_TRUE(SameBits(scalar[e], expect)) << "edge " << e;
    // Orientation does not matter (negation is exact): the rest lengths the builder stores
    // from either end match.
    ASSERT_TRUE(SameBits(Length(s.points[pairs[2 * e + 1]] - s.points[pairs[2 * e]]), expect));
  }
  EXPECT_EQ(simd[E - 1], 0.f);
}

TEST(FaceKernels, MusclePointsAreTheMuscleDeformJobsBits) {
  // A random CSR table (0 to 5 entries per point, some points none) and activations in
  // [0, 1] (what SanitizeActivations hands on), over split ranges as threads would run them.
  const uint32_t n = 203, muscles = 7;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-3.f, 3.f), a01(0.f, 1.f);
  MuscleTable table;
  table.muscle_count = muscles;
  table.offsets.assign(1, 0u);
  std::vector<float3> rest(n);
  for (uint32_t p = 0; p < n; ++p) {
    rest[p] = {u(rng), u(rng), u(rng)};
    const uint32_t count = (p * 5 + 3) % 6;
    for (uint32_t k = 0; k < count; ++k)
      table.entries.push_back({(p + 3 * k) % muscles, float3{u(rng), u(rng), u(rng)}});
    table.offsets.push_back(uint32_t(table.entries.size()));
  }
  std::vector<float> act(muscles);
  for (float& a : act) a = a01(rng);
  act[2] = 0.f;
  act[5] = 1.f;
  std::vector<float3> expect(n);
  ASSERT_TRUE((MuscleDeformJob{.table = &table,
                               .activations = act,
                               .rest_points = rest,
                               .out_points = expect,
                               .begin = 0,
                               .end = n}.Run()));
  for (const bool simd : {true, false}) {
    std::vector<float3> out(n + 1, float3{-7.f, -7.f, -7.f});  // padded
    const uint32_t cuts[] = {0, 1, 2, 64, 65, 150, n - 1, n};
    for (size_t c = 0; c + 1 < std::size(cuts); ++c) {
      if (simd)
        MusclePoints(table, act.data(), rest.data(), cuts[c], cuts[c + 1], out.data());
      else
        MusclePointsScalar(table, act.data(), rest.data(), cuts[c], cuts[c + 1], out.data());
    }
    for (uint32_t p = 0; p < n; ++p)
      ASSERT_EQ(std::memcmp(&out[p], &expect[p], sizeof(float3)), 0) << "point " << p << simd;
  }
  // A range writes only its own points: [10, 20) leaves 9 and 20 as they were.
  std::vector<float3> out(n + 1, float3{-7.f, -7.f, -7.f});
  MusclePoints(table, act.data(), rest.data(), 10, 20, out.data());
  EXPECT_EQ(out[9].x, -7.f);
  EXPECT_EQ(out[20].x, -7.f);
  EXPECT_EQ(std::memcmp(&out[19], &expect[19], sizeof(float3)), 0);
}

}  // namespace
}  // namespace mimetic
