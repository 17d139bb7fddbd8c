// tools/cmd_rig.cpp: `mimetic info`, `mimetic validate`, `mimetic eval`.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/file_util.h"
#include "expressions/offline/activation_binding.h"
#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "muscles/offline/muscle_builder.h"
#include "rig/offline/jaw_setting.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "io/companion_meshes.h"

namespace mimetic::tools {
namespace {

const char* kInfoUsage =
    "usage: mimetic info RIG\n\n"
    "Loads RIG (a .rig.json file, docs/rig-format.md, or a compiled .mrig, mimetic build)\n"
    "and its mesh and prints the mesh size,\n"
    "units, skin thickness and every muscle with the number of vertices it moves; warns\n"
    "about a muscle that moves fewer than 50 of the mesh file's vertices.\n";

const char* kValidateUsage =
    "usage: mimetic validate RIG\n\n"
    "Checks RIG and its mesh and prints every problem with where it is and what was\n"
    "expected. Exit status 0 when the rig is usable, 1 when it is not.\n";

const char* kEvalUsage =
    "usage: mimetic eval RIG [--set MUSCLE=VALUE]... --out FILE [--no-thickness]\n"
    "                    [--no-muscle-wrinkles] [--no-curve-wrinkles]\n\n"
    "Poses RIG with the given muscle activations (each in [0, 1]; unset muscles are 0) and\n"
    "writes the deformed mesh with normals and UVs, in the rig's vertex layout: the mesh\n"
    "file's vertices first, in the file's order, then the vertices refinement adds where\n"
    "wrinkles act (docs/rig-format.md).\n\n"
    "options:\n"
    "  --set MUSCLE=VALUE      activation of one muscle (repeatable); a NAME without a muscle\n"
    "                          of its own sets NAME_L and NAME_R together; jaw=VALUE opens\n"
    "                          the jaw (a fraction of its range, docs/model.md §18)\n"
    "  --out FILE              output mesh: .obj or .glb (not one of the rig's inputs); .glb\n"
    "                          is in metres (a root scale node over the rig's units), .obj\n"
    "                          in the rig's units with v up (docs/errors.md)\n"
    "  --no-thickness          skip the volume-preserving thickness layer (docs/model.md §4)\n"
    "  --no-muscle-wrinkles    skip muscle-derived wrinkles (docs/model.md §6)\n"
    "  --no-curve-wrinkles     skip curve wrinkles (docs/model.md §7-8)\n";

void PrintDiagnostics(const Diagnostics& diag) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
}

// Loads the rig named by the single positional argument. Returns 0 on success.
int LoadFromArgs(const std::string& command, const ParsedArgs& parsed, const char* usage,
                 LoadedRig* out) {
  if (parsed.positional.size() != 1)
    return UsageError(command, parsed.positional.empty() ? "missing RIG" : "expected one RIG",
                      usage);
  Diagnostics diag;
  const bool ok = LoadRig(parsed.positional[0], out, &diag);
  PrintDiagnostics(diag);
  if (!ok) {
    std::fprintf(stderr, "mimetic %s: %s: %zu error(s); nothing was done\n", command.c_str(),
                 parsed.positional[0].c_str(), diag.ErrorCount());
    return 1;
  }
  return 0;
}

// `info` warns about a muscle that moves fewer of the mesh file's vertices than this.
constexpr uint32_t kFewVertices = 50;

const char* ThicknessKind(ThicknessSpec::Kind k) {
  switch (k) {
    case ThicknessSpec::Kind::kConstant: return "constant";
    case ThicknessSpec::Kind::kPerVertex: return "per vertex";
    case ThicknessSpec::Kind::kImage: return "image";
  }
  return "?";
}

}  // namespace

int CmdInfo(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {}, {});
  if (parsed.help) return std::fputs(kInfoUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("info", parsed.error, kInfoUsage);
  LoadedRig loaded;
  if (int rc = LoadFromArgs("info", parsed, kInfoUsage, &loaded)) return rc;
  const Rig& rig = loaded.rig;
  float3 lo{}, hi{};
  if (rig.point_count() > 0) lo = hi = rig.rest_points()[0];
  for (const float3& p : rig.rest_points()) {
    lo = {std::fmin(lo.x, p.x), std::fmin(lo.y, p.y), std::fmin(lo.z, p.z)};
    hi = {std::fmax(hi.x, p.x), std::fmax(hi.y, p.y), std::fmax(hi.z, p.z)};
  }
  float hmin = rig.point_thickness().empty() ? 0.f : rig.point_thickness()[0], hmax = hmin;
  for (float h : rig.point_thickness()) hmin = std::fmin(hmin, h), hmax = std::fmax(hmax, h);
  // A compiled rig (.mrig) keeps the built rig only: no mesh file, no muscle specs.
  const uint32_t file_vertices =
      loaded.compiled ? loaded.source_vertex_count : uint32_t(loaded.mesh.vertex_count());
  std::printf("rig:        %s%s\n", parsed.positional[0].c_str(),
              loaded.compiled ? " (compiled, docs/mrig-format.md)" : "");
  if (!loaded.compiled) std::printf("mesh:       %s\n", loaded.spec.mesh_path.c_str());
  std::printf("units:      %s\n", loaded.spec.units.c_str());
  std::printf("vertices:   %u (%u surface points after welding seams)", rig.vertex_count(),
              rig.point_count());
  if (file_vertices != 0 && rig.vertex_count() != file_vertices)
    std::printf("; the file has %u, refined where wrinkles act%s", file_vertices,
                !loaded.compiled && loaded.spec.refinement.falloff_error > 0.f
                    ? " and muscles' fall-offs bend"
                    : "");
  std::printf("\n");
  std::printf("triangles:  %u\n", rig.triangle_count());
  std::printf("bounds:     [%.4g, %.4g, %.4g] .. [%.4g, %.4g, %.4g] (size %.4g x %.4g x %.4g %s)\n",
              lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, hi.x - lo.x, hi.y - lo.y, hi.z - lo.z,
              loaded.spec.units.c_str());
  std::printf("thickness:  %s, %.4g .. %.4g %s\n",
              loaded.compiled ? "per point" : ThicknessKind(loaded.spec.thickness.kind), hmin,
              hmax, loaded.spec.units.c_str());
  std::printf("per frame:  %u of %u points can move (%.0f%%), %u more can change normal\n",
              rig.active_point_count(), rig.point_count(),
              100.0 * rig.active_point_count() / std::max(1u, rig.point_count()),
              rig.normal_point_count() - rig.active_point_count());
  std::printf("layers:     thickness %s, muscle wrinkles %s, curve wrinkles %s\n",
              rig.layers().thickness ? "on" : "off", rig.layers().muscle_wrinkles ? "on" : "off",
              rig.layers().curve_wrinkles ? "on" : "off");
  if (!rig.eyes().empty()) {
    size_t full = 0;
    for (float w : rig.eyes().weights) full += w >= 1.f;
    std::printf("eyes:       %zu eyeballs; %zu points slide on them (docs/model.md §24), %zu fully\n",
                rig.eyes().centers.size(), rig.eyes().points.size(), full);
  }
  std::printf("muscles:    %u\n", rig.muscle_count());
  std::vector<uint32_t> influenced = CountInfluencedPoints(rig.muscles());
  influenced.resize(rig.muscle_count(), 0u);
  std::vector<const RigMuscleWrinkles*> wrinkles_of(rig.muscle_count(), nullptr);
  for (const RigMuscleWrinkles& w : rig.muscle_wrinkles())
    if (w.muscle < wrinkles_of.size()) wrinkles_of[w.muscle] = &w;
  for (uint32_t m = 0; m < rig.muscle_count(); ++m) {
    if (m < loaded.spec.muscles.size()) {
      const MuscleSpec& ms = loaded.spec.muscles[m];
      std::printf("  %-28s %-6s strength %-8.4g moves %u points", ms.name.c_str(),
                  MuscleTypeName(ms.type), ms.strength, influenced[m]);
    } else {
      std::printf("  %-28s moves %u points", rig.muscle_names()[m].c_str(), influenced[m]);
    }
    if (const RigMuscleWrinkles* w = wrinkles_of[m]) {
      std::printf(", wrinkles on %u (half cycle %.3g %s", w->row_count(), w->half_cycle,
                  loaded.spec.units.c_str());
      if (w->gate > 0.f) std::printf(", full from activation %.3g", double(w->gate));
      std::printf(")");
    }
    std::printf("\n");
  }
  // A muscle that moves almost none of the mesh's own vertices is usually misplaced for this
  // head (its zone or insertion off the face); say so.
  if (file_vertices > 0) {
    const uint32_t nv = file_vertices;
    std::vector<uint32_t> reach(rig.muscle_count(), 0);
    std::vector<uint8_t> seen(rig.point_count(), 0);
    const MuscleTable& table = rig.muscles();
    for (uint32_t v = 0; v < nv && v < rig.vertex_count(); ++v) {
      const uint32_t p = rig.vertex_points()[v];
      if (seen[p] || p + 1 >= table.offsets.size()) continue;
      seen[p] = 1;
      for (uint32_t k = table.offsets[p]; k < table.offsets[p + 1]; ++k)
        ++reach[table.entries[k].muscle];
    }
    for (uint32_t m = 0; m < rig.muscle_count(); ++m)
      if (reach[m] < kFewVertices)
        std::printf("warning: muscle '%s' moves only %u of the mesh's %u vertices: check its "
                    "placement (attachment, insertion, zone) on this mesh\n",
                    rig.muscle_names()[m].c_str(), reach[m], nv);
  }
  if (!rig.curve_wrinkles().names.empty()) {
    std::printf("curve wrinkles: %zu\n", rig.curve_wrinkles().names.size());
    std::vector<uint32_t> reach(rig.curve_wrinkles().names.size(), 0);
    for (const CurveWrinkleEntry& e : rig.curve_wrinkles().entries)
      if (e.wrinkle < reach.size()) ++reach[e.wrinkle];
    for (size_t c = 0; c < reach.size(); ++c)
      std::printf("  %-28s reaches %u points\n", rig.curve_wrinkles().names[c].c_str(), reach[c]);
  }
  return 0;
}

int CmdValidate(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {}, {});
  if (parsed.help) return std::fputs(kValidateUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("validate", parsed.error, kValidateUsage);
  LoadedRig loaded;
  if (int rc = LoadFromArgs("validate", parsed, kValidateUsage, &loaded)) return rc;
  std::printf("%s: ok (%u muscles, %u vertices, %u triangles)\n", parsed.positional[0].c_str(),
              loaded.rig.muscle_count(), loaded.rig.vertex_count(), loaded.rig.triangle_count());
  return 0;
}

int CmdEval(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"set", "out"},
                                      {"no-thickness", "no-muscle-wrinkles", "no-curve-wrinkles"});
  if (parsed.help) return std::fputs(kEvalUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("eval", parsed.error, kEvalUsage);
  const std::string out_path = parsed.Get("out");
  if (out_path.empty()) return UsageError("eval", "missing --out FILE", kEvalUsage);
  const std::string bad_ext = CheckOutputExtension("out", out_path, {".obj", ".glb"});
  if (!bad_ext.empty()) return UsageError("eval", bad_ext, kEvalUsage);
  LoadedRig loaded;
  if (int rc = LoadFromArgs("eval", parsed, kEvalUsage, &loaded)) return rc;
  // The posed mesh never replaces one of the rig's own inputs.
  for (const std::string& input : {parsed.positional[0], loaded.spec.mesh_path,
                                   loaded.spec.thickness.image_path}) {
    if (!input.empty() && SameFile(out_path, input))
      return UsageError("eval", "--out " + out_path + " is " + input +
                                    ", an input of the rig; expected another file name",
                        kEvalUsage);
  }
  const Rig& rig = loaded.rig;

  std::vector<float> activations;
  Diagnostics diag;
  const auto it = parsed.values.find("set");
  std::vector<std::string> sets = it == parsed.values.end() ? std::vector<std::string>{} : it->second;
  float jaw = 0.f;
  const bool jaw_ok = TakeJawSetting(rig, &sets, &jaw, &diag);
  if (!BindActivations(rig.muscle_names(), sets, &activations, &diag) || !jaw_ok) {
    PrintDiagnostics(diag);
    std::fprintf(stderr, "mimetic eval: %zu error(s) in --set; nothing was written\n",
                 diag.ErrorCount());
    return 1;
  }

  const MeshData rest = RestMesh(rig);
  MeshData posed;
  const SkinLayers layers{.thickness = !parsed.flags.count("no-thickness"),
                          .muscle_wrinkles = !parsed.flags.count("no-muscle-wrinkles"),
                          .curve_wrinkles = !parsed.flags.count("no-curve-wrinkles")};
  if (!PosedMesh(rig, activations, layers, &posed, jaw)) {
    std::fprintf(stderr, "mimetic eval: evaluation failed (internal error: job did not validate)\n");
    return 1;
  }
  // Non-finite output is an error naming the rig key that causes it (issue 11).
  if (Diagnostics bad; !CheckPosedFinite(rig, loaded.spec, activations, layers, posed, &bad)) {
    diag.Append(bad, parsed.positional[0]);
    PrintDiagnostics(diag);
    std::fprintf(stderr, "mimetic eval: the posed mesh is not finite; nothing was written\n");
    return 1;
  }

  float max_disp = 0.f;
  uint32_t max_vertex = 0;
  for (uint32_t v = 0; v < rig.vertex_count(); ++v) {
    const float d = Length(posed.positions[v] - rest.positions[v]);
    if (d > max_disp) max_disp = d, max_vertex = v;
  }
  const std::string out_dir = DirectoryOf(out_path);
  std::error_code ec;
  if (!out_dir.empty()) std::filesystem::create_directories(out_dir, ec);
  const double metres = MetresPerUnit(loaded.spec.units);
  // The mesh file's other meshes (the sample head's eyeballs) go along unchanged.
  CompanionMeshes companions;
  if (!LoadCompanionMeshes(loaded, &companions, &diag) ||
      !WritePosedWithCompanions(out_path, posed, companions, &diag, metres > 0 ? metres : 0.001)) {
    PrintDiagnostics(diag);
    return 1;
  }
  std::printf("posed %s with", parsed.positional[0].c_str());
  bool any = false;
  for (uint32_t m = 0; m < rig.muscle_count(); ++m) {
    if (activations[m] != 0.f) {
      std::printf(" %s=%g", rig.muscle_names()[m].c_str(), activations[m]);
      any = true;
    }
  }
  if (!any) std::printf(" all muscles at rest");
  if (jaw != 0.f) std::printf(", jaw=%g", jaw);
  std::printf("\nlayers: muscles");
  const struct {
    bool compiled, enabled;
    const char* name;
  } layer_list[] = {{rig.layers().thickness, layers.thickness, "thickness"},
                    {rig.layers().muscle_wrinkles, layers.muscle_wrinkles, "muscle wrinkles"},
                    {rig.layers().curve_wrinkles, layers.curve_wrinkles, "curve wrinkles"}};
  for (const auto& l : layer_list) {
    if (l.compiled && l.enabled) std::printf(", %s", l.name);
    else if (l.compiled) std::printf(" (%s switched off)", l.name);
  }
  std::printf("\nlargest displacement: %.4g %s at vertex %u\n", max_disp, loaded.spec.units.c_str(),
              max_vertex);
  std::printf("wrote %s (%u vertices, %u triangles, with normals%s)\n", out_path.c_str(),
              rig.vertex_count(), rig.triangle_count(), posed.uvs.empty() ? "" : " and UVs");
  return 0;
}

}  // namespace mimetic::tools
