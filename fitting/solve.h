// fitting/solve.h: the muscle activations that make a rig's output closest to a target
// shape of the rig's own input topology (`mimetic solve`).
//
// Method (docs/model.md §13). The muscles alone move each point by sum_m a_m U_m (§1-3):
// linear in the activations a in [0, 1]. So the first step is a bounded linear least-squares
// solve (fitting/box_least_squares.h) on the muscle basis U (one rig evaluation per muscle at
// a = 1, skin layers off), over the target's vertices weighted 1 where the target moves more
// than `region_threshold` from the rig's rest shape and `outside_weight` elsewhere (so the
// solve does not buy the region's fit by moving still skin). The skin layers (§4-8) are not
// linear; `refine_steps` Gauss-Newton steps with every layer the rig has then correct for
// them: a Jacobian by forward differences (one evaluation per unknown), a bounded step, and a
// step halved up to four times until the weighted residual drops.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "rig/runtime/rig.h"

namespace mimetic {

struct SolveOptions {
  // Muscles to solve for (indices, rig order); empty = all. The others stay at 0.
  std::vector<uint32_t> muscles;
  // Tie each NAME_L / NAME_R pair (both solved) to one value; other muscles stay single.
  bool mirror = false;
  // Mesh units; < 0: 2% of the target's largest displacement from the rest shape.
  float region_threshold = -1.f;
  float outside_weight = 0.25f;  // in [0, 1]
  int refine_steps = 3;          // >= 0; 0 = the linear solve only
  // Evaluate with every skin layer the rig has (true), or the muscles alone (false: the
  // linear solve is then exact and no refinement step runs).
  bool skin_layers = true;
  double ridge = 1e-9;           // Tikhonov weight, relative to the largest basis column norm^2
  // How much more the error's component along the neutral's vertex normals (its height, what
  // a surface distance sees) counts than the components along the skin: the objective sums
  // w_v (|e_v|^2 + (height_weight - 1) (n_v . e_v)^2). 1 = plain per-vertex least squares;
  // in [1e-6, 1e6].
  double height_weight = 1.0;
  // Also solve the linear problem on the muscle basis with no bounds (SolveResult::reach):
  // what these muscles could make with any activations, negative or above 1 included. It
  // tells a target's motion that no activation of the rig's muscles makes (the residual left
  // at the unbounded optimum) from what the bounds [0, 1] cost (docs/model.md §13).
  bool reach = false;
};

// The unbounded linear solve (SolveOptions::reach), muscles alone, over the same weights.
struct SolveReach {
  std::vector<float> activations;  // one per muscle, rig order, unclamped (0 if not solved)
  double motion = 0.0;             // weighted sum of |target - rest|^2: the real motion
  double residual = 0.0;           // weighted sum of squares left at the unbounded optimum
  double bounded_residual = 0.0;   // the same for the bounded linear solve (muscles alone)
  std::vector<float3> posed;       // rest + sum_m a_m U_m, the target's vertices
  // The unbounded optimum of the height alone: the same problem on the components along the
  // neutral's vertex normals (ComputeVertexNormals), the error a surface distance sees; the
  // activations, the weighted sums of squared heights of the motion and of what is left, and
  // rest + sum_m a_m U_m at those activations (its full motion, not only the height).
  std::vector<float> height_activations;
  double height_motion = 0.0, height_residual = 0.0;
  std::vector<float3> height_posed;
};

struct SolveResult {
  std::vector<float> activations;  // one per muscle, rig order, in [0, 1]
  uint32_t unknowns = 0;           // after mirroring
  uint32_t region_count = 0;       // target vertices in the region
  float region_threshold = 0.f;    // the threshold used, mesh units
  double neutral_residual = 0.0;   // weighted sum of squared distances at a = 0
  double linear_residual = 0.0;    // after the linear solve (layers as `skin_layers`)
  double residual = 0.0;           // final (layers as `skin_layers`)
  int refine_steps_taken = 0;      // steps that lowered the residual
  std::vector<float3> posed;       // the rig's output at `activations`, the target's vertices
  bool has_reach = false;          // SolveOptions::reach was set
  SolveReach reach;
};

// `neutral` is the rig's input mesh (LoadedRig::mesh); `target` must share its topology (the
// same vertex count and triangles), and the rig's first #V output vertices must be the input
// vertices (they are: refinement appends its new vertices). Returns false and records why
// for: a target of another topology, a rig whose output does not start with the neutral's
// vertices, no muscle to solve for, a muscle index out of range, a pair under `mirror` with
// only one side selected, options out of range, a target that does not move at all.
// Deterministic.
bool SolveActivations(const Rig& rig, const MeshData& neutral, const MeshData& target,
                      const SolveOptions& options, SolveResult* out, Diagnostics* diag);

}  // namespace mimetic
