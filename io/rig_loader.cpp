// io/rig_loader.cpp: LoadRig.
#include "io/rig_loader.h"

#include "io/image.h"
#include "io/mesh_io.h"
#include "io/rig_file.h"

namespace mimetic {

bool LoadRig(const std::string& rig_path, LoadedRig* out, Diagnostics* diag,
             const BuildOptions& options) {
  Diagnostics local;
  LoadedRig loaded;
  if (!LoadRigSpec(rig_path, &loaded.spec, &local)) {
    diag->Append(local, rig_path);
    return false;
  }
  if (!ImportMesh(loaded.spec.mesh_path, loaded.spec.mesh_name, &loaded.mesh, &local)) {
    diag->Append(local, loaded.spec.mesh_path);
    return false;
  }
  diag->Append(local, loaded.spec.mesh_path);
  local.Clear();
  if (loaded.spec.thickness.kind == ThicknessSpec::Kind::kImage &&
      !LoadGrayImage(loaded.spec.thickness.image_path, "thickness.path", "thickness image",
                     &loaded.spec.thickness.image, &local)) {
    diag->Append(local, rig_path);
    return false;
  }
  const bool ok = BuildRig(loaded.spec, loaded.mesh, options, &loaded.rig, &local);
  diag->Append(local, rig_path);
  if (!ok) return false;
  *out = std::move(loaded);
  return true;
}

}  // namespace mimetic
