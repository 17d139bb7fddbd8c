// muscles/offline/waters.h: Waters' muscle model evaluated directly from its formulas.
//
// Waters, "A Muscle Model for Animating Three-Dimensional Facial Expression", SIGGRAPH 1987,
// as restated in docs/model.md §2 (linear) and §3 (sheet, geometry of Zhang et al. 2005 §2.3).
// The rig compiler (muscle_builder.h) evaluates these once per vertex at unit activation;
// tests compare the compiled tables against them.
#pragma once

#include "core/math.h"
#include "muscles/offline/muscle_spec.h"

namespace mimetic {

// docs/model.md §2, angular factor A = cos(mu / Omega * pi/2); 0 outside [0, Omega].
double WatersAngularFactor(double mu, double omega);
// docs/model.md §2, radial factor R(D): rises from 0 at D = 0 to 1 at Rs, falls to 0 at Rf.
double WatersRadialFactor(double d, double rs, double rf);
// docs/model.md §3 (choice): the sheet's length fall-off Fl(lambda), lambda = l / Ls; it rises over
// [0, Rs/Ls] and falls to 0 at 1; 0 outside [0, 1].
double SheetLengthFalloff(double lambda, double rs_over_ls);
// docs/model.md §3 (choice): the sheet's width fall-off Fw(gamma) = cos(gamma * pi/2); 0 outside [0, 1].
double SheetWidthFalloff(double gamma);

// docs/model.md §2-3 (choice): the smooth fall-off is Waters' factor squared, F^2. Where F
// reaches 0 with slope F' != 0 (the zone's angle and radius, the sheet's width and length
// ends), (F^2)' = 2 F F' = 0: the displacement field is C1 there, so the skin does not fold
// along straight lines; where F = 1 and F' = 0 (the peaks) nothing changes.
double ApplyFalloff(double waters_factor, MuscleFalloff falloff);

// Displacement of point `p` for contraction `k` (mesh units; activation * strength).
// Linear, docs/model.md §2: k * A * R * (v1 - p) / |v1 - p|, toward the attachment.
float3 LinearMuscleDisplacement(const LinearMuscleSpec& m, float3 p, float k,
                                MuscleFalloff falloff = MuscleFalloff::kWaters);
// Sheet, docs/model.md §3: -k * Fl(lambda) * Fw(gamma) * f, f the unit fiber direction mAc -> mIc.
// `l` is measured from the attachment line's midpoint along f: l = (p - mAc) . f, and `h` is
// the distance from p to the central fiber's line (choice: 001 leaves both implicit).
float3 SheetMuscleDisplacement(const SheetMuscleSpec& m, float3 p, float k,
                               MuscleFalloff falloff = MuscleFalloff::kWaters);
// The muscle's own type and fall-off.
float3 MuscleDisplacement(const MuscleSpec& m, float3 p, float k);

// docs/model.md §11 (choice): how sharply the muscle's fall-off profile (its displacement
// magnitude over its strength, 1 at the peak) bends near `p`, in 1 / mesh units^2: the larger of
// its second derivatives along the two directions the fall-off varies in (linear: radially and
// around the axis, arc length D mu; sheet: along the fibre and across it), each factor's own
// bounded by the smooth fall-off's largest, |(cos^2(x pi/2))''| <= pi^2/2 per fall-off width
// squared, times the other factor's value:
//   linear: pi^2/2 * max(A^2 / W_r^2, R^2 / (Omega D)^2),  W_r = Rs or Rf - Rs;
//   sheet:  pi^2/2 * max(Fw^2 / W_l^2, Fl^2 / (Ws/2)^2),  W_l = Rs or Ls - Rs.
// Beyond the zone by up to half a fall-off width (radius, length, width; the angle by half of
// Omega) it is the nearest edge's, so triangles across the edge are refined too; 0 farther out
// and for degenerate geometry. Independent of the strength (so tuning a strength never changes
// the refined mesh) and of the fall-off kind (Waters' own bends half as much in the zone but
// kinks at its edges whatever the sampling), so the two kinds compare on the same mesh. Linear
// interpolation over an edge of length h errs by at most h^2 c / 8 of the peak: refinement keeps
// that under refinement.falloff_error.
double MuscleFalloffCurvature(const MuscleSpec& m, float3 p);

// A ball outside which MuscleFalloffCurvature(m, p) is 0 (its zone grown by half a fall-off
// width, with a margin for rounding), for a caller that asks at many points to skip the far
// ones; `all` when m's geometry gives none (degenerate or not finite: then ask everywhere).
struct MuscleBall {
  double x = 0, y = 0, z = 0, r = 0;
  bool all = true;
  bool Holds(float3 p) const {
    const double dx = p.x - x, dy = p.y - y, dz = p.z - z;
    return all || !(dx * dx + dy * dy + dz * dz > r * r);
  }
};
MuscleBall MuscleFalloffCurvatureBall(const MuscleSpec& m);

}  // namespace mimetic
