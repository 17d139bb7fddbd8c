// fitting/calibrate.h: calibrate a muscle template on real expression shapes
// (`mimetic calibrate`, docs/fidelity.md "Calibration").
//
// Method (docs/model.md §17). The template is fitted to a neutral head; for each training
// shape (same topology as the head) the muscles alone are solved for (bounded linear least
// squares on the muscle basis, as `mimetic solve` does, weight 1 where the shape moves more
// than `region_fraction` of its largest motion and `outside_weight` elsewhere). The score of a
// shape is its residual over the neutral's (0 = reproduced, 1 = no better than not moving),
// measured with the normal part of each vertex's residual counted `normal_weight` times more
// (Bando's surface distance sees that part); the objective is the mean score. A coordinate search then changes one parameter of one
// muscle at a time (strength, fall-off radii, zone angle or sheet size, the offsets of its
// attachment and insertion, the attachment's depth, its motion; where the seed names a
// muscle's motion tangent, the radius its normals are averaged over, 0 to 1 s), keeps a change when the
// objective drops, and halves a parameter's step when neither direction helps. Mirrored
// muscles change together (the template stays left/right symmetric).
//
// Anatomical constraints: every parameter stays in a box around the seed (offsets within
// `offset_reach` of the seed's, lengths and strengths within fixed factors), attachments stay
// at least `min_attachment_depth` under the skin and deeper than the insertion, insertions
// stay within `max_insertion_depth` of it, and a change is refused when the muscle no longer
// moves its probe point the way fitting/anatomy.h says, or when some combination of the
// muscles of a region (fitting/anatomy.h) at 0 or 1, or every muscle at 1, turns a triangle
// over (docs/model.md §16), on the training head and on every head of `check_heads`, or when
// the muscles would fold the skin along their zones' edges more than `crease_fraction` allows.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "fitting/landmarks.h"
#include "fitting/muscle_template.h"
#include "geometry/mesh.h"

namespace mimetic {

struct CalibrationShape {
  std::string name;
  const MeshData* mesh = nullptr;  // same vertices and triangles as the neutral head
};

// Another head the constraints must hold on (its muscles are fitted and checked, not scored).
struct CalibrationHead {
  std::string name;
  const MeshData* mesh = nullptr;
  const Landmarks* landmarks = nullptr;
  bool anatomy = true;  // check the anatomy table here too (false: the fold-over rule only)
};

struct CalibrationOptions {
  int passes = 3;                 // coordinate-search sweeps over every parameter
  float region_fraction = 0.02f;  // of the shape's largest motion
  float outside_weight = 0.25f;
  // The score's metric (docs/model.md §17): the residual's part along the neutral's vertex
  // normal counts (1 + normal_weight) times, its tangential part once. The solve itself stays
  // the plain weighted least squares of `mimetic solve`; 0 = the score is its residual. 1 (the
  // default) was chosen on the ICT report (docs/calibration.md): 0.5 and 2 did worse overall.
  float normal_weight = 1.f;
  float offset_reach = 0.2f;      // units of s, around the seed's offsets
  float min_attachment_depth = 0.03f;  // units of s
  float max_insertion_depth = 0.04f;   // units of s
  // On every head, a point whose ray misses the mesh (an attachment below a short neck) may
  // lie at most this far from the surface point used (units of s; the fit refuses above
  // kMaxOffMeshDistance, 0.5):
  // the margin lets a head a little different from the check heads still fit the result.
  float max_miss = 0.4f;
  // The crease rule (docs/model.md §2-3): on every head, each muscle alone at 1 (its own
  // fall-off) may crease the skin up to this fraction of the largest crease number the muscles
  // make there with Waters' fall-offs (fitting/creases.h; measured on the head's triangles
  // split once at their midpoints); a change may not push a muscle over that cap, nor make
  // one that is over it (from the seed) crease more. A third is the fidelity target for the
  // smooth fall-offs; 0 (the default) turns the rule off (docs/calibration.md: what it cost).
  float crease_fraction = 0.f;
  bool calibrate_motion = true;   // also try each muscle's other motion (chord / tangent)
  std::vector<std::string> muscles;  // source muscle names to change; empty = every muscle
  // Heads besides the training head on which every change must keep the anatomy and the
  // fold-over rule (the sample head, MakeHuman): the calibrated template must generalise.
  std::vector<CalibrationHead> check_heads;
  std::function<void(const std::string&)> progress;  // one line per accepted change / pass
};

struct CalibrationReport {
  std::vector<std::string> shapes;
  std::vector<double> score_before, score_after;  // per shape
  double objective_before = 0.0, objective_after = 0.0;
  int evaluations = 0, accepted = 0, refused_anatomy = 0;
  // Per head (the training head, then check_heads): the largest crease number of the muscles
  // over their largest with Waters' fall-offs (docs/model.md §2-3), of the seed and of the
  // result; empty without the crease rule.
  std::vector<double> crease_ratio_before, crease_ratio_after;
};

// Shape scores of `tmpl` on `head` (no change): what CalibrateTemplate minimises, for reports.
bool ScoreTemplate(const MuscleTemplate& tmpl, const MeshData& head, const Landmarks& landmarks,
                   const std::vector<CalibrationShape>& shapes, const CalibrationOptions& options,
                   std::vector<double>* scores, Diagnostics* diag);

// Calibrates `seed` (thickness and wrinkles are copied unchanged). Errors: no shape, a shape
// of another topology or that does not move, a seed the fit refuses, a muscle name in
// options.muscles that the seed lacks. Deterministic.
bool CalibrateTemplate(const MuscleTemplate& seed, const MeshData& head,
                       const Landmarks& landmarks, const std::vector<CalibrationShape>& shapes,
                       const CalibrationOptions& options, MuscleTemplate* out,
                       CalibrationReport* report, Diagnostics* diag);

}  // namespace mimetic
