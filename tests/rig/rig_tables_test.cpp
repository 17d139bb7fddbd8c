// tests/rig/rig_tables_test.cpp: the strain tables Rig::Build derives (rig/runtime/rig_tables.cpp),
// against a second derivation with std::map in the documented order.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "content/procedural.h"
#include "rig/offline/rig_builder.h"

namespace mimetic {
namespace {

Rig WrinkledRig() {
  const MeshData mesh = MakeSurfaceMesh(41, 41, 100.f, 100.f, 10.f);
  RigSpec spec = MakeSurfaceRigSpec(6, 100.f, 100.f, 10.f, 0.3f, 3.f);
  AddEverySkinLayer(&spec, 0.4f, 6.f);
  Rig rig;
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  return rig;
}

// Edge ids: point-major over the muscle-wrinkle rows (within a point, the rig's tables in order,
// each row's neighbours in order), then the curve-wrinkle probes (each side's v1v2, v1v3); an
// edge gets the next id the first time it is seen, whichever way round its points come.
TEST(RigTables, StrainEdgesAreNumberedInFirstSeenOrderOncePerEdge) {
  const Rig rig = WrinkledRig();
  const RigData& r = rig.data();
  const RigTables& t = rig.tables();
  ASSERT_TRUE(rig.tables_checked());
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> ids;
  std::vector<uint32_t> pairs;
  auto id = [&](uint32_t a, uint32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, fresh] = ids.emplace(std::pair<uint32_t, uint32_t>(key.first, key.second),
                                   uint32_t(ids.size()));
    if (fresh) {
      pairs.push_back(key.first);
      pairs.push_back(key.second);
    }
    return it->second;
  };
  std::vector<uint32_t> entries, rows_per_point(r.active.points, 0), row_muscles;
  size_t entry_count = 0;
  for (uint32_t p = 0; p < r.active.points; ++p)
    for (const RigMuscleWrinkles& w : r.muscle_wrinkles)
      for (uint32_t i = 0; i < w.row_count(); ++i) {
        if (w.points[i] != p) continue;
        ++rows_per_point[p];
        row_muscles.push_back(w.muscle);  // the row's gate is its own muscle's (docs/model.md §6)
        for (uint32_t k = w.edge_offsets[i]; k < w.edge_offsets[i + 1]; ++k)
          entries.push_back(id(p, w.edge_neighbors[k]));
        entry_count += w.edge_offsets[i + 1] - w.edge_offsets[i];
      }
  std::vector<uint32_t> probes(4 * r.curve_wrinkles.probes.size(), 0u);
  for (size_t k = 0; k < r.curve_wrinkles.probes.size(); ++k) {
    const ShrinkageProbe& probe = r.curve_wrinkles.probes[k];
    for (uint32_t s = 0; s < probe.side_count; ++s) {
      probes[4 * k + 2 * s] = id(probe.point, probe.sides[s].v2);
      probes[4 * k + 2 * s + 1] = id(probe.point, probe.sides[s].v3);
    }
  }
  ASSERT_GT(entry_count, 1000u);  // the fixture exercises the tables
  ASSERT_GT(r.curve_wrinkles.probes.size(), 100u);
  EXPECT_EQ(t.entry_edges, entries);
  EXPECT_EQ(t.row_muscles, row_muscles);
  EXPECT_GT(std::set<uint32_t>(row_muscles.begin(), row_muscles.end()).size(), 1u);
  EXPECT_EQ(t.probe_edges, probes);
  EXPECT_EQ(t.edge_pairs, pairs);
  // Per point, its rows are a contiguous range of the right length.
  ASSERT_EQ(t.point_row_offsets.size(), size_t(r.active.points) + 1);
  for (uint32_t p = 0; p < r.active.points; ++p)
    ASSERT_EQ(t.point_row_offsets[p + 1] - t.point_row_offsets[p], rows_per_point[p]) << p;
  // Curve rows per point, in row order; wrinkle points are those with any row.
  std::vector<std::vector<uint32_t>> curves(r.active.points);
  for (uint32_t i = 0; i < r.curve_wrinkles.row_count(); ++i)
    curves[r.curve_wrinkles.points[i]].push_back(i);
  std::vector<uint32_t> flat, wrinkle_points;
  for (uint32_t p = 0; p < r.active.points; ++p) {
    flat.insert(flat.end(), curves[p].begin(), curves[p].end());
    ASSERT_EQ(t.point_curve_offsets[p + 1], flat.size()) << p;
    if (rows_per_point[p] > 0 || !curves[p].empty()) wrinkle_points.push_back(p);
  }
  EXPECT_EQ(t.point_curve_rows, flat);
  EXPECT_EQ(t.wrinkle_points, wrinkle_points);
}

}  // namespace
}  // namespace mimetic
