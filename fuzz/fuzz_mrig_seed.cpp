// fuzz/fuzz_mrig_seed.cpp: writes the seed of fuzz_mrig, a small real .mrig of the procedural
// test surface with every section non-empty (thickness, a wrinkle region per muscle, one curve
// wrinkle of each profile, a gate on the first wrinkled muscle so that the optional section 47
// is there too):  fuzz_mrig_seed FILE.mrig   (fuzz/run.sh runs it; the seed is generated, not
// committed, so that it always has the current format).
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
  AddEverySkinLayer(&spec, 0.2f, 15.f);
  for (auto& w : spec.muscle_wrinkles)
    if (w) {
      w->gate = 0.5f;  // docs/model.md §6: .mrig section 47
      break;
    }
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
