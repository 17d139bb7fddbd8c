// io/rig_loader.cpp: LoadRig.
#include "io/rig_loader.h"

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "io/image.h"
#include "io/json_reader.h"
#include "io/mesh_io.h"
#include "io/rig_file.h"

namespace mimetic {
namespace {

// When the rig file itself has errors, its mesh is still checked for existence, so that one
// run of `validate` reports both: the mesh path is taken from the text (`mesh.path`) when the
// JSON parses and that key is a string.
void CheckMeshOfBrokenRig(const std::string& rig_path, Diagnostics* diag) {
  std::string text;
  Diagnostics ignored;
  if (!ReadFile(rig_path, &text, &ignored, kMaxJsonFileBytes, "rig file")) return;
  if (!json_reader::CheckJsonText(text).empty()) return;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (!j.is_object() || !j.contains("mesh") || !j["mesh"].is_object()) return;
    const auto& mesh = j["mesh"];
    if (!mesh.contains("path") || !mesh["path"].is_string()) return;
    const std::string rel = mesh["path"].get<std::string>();
    if (rel.empty()) return;
    const std::string path = JoinPath(DirectoryOf(rig_path), rel);
    const std::string why = CheckRegularFile(path, kMaxMeshFileBytes, "mesh file");
    if (!why.empty()) diag->Error(rig_path + ": mesh.path: " + path, why);
  } catch (const std::exception&) {
    // invalid JSON: the rig's own messages say so
  }
}

}  // namespace

bool LoadRig(const std::string& rig_path, LoadedRig* out, Diagnostics* diag,
             const BuildOptions& options) {
  Diagnostics local;
  LoadedRig loaded;
  // LoadRigSpec names the file in its messages already.
  if (!LoadRigSpec(rig_path, &loaded.spec, diag)) {
    CheckMeshOfBrokenRig(rig_path, diag);
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
