// tools/cmd_export_blendshapes.cpp: `mimetic export-blendshapes RIG --map arkit --out FILE.glb`,
// the rig evaluated at each of the 52 ARKit shapes of a map and written as one glTF binary with
// 52 named morph targets (docs/embedding.md "Blendshape export").
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/file_util.h"
#include "expressions/runtime/clip.h"
#include "io/arkit_map.h"
#include "io/gltf_bake.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {
namespace {

const char* kExportUsage =
    "usage: mimetic export-blendshapes RIG --out FILE.glb [--map arkit|MAP] [--no-normals]\n"
    "                                  [--quiet]\n\n"
    "Evaluates RIG (a rig JSON or a compiled .mrig, every skin layer on) at each of the 52\n"
    "ARKit blendshapes of an ARKit map and writes one glTF 2.0 binary: the neutral as the base\n"
    "mesh and 52 morph targets in Apple's order, named as ARKit names them (the mesh's\n"
    "extras.targetNames, which three.js turns into morphTargetDictionary), plus a preview\n"
    "animation showing each shape for one second. A shape the map marks \"none\" (the rig\n"
    "cannot make it: blinks, eye gaze, the tongue, ...) is an all-zero target, so the 52\n"
    "names are always there; they are listed in one warning.\n\n"
    "  --map arkit|MAP   the map: `arkit` (the default) is assets/arkit/default.arkit.json\n"
    "                    found from the rig's folder upwards; or a mimetic-arkit-map file\n"
    "  --out FILE.glb    the glTF binary, written atomically\n"
    "  --no-normals      no NORMAL attribute and no normal deltas (half the size)\n"
    "  --quiet           no progress bar and no summary\n\n"
    "example:\n"
    "  mimetic export-blendshapes assets/head/sample_head.rig.json --map arkit \\\n"
    "      --out out/head_arkit52.glb\n";

}  // namespace

int CmdExportBlendshapes(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"map", "out"}, {"no-normals", "quiet"});
  if (parsed.help) return std::fputs(kExportUsage, stdout), 0;
  const char* cmd = "export-blendshapes";
  if (!parsed.error.empty()) return UsageError(cmd, parsed.error, kExportUsage);
  if (parsed.positional.size() != 1)
    return UsageError(cmd, parsed.positional.empty() ? "missing RIG" : "expected one RIG",
                      kExportUsage);
  const std::string rig_path = parsed.positional[0], out = parsed.Get("out");
  if (out.empty()) return UsageError(cmd, "missing --out FILE.glb", kExportUsage);
  const std::string bad = CheckOutputExtension("out", out, {".glb"});
  if (!bad.empty()) return UsageError(cmd, bad, kExportUsage);
  const std::string map_arg = parsed.Get("map", "arkit");
  const std::string map_path = map_arg == "arkit" ? DefaultArkitMap(rig_path) : map_arg;
  for (const std::string& input : {rig_path, map_path})
    if (SameFile(out, input))
      return UsageError(cmd, "--out " + out + " is " + input + ", an input; expected another "
                             "file name", kExportUsage);
  const bool normals = !parsed.Has("no-normals"), quiet = parsed.Has("quiet");
  const auto start = std::chrono::steady_clock::now();

  Diagnostics diag;
  std::vector<ArkitShape> map;
  const bool map_ok = LoadArkitMap(map_path, &map, &diag);
  LoadedRig loaded;
  const bool rig_ok = LoadRig(rig_path, &loaded, &diag);
  if (!map_ok || !rig_ok) {
    std::fputs(diag.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic export-blendshapes: %zu error(s); nothing was written\n",
                 diag.ErrorCount());
    return kExitInput;
  }
  const Rig& rig = loaded.rig;
  if (!CheckArkitMuscles(map, rig.muscle_names(), map_path, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic export-blendshapes: %s names muscles %s does not have; "
                         "nothing was written\n", map_path.c_str(), rig_path.c_str());
    return kExitInput;
  }

  // The poses: each shape's activations (and jaw) in rig order.
  const size_t nv = rig.vertex_count(), ns = map.size();
  std::vector<std::string> none, jawless;
  BakedFrames frames;
  const double unit = MetresPerUnit(loaded.spec.units);
  frames.metres_per_unit = unit > 0 ? unit : 0.001;  // as mimetic play
  const std::vector<float> zero(rig.muscle_count(), 0.f);
  if (!PosedMesh(rig, zero, SkinLayers{}, &frames.base)) {
    std::fprintf(stderr, "mimetic export-blendshapes: evaluation failed (internal error)\n");
    return kExitInput;
  }
  if (!normals) frames.base.normals.clear();
  SetDefaultEpsilons(&frames);
  frames.positions.resize(ns * nv * 3);
  if (normals) frames.normals.resize(ns * nv * 3);
  const bool bar = !quiet && isatty(fileno(stderr)) != 0;
  for (size_t k = 0; k < ns; ++k) {
    const ArkitShape& shape = map[k];
    std::vector<float> activations(rig.muscle_count(), 0.f);
    float jaw = 0.f;
    for (const auto& [name, value] : shape.activations) {
      if (name == kJawInputName) {
        jaw = value;
        if (rig.jaw().empty() && value != 0.f) jawless.push_back(shape.name);
        continue;
      }
      activations[size_t(rig.FindMuscle(name))] = value;  // CheckArkitMuscles: every name known
    }
    if (shape.how == ArkitShape::How::kNone) none.push_back(shape.name);
    MeshData posed;
    if (!PosedMesh(rig, activations, SkinLayers{}, &posed, jaw)) {
      std::fprintf(stderr, "mimetic export-blendshapes: evaluation of %s failed (internal "
                           "error)\n", shape.name.c_str());
      return kExitInput;
    }
    for (size_t v = 0; v < nv; ++v) {
      const float3 p = posed.positions[v];
      frames.positions[(k * nv + v) * 3 + 0] = p.x;
      frames.positions[(k * nv + v) * 3 + 1] = p.y;
      frames.positions[(k * nv + v) * 3 + 2] = p.z;
      if (!normals) continue;
      const float3 n = posed.normals[v];
      frames.normals[(k * nv + v) * 3 + 0] = n.x;
      frames.normals[(k * nv + v) * 3 + 1] = n.y;
      frames.normals[(k * nv + v) * 3 + 2] = n.z;
    }
    frames.times.push_back(double(k));
    frames.target_names.push_back(shape.name);
    if (bar) {
      const int width = 40, filled = int(width * (k + 1) / ns);
      std::fprintf(stderr, "\r[%s%s] %zu/%zu shapes evaluated",
                   std::string(size_t(filled), '#').c_str(),
                   std::string(size_t(width - filled), ' ').c_str(), k + 1, ns);
      std::fflush(stderr);
    }
  }
  if (bar) std::fputc('\n', stderr);

  const std::string dir = DirectoryOf(out);
  std::error_code ec;
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  BakeStats stats;
  Diagnostics write;
  if (!WriteBakedGlb(out, frames, &stats, &write)) {
    std::fputs(write.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic export-blendshapes: nothing was written\n");
    return kExitInput;
  }
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  };
  if (!none.empty())
    std::fprintf(stderr, "mimetic export-blendshapes: warning: %zu shape(s) the rig cannot make "
                         "are all-zero targets: %s\n", none.size(), join(none).c_str());
  if (!jawless.empty())
    std::fprintf(stderr, "mimetic export-blendshapes: warning: %s has no jaw; the jaw part of "
                         "%s is left out\n", rig_path.c_str(), join(jawless).c_str());
  if (!quiet) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("exported %zu ARKit blendshapes of %s through %s into %s: %.2f MB, %zu "
                "vertices, %zu triangles, %zu morph targets (%zu sparse), %zu vertices moved "
                "by some shape; took %.2f s\n",
                ns, rig_path.c_str(), map_path.c_str(), out.c_str(), double(stats.bytes) / 1e6,
                nv, size_t(rig.triangle_count()), stats.targets, stats.sparse_targets,
                stats.moved_vertices, seconds);
  }
  return 0;
}

}  // namespace mimetic::tools
