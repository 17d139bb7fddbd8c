// fuzz/fuzz_mrig_seed.cpp: writes the seed of fuzz_mrig, a small real .mrig of the procedural
// test surface with every section non-empty (thickness, a wrinkle region per muscle, one curve
// wrinkle of each profile):  fuzz_mrig_seed FILE.mrig   (fuzz/run.sh runs it; the seed is
// generated, not committed, so that it always has the current format).
#include <cstdio>
#include <string>

#include "content/procedural.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/rig_binary.h"

int main(int argc, char** argv) {
  using namespace mimetic;
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_mrig_seed FILE.mrig\n");
    return 2;
  }
  const MeshData mesh = MakeSurfaceMesh(9, 9, 100.f, 100.f, 10.f);
  RigSpec spec = MakeSurfaceRigSpec(2, 100.f, 100.f, 10.f, 0.4f, 3.f);
  spec.thickness.value = 3.f;
  spec.muscle_wrinkles.resize(spec.muscles.size());
  for (size_t m = 0; m < spec.muscles.size(); ++m) {
    MuscleWrinkleSpec w;
    w.lambda_w = 0.2f;
    w.depth = 0.5f;
    w.shape = 0.5f;
    w.phi_c = spec.muscles[m].type == MuscleType::kLinear ? 0.2f : 0.f;
    w.h_c = spec.muscles[m].type == MuscleType::kSheet ? 0.1f * spec.muscles[m].sheet.width : 0.f;
    spec.muscle_wrinkles[m] = w;
  }
  for (int k = 0; k < 3; ++k) {
    NamedCurveWrinkle c;
    c.name = "curve_" + std::to_string(k);
    c.spec.control[0] = {0.2f, 0.2f + 0.3f * k};
    c.spec.control[1] = {0.4f, 0.25f + 0.3f * k};
    c.spec.control[2] = {0.6f, 0.15f + 0.3f * k};
    c.spec.control[3] = {0.8f, 0.2f + 0.3f * k};
    c.spec.depth = 0.5f;
    c.spec.width = 15.f;
    c.spec.modulation = k == 1 ? CurveWrinkleModulation::kArea : CurveWrinkleModulation::kDirectional;
    c.spec.profile = CurveWrinkleProfile(k);
    c.spec.rest_amplitude = 0.2f;
    spec.curve_wrinkles.push_back(c);
  }
  spec.refinement.enabled = false;
  Rig rig;
  Diagnostics diag;
  if (!BuildRig(spec, mesh, {}, &rig, &diag)) {
    std::fprintf(stderr, "fuzz_mrig_seed: the surface rig does not build\n%s", diag.Format().c_str());
    return 1;
  }
  const RigBinaryInfo info{"mm", uint32_t(mesh.vertex_count())};
  const std::string bytes = WriteRigBinary(rig.data(), &info);
  std::FILE* f = std::fopen(argv[1], "wb");
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
    std::fprintf(stderr, "fuzz_mrig_seed: cannot write %s\n", argv[1]);
    return 1;
  }
  std::printf("fuzz_mrig_seed: wrote %s (%zu bytes)\n", argv[1], bytes.size());
  return 0;
}
