// tools/cmd_render.cpp: `mimetic render`, a software render of a mesh to PNG.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "geometry/mesh.h"
#include "io/image.h"
#include "io/mesh_io.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/render/close_up.h"
#include "tools/render/render.h"

namespace mimetic::tools {

static const char* kRenderUsage =
    "usage: mimetic render MESH --out IMAGE.png [--yaw DEG] [--pitch DEG] [--size N]\n"
    "                      [--zoom Z] [--focus X,Y] [--wireframe]\n\n"
    "Renders MESH (.obj, .gltf, .glb) with skin shading (docs/model.md §12) on grey,\n"
    "seen from +Z turned by --yaw about +Y (toward +X) and --pitch (from above), fitted to\n"
    "the bounding box. --size N gives an N x N image (default 800, at most 8192).\n"
    "--zoom Z (1 to 8, default 1) shows a close-up: the full view is rendered Z times larger\n"
    "(at most 8192 pixels) and the N x N window centred on --focus X,Y is kept, X and Y\n"
    "being fractions of the full view's width and height (0,0 = top left; default 0.5,0.5;\n"
    "the window is moved inside the view where it would cross an edge).\n";

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
      ParseArgs(args, {"out", "yaw", "pitch", "size", "zoom", "focus"}, {"wireframe"});
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

  Diagnostics diag, local;
  MeshData mesh;
  const bool mesh_ok = ImportMesh(parsed.positional[0], "", &mesh, &local);
  diag.Append(local, parsed.positional[0]);
  if (!mesh_ok) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  RenderOptions options;
  options.yaw_deg = static_cast<float>(yaw);
  options.pitch_deg = static_cast<float>(pitch);
  options.wireframe = parsed.flags.count("wireframe") > 0;
  const Image image = RenderCloseUp(mesh, options, n, zoom, focus_x, focus_y);
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
