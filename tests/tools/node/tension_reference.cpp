// tests/tools/node/tension_reference.cpp: the independent reference of the three.js tension
// check (three_tension.mjs, ctest tools.bake_node_three_tension):
//   tension_reference RIG CLIP LIBRARY T OUT
// evaluates RIG at CLIP's time T here (LoadRig, BuildClip with LIBRARY's expressions,
// ClipSampleJob, EvaluateJob with out_tension; not `mimetic play`'s bake) and writes per vertex
// (r - 1, eps) as f32 in the host's byte order (little-endian on the machines the
// tests run on) to OUT. Exit 1 with a message on any failure.
#include <cstdio>
#include <string>
#include <vector>

#include "expressions/offline/clip_builder.h"
#include "expressions/runtime/clip_sample_job.h"
#include "io/clip_file.h"
#include "io/expression_library.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"

int main(int argc, char** argv) {
  using namespace mimetic;
  if (argc != 6) {
    std::fprintf(stderr, "usage: tension_reference RIG CLIP LIBRARY T OUT\n");
    return 2;
  }
  Diagnostics diag;
  LoadedRig loaded;
  ClipSpec spec;
  std::vector<Expression> library;
  CompiledClip clip;
  if (!LoadRig(argv[1], &loaded, &diag) || !LoadClip(argv[2], &spec, &diag) ||
      !LoadExpressionLibrary(argv[3], &library, &diag) ||
      !BuildClip(spec, loaded.rig.muscle_names(), library, &clip, &diag)) {
    std::fprintf(stderr, "tension_reference: %s", diag.Format().c_str());
    return 1;
  }
  const Rig& rig = loaded.rig;
  std::vector<float> activations(rig.muscle_count()), positions(3 * size_t(rig.vertex_count())),
      tension(2 * size_t(rig.vertex_count()));
  float jaw = 0.f;
  ClipSampleJob sample;
  sample.clip = &clip;
  sample.time = std::stof(argv[4]);
  sample.out_activations = activations;
  sample.out_jaw = span<float>(&jaw, 1);
  if (!sample.Run()) {
    std::fprintf(stderr, "tension_reference: ClipSampleJob refused the job\n");
    return 1;
  }
  EvaluateContext context(rig);
  EvaluateJob job;
  job.rig = &rig;
  job.context = &context;
  job.activations = activations;
  job.jaw = jaw;
  job.out_positions = positions;
  job.out_tension = tension;
  if (!job.Run()) {
    std::fprintf(stderr, "tension_reference: EvaluateJob refused the job\n");
    return 1;
  }
  for (size_t v = 0; v < tension.size(); v += 2) tension[v] -= 1.f;  // r - 1, as the bake
  std::FILE* f = std::fopen(argv[5], "wb");
  const bool ok = f && std::fwrite(tension.data(), sizeof(float), tension.size(), f) ==
                           tension.size();
  if (!f || std::fclose(f) != 0 || !ok) {
    std::fprintf(stderr, "tension_reference: cannot write %s\n", argv[5]);
    return 1;
  }
  return 0;
}
