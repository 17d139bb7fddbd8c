// tools/cmd_render.cpp: `mimetic render`, a software render of a mesh to PNG.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rig/offline/mesh.h"
#include "rig/offline/render.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {

static const char* kRenderUsage =
    "usage: mimetic render MESH --out IMAGE.png [--yaw DEG] [--pitch DEG] [--size N]\n"
    "                      [--wireframe]\n\n"
    "Renders MESH (.obj, .gltf, .glb) with skin shading (MODEL.md section 12) on grey,\n"
    "seen from +Z turned by --yaw about +Y (toward +X) and --pitch (from above), fitted to\n"
    "the bounding box. --size N gives an N x N image (default 800, at most 8192).\n";

static bool ParseReal(const std::string& text, double lo, double hi, double* out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v >= lo && v <= hi)) return false;
  *out = v;
  return true;
}

int CmdRender(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"out", "yaw", "pitch", "size"}, {"wireframe"});
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
  double yaw = 0, pitch = 0, size = 800;
  if (parsed.Has("yaw") && !ParseReal(parsed.Get("yaw"), -3600, 3600, &yaw))
    return UsageError("render", "--yaw '" + parsed.Get("yaw") + "': expected degrees",
                      kRenderUsage);
  if (parsed.Has("pitch") && !ParseReal(parsed.Get("pitch"), -89, 89, &pitch))
    return UsageError("render", "--pitch '" + parsed.Get("pitch") +
                                    "': expected degrees in [-89, 89]",
                      kRenderUsage);
  if (parsed.Has("size") && (!ParseReal(parsed.Get("size"), 1, 8192, &size) ||
                             size != static_cast<double>(static_cast<int>(size))))
    return UsageError("render", "--size '" + parsed.Get("size") +
                                    "': expected a whole number of pixels in [1, 8192]",
                      kRenderUsage);

  Diagnostics diag;
  MeshData mesh;
  if (!ImportMesh(parsed.positional[0], "", &mesh, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  RenderOptions options;
  options.width = options.height = static_cast<int>(size);
  options.yaw_deg = static_cast<float>(yaw);
  options.pitch_deg = static_cast<float>(pitch);
  options.wireframe = parsed.flags.count("wireframe") > 0;
  const Image image = RenderMesh(mesh, options);
  if (!SavePng(out, image, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  std::printf("wrote %s: %dx%d, %zu triangles, yaw %g, pitch %g\n", out.c_str(), image.width,
              image.height, mesh.triangle_count(), yaw, pitch);
  return 0;
}

}  // namespace mimetic::tools
