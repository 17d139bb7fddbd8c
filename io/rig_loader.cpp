// io/rig_loader.cpp: LoadRig.
#include "io/rig_loader.h"

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "io/image.h"
#include "io/json_reader.h"
#include "io/mesh_io.h"
#include "io/rig_file.h"
#include "rig/runtime/rig_binary.h"

#include <cctype>
#include <cstdio>

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

bool LoadCompiledRig(const std::string& rig_path, LoadedRig* out, Diagnostics* diag) {
  LoadedRig loaded;
  std::string bytes, why;
  RigBinaryInfo info;
  if (!ReadRigBinaryFile(rig_path, &bytes, &why) ||
      !ReadRigBinary(span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()),
                                         bytes.size()),
                     &loaded.rig, &info, &why)) {
    diag->Error(rig_path, why);
    return false;
  }
  loaded.compiled = true;
  loaded.spec.units = info.units;
  loaded.source_vertex_count = info.source_vertex_count;
  *out = std::move(loaded);
  return true;
}

}  // namespace

bool IsCompiledRigPath(const std::string& path) {
  std::string lower = path;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (lower.size() >= 5 && lower.compare(lower.size() - 5, 5, ".mrig") == 0) return true;
  if (!CheckRegularFile(path, kMaxRigBinaryFileBytes, "rig file").empty()) return false;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  uint8_t tag[4] = {};
  const size_t got = std::fread(tag, 1, 4, f);
  std::fclose(f);
  return got == 4 && HasRigBinaryTag(span<const uint8_t>(tag, 4));
}

bool LoadRig(const std::string& rig_path, LoadedRig* out, Diagnostics* diag,
             const BuildOptions& options) {
  if (IsCompiledRigPath(rig_path)) return LoadCompiledRig(rig_path, out, diag);
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
