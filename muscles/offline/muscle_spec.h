// muscles/offline/muscle_spec.h: authored description of Waters muscles (docs/model.md §2-3).
// All lengths are in mesh units; angles in radians here (the rig file stores degrees).
#pragma once

#include <string>

#include "core/math.h"

namespace mimetic {

// Waters linear muscle, docs/model.md §2.
struct LinearMuscleSpec {
  float3 attachment;         // v1, on the bone; the skin moves toward it
  float3 insertion;          // v2, in the skin; v2 - v1 is the zone's axis
  float zone_angle = 0.f;    // Omega, radians, (0, pi)
  float falloff_start = 0.f; // Rs, > 0
  float falloff_end = 0.f;   // Rf, > Rs
};

// Waters sheet muscle, docs/model.md §3 (geometry as in Zhang et al. 2005, §2.3).
struct SheetMuscleSpec {
  float3 attachment[2];      // mA1, mA2: the attachment line
  float3 insertion[2];       // mI1, mI2: the insertion line
  float length = 0.f;        // Ls, AOI length along the central fiber, > 0
  float width = 0.f;         // Ws, AOI width across it, > 0
  float falloff_start = 0.f; // Rs, in (0, Ls): where Fl peaks
};

enum class MuscleType { kLinear, kSheet };

// How a muscle's influence falls to zero at the edges of its zone (docs/model.md §2-3):
// kWaters, Waters' cosines, which reach 0 with a non-zero slope, so the skin creases along the
// zone's edges; kSmooth, the same factors squared, which reach 0 with zero slope (C1).
enum class MuscleFalloff { kWaters, kSmooth };
// Which way the skin goes (docs/model.md §2-3, "Motion"): kChord, Waters' own, straight toward
// the attachment under the skin, so every motion has a part into the surface; kTangent, that
// motion with its part along the rest surface normal removed, so the skin slides over the
// tissue beneath instead of sinking into it.
enum class MuscleMotion { kChord, kTangent };

struct MuscleSpec {
  std::string name;       // unique within a rig
  MuscleType type = MuscleType::kLinear;
  MuscleFalloff falloff = MuscleFalloff::kWaters;  // the paper's, for files that do not say
  MuscleMotion motion = MuscleMotion::kChord;      // the paper's, for files that do not say
  // kTangent only: the radius (mesh units) of the ball the rest normals are averaged over
  // before the projection (geometry/normal_field.h); 0 = each point's own normal.
  float tangent_radius = 0.f;
  float strength = 0.f;   // contraction at activation 1, mesh units (k = activation * strength)
  LinearMuscleSpec linear;  // used when type == kLinear
  SheetMuscleSpec sheet;    // used when type == kSheet
};

const char* MuscleTypeName(MuscleType type);
const char* MuscleFalloffName(MuscleFalloff falloff);  // "waters", "smooth"
const char* MuscleMotionName(MuscleMotion motion);     // "chord", "tangent"

}  // namespace mimetic
