// tools/cmd_head.cpp: `mimetic make-head`, the procedural sample head and its landmarks.
#include <algorithm>
#include <cstdio>
#include <string>

#include "content/sample_head.h"
#include "fitting/landmarks.h"
#include "geometry/mesh.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {

static const char* kHeadUsage =
    "usage: mimetic make-head --out FILE [--landmarks FILE.json]\n\n"
    "Writes the procedural sample head (millimetres, +Y up, facing +Z, ~34k vertices; the\n"
    "skin, mesh \"head\", then the eyeballs, mesh \"eyes\") as .glb or .obj (objects \"head\"\n"
    "and \"eyes\"), and optionally its 68 iBUG landmarks (docs/landmarks-format.md).\n"
    "Deterministic: the same build writes the same bytes. The bundled copy was made with\n"
    "  mimetic make-head --out assets/head/sample_head.glb \\\n"
    "                    --landmarks assets/head/sample_head.landmarks.json\n";

int CmdMakeHead(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"out", "landmarks"}, {});
  if (parsed.help) return std::fputs(kHeadUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("make-head", parsed.error, kHeadUsage);
  if (!parsed.positional.empty())
    return UsageError("make-head", "unexpected argument '" + parsed.positional[0] + "'",
                      kHeadUsage);
  const std::string out = parsed.Get("out");
  if (out.empty()) return UsageError("make-head", "missing --out FILE", kHeadUsage);
  const std::string bad_ext = CheckOutputExtension("out", out, {".obj", ".glb"});
  if (!bad_ext.empty()) return UsageError("make-head", bad_ext, kHeadUsage);
  const std::string landmarks_path = parsed.Get("landmarks");

  const SampleHead head = MakeSampleHead();
  const MeshData eyes = MakeSampleHeadEyes();
  Diagnostics diag;
  // The skin first (what every reader takes when the rig names no mesh), then the eyeballs.
  if (!ExportMeshes(out, {{"head", &head.mesh}, {"eyes", &eyes}}, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  float3 lo = head.mesh.positions[0], hi = lo;
  for (const float3& p : head.mesh.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  std::printf("wrote %s: %zu vertices, %zu triangles, %.1f x %.1f x %.1f mm (w x h x d); "
              "eyes: %zu vertices, %zu triangles\n",
              out.c_str(), head.mesh.vertex_count(), head.mesh.triangle_count(), hi.x - lo.x,
              hi.y - lo.y, hi.z - lo.z, eyes.vertex_count(), eyes.triangle_count());
  if (!landmarks_path.empty()) {
    Landmarks lm;
    lm.points = head.landmarks;
    if (!SaveLandmarks(landmarks_path, lm, &diag)) {
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
    std::printf("wrote %s: %zu landmarks (ibug68, mm)\n", landmarks_path.c_str(),
                lm.points.size());
  }
  return 0;
}

}  // namespace mimetic::tools
