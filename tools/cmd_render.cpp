// tools/cmd_render.cpp: `mimetic render`, a software render of a mesh to PNG.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "content/sample_head.h"
#include "geometry/mesh.h"
#include "io/image.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "io/companion_meshes.h"
#include "tools/render/close_up.h"
#include "tools/render/render.h"

namespace mimetic::tools {

static const char* kRenderUsage =
    "usage: mimetic render MESH|RIG --out IMAGE.png [--yaw DEG] [--pitch DEG] [--size N]\n"
    "                      [--zoom Z] [--focus X,Y] [--wireframe] [--skin-inside]\n"
    "                      [--fine DIR [--fine-depth D]] [--activate MUSCLE=A ...]\n\n"
    "Renders MESH (.obj, .gltf, .glb) with skin shading (docs/model.md §12) on grey,\n"
    "seen from +Z turned by --yaw about +Y (toward +X) and --pitch (from above), fitted to\n"
    "the bounding box. --size N gives an N x N image (default 800, at most 8192).\n"
    "--zoom Z (1 to 8, default 1) shows a close-up: the full view is rendered Z times larger\n"
    "(at most 8192 pixels) and the N x N window centred on --focus X,Y is kept, X and Y\n"
    "being fractions of the full view's width and height (0,0 = top left; default 0.5,0.5;\n"
    "the window is moved inside the view where it would cross an edge).\n"
    "A RIG (.rig.json or .mrig) is posed first: --activate MUSCLE=A (repeatable) sets a\n"
    "muscle's activation in [0, 1] (the others are 0).\n"
    "--fine DIR bump-maps DIR/fine_height_1.png and fine_height_2.png (`mimetic texture`)\n"
    "over the shading, each scaled by its per-vertex amplitude (EvaluateJob\n"
    "out_fine_amplitudes, docs/model.md §23; 1 for a plain MESH); --fine-depth D is a full\n"
    "furrow's depth at amplitude 1 in mesh units (default 0.15).\n"
    "Back faces are the skin seen from inside (through an open mouth, the eye openings, a\n"
    "scan's holes) and are shaded dark, as a cavity; --skin-inside shades them as skin.\n"
    "The mesh file's other meshes (a glTF's meshes after the first, or after the rig's\n"
    "mesh: the sample head's eyeballs) are drawn too, unposed (not with --fine); a mesh\n"
    "named \"eyes\" with sclera, iris and pupil by its normals (looking along +Z).\n";

// Parses "X,Y" with both in [0, 1].
static bool ParseFocus(const std::string& text, double* x, double* y) {
  const size_t comma = text.find(',');
  if (comma == std::string::npos) return false;
  char* end = nullptr;
  const std::string a = text.substr(0, comma), b = text.substr(comma + 1);
  const double vx = std::strtod(a.c_str(), &end);
  if (a.empty() || *end != '\0') return false;
  const double vy = std::strtod(b.c_str(), &end);
  if (b.empty() || *end != '\0') return false;
  if (!(vx >= 0 && vx <= 1 && vy >= 0 && vy <= 1)) return false;
  *x = vx;
  *y = vy;
  return true;
}

int CmdRender(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"out", "yaw", "pitch", "size", "zoom", "focus", "fine", "fine-depth", "activate"},
                {"wireframe", "skin-inside"});
  if (parsed.help) return std::fputs(kRenderUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("render", parsed.error, kRenderUsage);
  if (parsed.positional.size() != 1)
    return UsageError("render",
                      parsed.positional.empty() ? "missing MESH"
                                                : "expected one MESH, got " +
                                                      std::to_string(parsed.positional.size()),
                      kRenderUsage);
  const std::string out = parsed.Get("out");
  if (out.empty()) return UsageError("render", "missing --out IMAGE.png", kRenderUsage);
  // Only PNG is written: another extension would get PNG bytes under a misleading name.
  const std::string bad_ext = CheckOutputExtension("out", out, {".png"});
  if (!bad_ext.empty()) return UsageError("render", bad_ext, kRenderUsage);
  double yaw = 0, pitch = 0, size = 800;
  if (parsed.Has("yaw") && !ParseNumber(parsed.Get("yaw"), -3600, 3600, &yaw))
    return UsageError("render", "--yaw '" + parsed.Get("yaw") + "': expected degrees",
                      kRenderUsage);
  if (parsed.Has("pitch") && !ParseNumber(parsed.Get("pitch"), -89, 89, &pitch))
    return UsageError("render", "--pitch '" + parsed.Get("pitch") +
                                    "': expected degrees in [-89, 89]",
                      kRenderUsage);
  if (parsed.Has("size") && (!ParseNumber(parsed.Get("size"), 1, 8192, &size) ||
                             size != static_cast<double>(static_cast<int>(size))))
    return UsageError("render", "--size '" + parsed.Get("size") +
                                    "': expected a whole number of pixels in [1, 8192]",
                      kRenderUsage);

  double zoom = 1, focus_x = 0.5, focus_y = 0.5;
  if (parsed.Has("zoom") && !ParseNumber(parsed.Get("zoom"), 1, 8, &zoom))
    return UsageError("render", "--zoom '" + parsed.Get("zoom") + "': expected a number in [1, 8]",
                      kRenderUsage);
  if (parsed.Has("focus") && !ParseFocus(parsed.Get("focus"), &focus_x, &focus_y))
    return UsageError("render", "--focus '" + parsed.Get("focus") +
                                    "': expected X,Y, two fractions in [0, 1] of the view",
                      kRenderUsage);
  const int n = static_cast<int>(size);
  const int full = static_cast<int>(std::lround(std::min(8192.0, size * zoom)));

  double fine_depth = 0.15;
  if (parsed.Has("fine-depth") && !ParseNumber(parsed.Get("fine-depth"), 0, 1e6, &fine_depth))
    return UsageError("render", "--fine-depth '" + parsed.Get("fine-depth") +
                                    "': expected a depth >= 0 in mesh units", kRenderUsage);
  const std::string& input = parsed.positional[0];
  const bool is_rig = IsCompiledRigPath(input) ||
                      (input.size() > 5 && input.compare(input.size() - 5, 5, ".json") == 0);
  if (parsed.Has("activate") && !is_rig)
    return UsageError("render", "--activate poses a rig; " + input + " is a mesh", kRenderUsage);

  Diagnostics diag, local;
  MeshData mesh;
  std::vector<float> amplitudes;
  CompanionMeshes companions;  // the file's other meshes (the sample head's eyeballs)
  if (is_rig) {
    LoadedRig loaded;
    if (!LoadRig(input, &loaded, &diag) || !LoadCompanionMeshes(loaded, &companions, &diag)) {
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
    const Rig& rig = loaded.rig;
    std::vector<float> act(rig.muscle_count(), 0.f);
    if (const auto it = parsed.values.find("activate"); it != parsed.values.end())
      for (const std::string& a : it->second) {
        const size_t eq = a.find('=');
        double v = 0;
        const int m = eq == std::string::npos ? -1 : rig.FindMuscle(a.substr(0, eq));
        if (m < 0 || !ParseNumber(a.substr(eq + 1), 0, 1, &v))
          return UsageError("render", "--activate '" + a + "': expected MUSCLE=A with a muscle "
                                      "of the rig and A in [0, 1]", kRenderUsage);
        act[size_t(m)] = float(v);
      }
    if (!PosedMesh(rig, act, SkinLayers{}, &mesh)) {
      std::fprintf(stderr, "mimetic render: %s: the rig did not evaluate\n", input.c_str());
      return 1;
    }
    EvaluateContext ctx(rig);
    std::vector<float> positions(3 * rig.vertex_count());
    amplitudes.assign(2 * rig.vertex_count(), 1.f);
    EvaluateJob job;
    job.rig = &rig;
    job.context = &ctx;
    job.activations = act;
    job.out_positions = positions;
    if (!rig.fine_scale().empty()) job.out_fine_amplitudes = amplitudes;
    job.Run();
  } else {
    bool mesh_ok = ImportMesh(input, "", &mesh, &local);
    mesh_ok = mesh_ok && ImportOtherMeshes(input, "", &companions.others, &local);
    diag.Append(local, input);
    if (!mesh_ok) {
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
  }
  Gray16Image heights[2];
  FineScaleShading fine;
  if (parsed.Has("fine")) {
    const std::string dir = parsed.Get("fine");
    for (int k = 0; k < 2; ++k) {
      const std::string path = dir + "/fine_height_" + std::to_string(k + 1) + ".png";
      if (!LoadGray16Png(path, path, "fine-scale height map", &heights[k], &diag)) {
        std::fputs(diag.Format().c_str(), stderr);
        return 1;
      }
      fine.height[k] = &heights[k];
    }
    if (mesh.uvs.size() != mesh.vertex_count()) {
      std::fprintf(stderr, "mimetic render: --fine: %s has no texture coordinates to map the "
                           "height maps with\n", input.c_str());
      return 1;
    }
    fine.amplitudes = amplitudes.empty() ? nullptr : &amplitudes;
    fine.depth = float(fine_depth);
  }
  // The other meshes are drawn with the skin (not with --fine: the height maps and amplitudes
  // are the skin's).
  // A mesh named "eyes" is shaded as eyeballs looking along +z (by its normals: a dark iris
  // disc within 30 degrees of +z with a darker pupil inside 12, white sclera elsewhere); the
  // others in the skin colour.
  std::vector<float3> colors;
  if (!parsed.Has("fine") && !companions.others.empty()) {
    const size_t skin_vertices = mesh.vertex_count();
    mesh = MergeForDrawing(mesh, companions);
    RenderOptions defaults;
    colors.assign(mesh.vertex_count(), defaults.base_color);
    size_t v = skin_vertices;
    for (const NamedMeshData& m : companions.others) {
      const bool eyes = m.name == "eyes" && m.mesh.normals.size() == m.mesh.vertex_count();
      for (size_t k = 0; k < m.mesh.vertex_count(); ++k, ++v) {
        if (!eyes) continue;
        colors[v] = SampleHeadEyeColor(m.mesh.normals[k]);
      }
    }
  }
  RenderOptions options;
  if (!colors.empty()) options.vertex_colors = &colors;
  if (parsed.Has("fine")) options.fine = &fine;
  options.yaw_deg = static_cast<float>(yaw);
  options.pitch_deg = static_cast<float>(pitch);
  options.wireframe = parsed.flags.count("wireframe") > 0;
  options.shade_inside = parsed.flags.count("skin-inside") == 0;
  const Image image = RenderCloseUp(mesh, options, n, zoom, focus_x, focus_y);
  if (diag.HasErrors()) std::fputs(diag.Format().c_str(), stderr);
  if (!SavePng(out, image, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  std::printf("wrote %s: %dx%d, %zu triangles, yaw %g, pitch %g", out.c_str(), image.width,
              image.height, mesh.triangle_count(), yaw, pitch);
  if (full > n) std::printf(", zoom %g about (%g, %g)", double(full) / n, focus_x, focus_y);
  std::printf("\n");
  return 0;
}

}  // namespace mimetic::tools
