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

namespace mimetic {

struct Rig {
  // Identity used by EvaluateContext to refuse a context sized for another rig. Unique per
  // built rig, kept across moves.
  uint64_t uid = 0;

  // Welded surface.
  std::vector<float3> rest_points;              // #P, mesh units
  std::vector<uint32_t> triangles;              // 3 * #T, into points, counter-clockwise
  std::vector<uint32_t> point_triangle_offsets; // #P + 1 (CSR): triangles around each point
  std::vector<uint32_t> point_triangles;        // triangle indices, ascending per point

  // The file's layout.
  std::vector<uint32_t> vertex_points;   // #V: output vertex -> point
  std::vector<uint32_t> vertex_indices;  // 3 * #T, into vertices (the file's index buffer)
  std::vector<float2> vertex_uvs;        // #V, or empty when the mesh has none

  // Skin.
  std::vector<float> point_thickness;    // #P, mesh units (MODEL.md §4)

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
