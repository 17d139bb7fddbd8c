// rig/runtime/rig.h: the compiled, immutable rig shared by every instance of a face.
//
// Built offline by BuildRig (rig/offline/rig_builder.h). Geometry lives on welded "points"
// (one per surface position); outputs are written per file "vertex" (the mesh's own layout,
// split at UV / normal seams), each vertex reading its point, so a posed mesh never cracks.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "muscles/runtime/muscle_table.h"
#include "rig/runtime/skin_layers.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {

// One muscle's wrinkling region (MODEL.md §6), fixed on the rest pose; see MuscleWrinkleJob
// and EdgeCompressionJob for the meaning of each array (rows = region points).
struct RigMuscleWrinkles {
  uint32_t muscle = 0;                    // index into the rig's muscles
  std::vector<uint32_t> points;           // rows
  std::vector<float> phase;               // w_i, mesh units
  std::vector<float> attenuation;         // At_i
  std::vector<float> profile;             // H(w_i) At_i (MuscleWrinkleProfile), per row
  std::vector<uint32_t> edge_offsets;     // rows + 1
  std::vector<uint32_t> edge_neighbors;
  std::vector<float> edge_rest_lengths;   // mesh units
  std::vector<float> edge_weights;        // |cos theta|
  float half_cycle = 0.f;                 // u, mesh units
  float furrow_depth = 0.f;               // k0, mesh units
  float shape = 0.f;                      // alpha
  uint32_t row_count() const { return uint32_t(points.size()); }
};

// Every curve wrinkle of the rig in one table (MODEL.md §7-8); see CurveWrinkleJob.
struct RigCurveWrinkles {
  std::vector<std::string> names;            // one per wrinkle
  std::vector<CurveWrinkleParams> wrinkles;  // one per wrinkle
  std::vector<uint32_t> points;              // rows
  std::vector<uint32_t> offsets;             // rows + 1
  std::vector<CurveWrinkleEntry> entries;
  std::vector<ShrinkageProbe> probes;        // one per entry
  uint32_t row_count() const { return uint32_t(points.size()); }
};

struct Rig {
  // Identity used by EvaluateContext to refuse a context sized for another rig. Unique per
  // built rig, kept across moves.
  uint64_t uid = 0;

  // Welded surface.
  std::vector<float3> rest_points;              // #P, mesh units
  std::vector<uint32_t> triangles;              // 3 * #T, into points, counter-clockwise
  std::vector<uint32_t> point_triangle_offsets; // #P + 1 (CSR): triangles around each point
  std::vector<uint32_t> point_triangles;        // triangle indices, ascending per point
  // Points are ordered so that a frame only touches leading ranges (rig_builder ActiveOrder):
  // [0, active_point_count) can move; [0, normal_point_count) can change normal; the rest
  // stay at their rest position and normal. Triangles [0, active_triangle_count) touch a
  // point that can move; the others keep their rest normal.
  uint32_t active_point_count = 0;
  uint32_t normal_point_count = 0;
  uint32_t active_triangle_count = 0;

  // The file's layout.
  std::vector<uint32_t> vertex_points;   // #V: output vertex -> point
  std::vector<uint32_t> vertex_indices;  // 3 * #T, into vertices (the file's index buffer)
  std::vector<float2> vertex_uvs;        // #V, or empty when the mesh has none

  // Skin (MODEL.md §4-8).
  // What was compiled: a layer is on when the rig file enables it and it has something to do
  // (all off until the builder says otherwise).
  SkinLayers layers{false, false, false};
  std::vector<float> point_thickness;    // #P, mesh units (MODEL.md §4)
  std::vector<float> rest_triangle_areas;  // #T, mesh units^2 (when any skin layer is on)
  float min_area_ratio = kDefaultMinAreaRatio;  // r_min (MODEL.md §4 choice)
  std::vector<RigMuscleWrinkles> muscle_wrinkles;  // one per wrinkled muscle, muscle order
  RigCurveWrinkles curve_wrinkles;

  // Muscles.
  std::vector<std::string> muscle_names;  // rig order = activation order
  MuscleTable muscles;

  uint32_t point_count() const { return uint32_t(rest_points.size()); }
  uint32_t triangle_count() const { return uint32_t(triangles.size() / 3); }
  uint32_t vertex_count() const { return uint32_t(vertex_points.size()); }
  uint32_t muscle_count() const { return uint32_t(muscle_names.size()); }
  // Index of the muscle called `name`, or -1.
  int FindMuscle(std::string_view name) const;
};

}  // namespace mimetic
