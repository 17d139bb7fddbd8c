// viewer/core/scene_query.h: what is under the cursor (a ray against the posed mesh) and which
// muscles reach the point found (hover), plus the grouping of the muscles panel.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/span.h"
#include "rig/runtime/rig.h"

namespace mimetic::viewer {

struct PickHit {
  uint32_t triangle = 0;   // index into the index buffer's triangles
  float distance = 0.f;    // along the ray, mesh units
  float u = 0.f, w = 0.f;  // barycentric weights of the triangle's second and third corner
  uint32_t nearest = 0;    // the corner (vertex index) with the largest weight
};

// The nearest triangle of `indices` (3 per triangle, into `positions`) that the ray from
// `origin` along unit `direction` enters (either side; Moller-Trumbore), in front of the
// origin. False when the ray hits none (or an index is out of range).
bool PickTriangle(span<const float3> positions, span<const uint32_t> indices,
                  const float3& origin, const float3& direction, PickHit* hit);

// The muscles (indices, ascending) whose influence reaches `point`: the entries of the point in
// the rig's muscle table (docs/model.md §1: the points within a muscle's zone of influence)
// with a non-zero displacement at activation 1. Empty for a point out of range.
std::vector<uint32_t> MusclesReachingPoint(const Rig& rig, uint32_t point);

// The muscles panel's regions (grouping by the name's anatomical prefix; "other" for a name
// the table does not know): "brow and forehead", "eyes", "nose", "cheeks", "mouth and chin".
const char* MuscleRegion(const std::string& muscle_name);
// The regions in panel order, each with the indices of its muscles (rig order), regions
// without a muscle left out.
struct MuscleGroup {
  std::string region;
  std::vector<uint32_t> muscles;
};
std::vector<MuscleGroup> GroupMuscles(const std::vector<std::string>& muscle_names);

// The other side's muscle of a NAME_L / NAME_R pair, or -1 (no suffix, or no such muscle).
int MirrorMuscle(const std::vector<std::string>& muscle_names, uint32_t muscle);

}  // namespace mimetic::viewer
