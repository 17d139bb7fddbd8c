// muscles/offline/muscle_builder.h: compiles muscle specs into a MuscleTable on rest points.
#pragma once

#include <vector>

#include "core/span.h"
#include "muscles/offline/muscle_spec.h"
#include "muscles/runtime/muscle_table.h"

namespace mimetic {

// For every point and muscle, evaluates docs/model.md §2-3 at activation 1 (k = strength) and keeps
// non-zero displacements. Specs must already be valid (the rig loader checks them).
MuscleTable BuildMuscleTable(span<const MuscleSpec> muscles, span<const float3> rest_points);

}  // namespace mimetic
