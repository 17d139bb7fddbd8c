// tools/cmd_surface.cpp: `mimetic make-surface`, the procedural test surface.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "content/procedural.h"
#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {

static const char* kUsage =
    "usage: mimetic make-surface --out FILE [--columns N] [--rows N] [--width W] [--height H]\n"
    "                            [--bulge B]\n\n"
    "Writes a gently bulged rectangular sheet (a stand-in for a cheek) as .obj or .glb.\n"
    "Defaults: 41 x 41 vertices, 100 x 100 x 10 mesh units (the bundled assets/surface).\n";

int CmdMakeSurface(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"out", "columns", "rows", "width", "height", "bulge"}, {});
  if (parsed.help) return std::fputs(kUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("make-surface", parsed.error, kUsage);
  if (!parsed.positional.empty())
    return UsageError("make-surface", "unexpected argument '" + parsed.positional[0] + "'", kUsage);
  const std::string out = parsed.Get("out");
  if (out.empty()) return UsageError("make-surface", "missing --out FILE", kUsage);
  const std::string bad_ext = CheckOutputExtension("out", out, {".obj", ".glb"});
  if (!bad_ext.empty()) return UsageError("make-surface", bad_ext, kUsage);
  long long columns = 41, rows = 41;
  for (auto [key, value] : {std::pair<const char*, long long*>{"columns", &columns},
                            std::pair<const char*, long long*>{"rows", &rows}}) {
    if (parsed.Has(key) && !ParseInteger(parsed.Get(key), 2, 4096, value))
      return UsageError("make-surface",
                        std::string("--") + key + " '" + parsed.Get(key) +
                            "': expected a whole number in [2, 4096]",
                        kUsage);
  }
  double width = 100, height = 100, bulge = 10;
  struct {
    const char* key;
    double* value;
    double lo, hi;
  } numbers[] = {{"width", &width, 1e-6, 1e9}, {"height", &height, 1e-6, 1e9},
                 {"bulge", &bulge, -1e9, 1e9}};
  for (auto& n : numbers) {
    if (parsed.Has(n.key) && !ParseNumber(parsed.Get(n.key), n.lo, n.hi, n.value))
      return UsageError("make-surface",
                        std::string("--") + n.key + " '" + parsed.Get(n.key) +
                            "': expected a number in [" + std::to_string(n.lo) + ", " +
                            std::to_string(n.hi) + "]",
                        kUsage);
  }
  const MeshData mesh = MakeSurfaceMesh(uint32_t(columns), uint32_t(rows), float(width),
                                        float(height), float(bulge));
  Diagnostics diag;
  if (!ExportMesh(out, mesh, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  std::printf("wrote %s: %zu vertices, %zu triangles, %g x %g, bulge %g\n", out.c_str(),
              mesh.vertex_count(), mesh.triangle_count(), width, height, bulge);
  return 0;
}

}  // namespace mimetic::tools
