// bench/evaluate_setup.h: an EvaluateJob over its own context and output buffers (every
// benchmark's instance of a rig).
#pragma once

#include <vector>

#include "rig/runtime/evaluate_job.h"

namespace mimetic::bench {

struct EvaluateSetup {
  EvaluateSetup(const Rig& rig, SkinLayers layers = {})
      : context(rig), activations(rig.muscle_count()), positions(3 * rig.vertex_count()),
        normals(3 * rig.vertex_count()) {
    job.rig = &rig;
    job.context = &context;
    job.activations = activations;
    job.out_positions = positions;
    job.out_normals = normals;
    job.layers = layers;
  }
  EvaluateContext context;
  std::vector<float> activations, positions, normals;
  EvaluateJob job;
};

}  // namespace mimetic::bench
