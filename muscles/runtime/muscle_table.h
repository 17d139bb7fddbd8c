// muscles/runtime/muscle_table.h: compiled muscle influences and the per-frame muscle job.
//
// Muscles are evaluated on the rest pose and their displacements summed (docs/model.md §1, step 1).
// Waters' displacement is linear in the contraction k = activation * strength (docs/model.md §2-3),
// so each muscle's effect on a point is a fixed vector times its activation. The rig compiler
// stores, per point, the muscles that reach it and that vector at activation 1; a frame then
// costs one multiply-add per (point, muscle) pair that actually interacts, not muscles x points.
//
// Layout is point-major (CSR): a point's entries are contiguous, so any point range can be
// evaluated on its own, and the result for a point never depends on how ranges are split.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/span.h"

namespace mimetic {

struct MuscleInfluence {
  uint32_t muscle;       // index into the rig's muscles
  float3 displacement;   // mesh units, at activation 1
};
static_assert(sizeof(MuscleInfluence) == 16, "MuscleInfluence is 16 bytes");

struct MuscleTable {
  uint32_t muscle_count = 0;
  std::vector<uint32_t> offsets;          // #points + 1; entries of point p: [offsets[p], offsets[p+1])
  std::vector<MuscleInfluence> entries;   // sorted by point, then by muscle index

  uint32_t point_count() const { return offsets.empty() ? 0u : uint32_t(offsets.size() - 1); }
  // Points a muscle reaches (offline statistics; O(entries)).
  uint32_t CountInfluenced(uint32_t muscle) const;
};

// out[p] = rest[p] + sum over p's entries of clamp(activations[muscle], 0, 1) * displacement,
// for p in [begin, end). NaN activations count as 0. Owns nothing, allocates nothing.
struct MuscleDeformJob {
  // Validate(): table non-null and consistent; activations.size() >= table->muscle_count;
  // rest_points and out_points >= table->point_count(); begin <= end <= point_count().
  bool Validate() const;
  bool Run() const;

  const MuscleTable* table = nullptr;
  span<const float> activations;   // one per muscle, rig order; clamped to [0, 1]
  span<const float3> rest_points;  // #points, mesh units
  span<float3> out_points;         // #points; only [begin, end) is written; may not alias rest
  uint32_t begin = 0;
  uint32_t end = 0;                // exclusive
};

}  // namespace mimetic
