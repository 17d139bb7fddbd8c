// Builds the test surface's rig, raises one muscle and checks that some vertex moved.
#include <cmath>
#include <cstdio>
#include <vector>
#include "content/procedural.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
int main() {
  using namespace mimetic;
  const MeshData mesh = MakeSurfaceMesh(20, 20, 40.f, 40.f, 4.f);
  Rig rig;
  Diagnostics diag;
  if (!BuildRig(MakeSurfaceRigSpec(2, 40.f, 40.f, 4.f, 0.5f, 2.f), mesh, {}, &rig, &diag)) return 2;
  EvaluateContext context(rig);
  std::vector<float> weights(rig.muscle_count(), 1.f), out(3 * rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &context;
  job.activations = weights;
  job.out_positions = out;
  if (!job.Run()) return 3;
  float moved = 0.f;
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    moved += std::abs(out[3 * v + 2] - mesh.positions[v].z);
  std::printf("consumer: %u vertices, summed |dz| = %g\n", rig.vertex_count(), moved);
  return moved > 0.f ? 0 : 1;
}
