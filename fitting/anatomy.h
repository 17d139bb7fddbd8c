// fitting/anatomy.h: which way each muscle of the default template must move the skin.
//
// A fitted or calibrated muscle is anatomically plausible when it moves a probe point (an
// iBUG landmark near its insertion, or the insertion's own surface point) in the direction
// the anatomy literature gives for that muscle (Zhang et al. 2005 Fig. 1; Bando et al. 2003
// §6; Ekman and Friesen's FACS manual for the action units), by a clear amount. The fit tests
// and `mimetic calibrate` (fitting/calibrate.h) check the same table, so the calibration
// cannot buy a better score with a muscle that pulls the wrong way.
#pragma once

#include <string>
#include <vector>

#include "core/math.h"
#include "core/span.h"
#include "fitting/fit.h"
#include "geometry/mesh.h"
#include "muscles/offline/muscle_spec.h"

namespace mimetic {

struct MuscleAnatomy {
  const char* muscle;  // name without _L / _R
  int probe;           // iBUG landmark on the left side (mirrored for _R), or -1: the insertion
  int lateral;         // expected sign of the motion away from the midline (0 = unchecked)
  int up;              // expected sign of the motion along y of the face frame (0 = unchecked)
  const char* action;  // what the muscle does, for messages
};

// The table for the default template's muscles.
span<const MuscleAnatomy> DefaultMuscleAnatomy();

// The anatomy entry for a muscle name ("zygomaticus_major_L"), or nullptr.
const MuscleAnatomy* FindMuscleAnatomy(const std::string& muscle_name);

// Where to probe one muscle: the mesh vertex nearest the probe landmark (mirrored for _R) or,
// for probe -1, nearest the insertion's surface point in `points` (the fit's report).
struct AnatomyProbe {
  uint32_t vertex = 0;
  bool found = false;
};
AnatomyProbe FindAnatomyProbe(const MuscleAnatomy& a, const std::string& muscle_name,
                              const MeshData& head, span<const float3> landmarks,
                              span<const PlacedPoint> points);

// Checks that `muscle` (fitted, mesh units) at activation 1 moves the probe vertex the way `a`
// says: each checked component (lateral, up, in the face frame) has the expected sign and is
// at least `min_fraction` of the muscle's strength. `normal` is the probe's unit rest normal
// (for tangent motion). Returns "" when it does, else what is wrong.
std::string CheckMuscleAnatomy(const MuscleAnatomy& a, const MuscleSpec& muscle,
                               const FaceFrame& frame, float3 probe_position, float3 normal,
                               float min_fraction = 0.05f);

// Groups of muscles that act on the same skin (docs/model.md §16): one brow, the upper and the
// lower mouth of one side, and across the midline the glabella, the nose and upper lip and the
// chin. Every combination of a group's muscles at 0 or 1 must leave every triangle the right
// way up; the fold-over tests sample these corners and `mimetic calibrate` refuses a change
// that breaks one.
struct MuscleRegion {
  std::string name;
  std::vector<std::string> muscles;
};
std::vector<MuscleRegion> DefaultMuscleRegions();

}  // namespace mimetic
