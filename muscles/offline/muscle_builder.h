// muscles/offline/muscle_builder.h: compiles muscle specs into a MuscleTable on rest points.
#pragma once

#include <vector>

#include "core/span.h"
#include "geometry/normal_field.h"
#include "muscles/offline/muscle_spec.h"
#include "muscles/runtime/muscle_table.h"

namespace mimetic {

// docs/model.md §2-3, "Motion": `d` itself for kChord; for kTangent, d - (d . n) n, the part of
// d across the surface (`normal` is the unit rest normal; a zero normal leaves d as it is).
float3 ApplyMuscleMotion(float3 d, float3 normal, MuscleMotion motion);

// For every point and muscle, evaluates docs/model.md §2-3 at activation 1 (k = strength) and keeps
// non-zero displacements. Specs must already be valid (the rig loader checks them). Each muscle
// is evaluated only at the points inside a sphere that holds its zone (a grid finds them), so
// the cost is linear in #points + #muscles + #influences, not #points x #muscles; the table is
// the same as evaluating every pair. Non-finite points are moved by no muscle.
// `rest_normals` (unit, one per point) is read by kTangent muscles only; when it is empty they
// move as kChord.
MuscleTable BuildMuscleTable(span<const MuscleSpec> muscles, span<const float3> rest_points,
                             span<const float3> rest_normals = {});
// The same with each kTangent muscle projecting on `field`'s normals averaged over its own
// `tangent_radius` (the points' own normals for 0); `field` is of these rest points (null: every
// muscle moves as kChord).
MuscleTable BuildMuscleTable(span<const MuscleSpec> muscles, span<const float3> rest_points,
                             NormalField* field);

// The number of points each muscle moves (table.muscle_count entries), in one pass over the
// entries (MuscleTable::CountInfluenced per muscle would be #muscles x #entries).
std::vector<uint32_t> CountInfluencedPoints(const MuscleTable& table);

}  // namespace mimetic
