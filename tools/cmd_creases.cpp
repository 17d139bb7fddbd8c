// tools/cmd_creases.cpp: `mimetic creases`, the crease number of each muscle
// (fitting/creases.h), for the rig's own fall-offs or with every muscle switched to one kind.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <vector>

#include "fitting/creases.h"
#include "io/image.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "tools/render/close_up.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {

static const char* kCreasesUsage =
    "usage: mimetic creases RIG [--falloff waters|smooth] [--rings N] [--min-shape S]\n"
    "                       [--image FILE.png [--muscle NAME] [--size N] [--zoom Z]]\n\n"
    "How sharply each muscle of RIG, alone at activation 1, folds the skin along the edges of\n"
    "its zone: the largest change of dihedral angle from rest (degrees) over the edges in a\n"
    "band around the zone's boundary, the boundary ring grown by N rings (--rings, default 2;\n"
    "docs/model.md §2-3). --falloff rebuilds the rig with every muscle's fall-off set to one\n"
    "kind, to compare Waters' cosines with the smooth (squared) ones on the same rig.\n"
    "Slivers are left out: an edge counts when both of its triangles are at least S times\n"
    "as high as their longest edge (--min-shape, default 0.05; 0 counts every edge), since a\n"
    "sliver's normal swings by its apex's motion over its height whatever the fall-off.\n"
    "Each line names where the muscle's worst edge lies (its midpoint at rest).\n"
    "--image writes a picture: rest | Waters' fall-offs | smooth fall-offs, one muscle at\n"
    "activation 1 (--muscle, default the one with the largest crease number under Waters'),\n"
    "every skin layer the rig has, N pixels a panel (--size, default 320), Z times the fitted\n"
    "view (--zoom, default 1.8) around that muscle.\n";

namespace {

// `mesh` posed by `rig` with muscle m at 1 (the input's vertices; refinement's are dropped).
MeshData PoseOne(const Rig& rig, const MeshData& mesh, int m) {
  std::vector<float> act(rig.muscle_count(), 0.f);
  if (m >= 0) act[size_t(m)] = 1.f;
  EvaluateContext ctx(rig);
  std::vector<float3> out(rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = span<float>(&out[0].x, out.size() * 3);
  MeshData posed = mesh;
  posed.normals.clear();
  if (!job.Run()) return posed;
  for (size_t v = 0; v < posed.vertex_count(); ++v) posed.positions[v] = out[v];
  return posed;
}

}  // namespace

int CmdCreases(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"falloff", "rings", "min-shape", "image", "muscle", "size", "zoom"}, {});
  if (parsed.help) return std::fputs(kCreasesUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("creases", parsed.error, kCreasesUsage);
  if (parsed.positional.size() != 1)
    return UsageError("creases", parsed.positional.empty() ? "missing RIG" : "expected one RIG",
                      kCreasesUsage);
  double rings = 2;
  if (parsed.Has("rings") && (!ParseNumber(parsed.Get("rings"), 0, 16, &rings) ||
                              rings != double(int(rings))))
    return UsageError("creases", "--rings '" + parsed.Get("rings") +
                                     "': expected a whole number in [0, 16]",
                      kCreasesUsage);
  double min_shape = kCreaseMinShape;
  if (parsed.Has("min-shape") && !ParseNumber(parsed.Get("min-shape"), 0, 0.5, &min_shape))
    return UsageError("creases", "--min-shape '" + parsed.Get("min-shape") +
                                     "': expected a number in [0, 0.5]",
                      kCreasesUsage);
  const std::string falloff = parsed.Get("falloff");
  if (parsed.Has("falloff") && falloff != "waters" && falloff != "smooth")
    return UsageError("creases", "--falloff '" + falloff + "': expected waters or smooth",
                      kCreasesUsage);
  double size = 320, zoom = 1.8;
  if (parsed.Has("size") && (!ParseNumber(parsed.Get("size"), 64, 2048, &size) ||
                             size != double(int(size))))
    return UsageError("creases", "--size '" + parsed.Get("size") +
                                     "': expected a whole number of pixels in [64, 2048]",
                      kCreasesUsage);
  if (parsed.Has("zoom") && !ParseNumber(parsed.Get("zoom"), 1, 16, &zoom))
    return UsageError("creases", "--zoom '" + parsed.Get("zoom") + "': expected a number in [1, 16]",
                      kCreasesUsage);
  const std::string image = parsed.Get("image");
  if (parsed.Has("image") && (image.size() < 4 || image.substr(image.size() - 4) != ".png"))
    return UsageError("creases", "--image '" + image + "': expected a .png file", kCreasesUsage);
  if ((parsed.Has("muscle") || parsed.Has("size") || parsed.Has("zoom")) && !parsed.Has("image"))
    return UsageError("creases", "--muscle, --size and --zoom go with --image", kCreasesUsage);
  Diagnostics diag;
  LoadedRig loaded;
  if (!LoadRig(parsed.positional[0], &loaded, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  if (parsed.Has("falloff")) {
    const MuscleFalloff kind = falloff == "smooth" ? MuscleFalloff::kSmooth : MuscleFalloff::kWaters;
    for (MuscleSpec& m : loaded.spec.muscles) m.falloff = kind;  // as the lines below print it
    Diagnostics build;
    Rig rebuilt;
    if (!BuildRigWithFalloff(loaded.spec, loaded.mesh, kind, &rebuilt, &build)) {
      diag.Append(build, parsed.positional[0]);
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
    loaded.rig = std::move(rebuilt);
  }
  const Rig& rig = loaded.rig;
  const CreaseReport report = MeasureCreases(rig, int(rings), min_shape);
  std::printf("creases of %s (%s fall-offs, band of %d rings, %u sliver edges under %g left "
              "out), degrees:\n",
              parsed.positional[0].c_str(),
              parsed.Has("falloff") ? falloff.c_str() : "the rig's own", int(rings),
              report.sliver_edges, min_shape);
  for (uint32_t m = 0; m < rig.muscle_count(); ++m)
    std::printf("  %-28s %-6s %7.3f  (%u edges; worst at %.4g %.4g %.4g)\n",
                rig.muscle_names()[m].c_str(), MuscleFalloffName(loaded.spec.muscles[m].falloff),
                report.muscle_degrees[m], report.band_edges[m], report.worst_at[m].x,
                report.worst_at[m].y, report.worst_at[m].z);
  std::printf("crease number: %.3f degrees (%s)\n", report.max_degrees,
              rig.muscle_count() ? rig.muscle_names()[report.worst_muscle].c_str() : "no muscles");
  if (!parsed.Has("image")) return 0;
  Rig waters, smooth;
  Diagnostics build;
  if (!BuildRigWithFalloff(loaded.spec, loaded.mesh, MuscleFalloff::kWaters, &waters, &build) ||
      !BuildRigWithFalloff(loaded.spec, loaded.mesh, MuscleFalloff::kSmooth, &smooth, &build)) {
    diag.Append(build, parsed.positional[0]);
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  int muscle = -1;
  if (parsed.Has("muscle")) {
    muscle = rig.FindMuscle(parsed.Get("muscle"));
    if (muscle < 0) {
      std::fprintf(stderr, "mimetic creases: --muscle '%s': no such muscle in %s\n",
                   parsed.Get("muscle").c_str(), parsed.positional[0].c_str());
      return 1;
    }
  } else if (rig.muscle_count() > 0) {
    muscle = int(MeasureCreases(waters, int(rings), min_shape).worst_muscle);
  }
  // Centre the view on the muscle's moving skin: the mean of the points it moves, projected
  // as RenderMesh's front camera does (tools/render/render.cpp: the bounding sphere fitted
  // into the view, perspective along -z).
  RenderOptions ro;
  ro.supersample = 2;
  const MeshData rest = PoseOne(smooth, loaded.mesh, -1);
  const MeshData moved_w = PoseOne(waters, loaded.mesh, muscle);
  const MeshData moved_s = PoseOne(smooth, loaded.mesh, muscle);
  float3 lo = loaded.mesh.positions[0], hi = lo, sum{0, 0, 0};
  double count = 0;
  for (size_t v = 0; v < loaded.mesh.vertex_count(); ++v) {
    const float3 p = loaded.mesh.positions[v];
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    if (Length(moved_s.positions[v] - p) > 0.f) sum += p, count += 1;
  }
  double fx = 0.5, fy = 0.45;
  if (count > 0) {
    const float3 c = sum * float(1.0 / count), centre = (lo + hi) * 0.5f;
    const double radius = std::max(1e-20, 0.5 * double(Length(hi - lo)));
    const double tan = std::tan(0.5 * double(ro.fov_deg) * 3.14159265358979323846 / 180.0);
    const double dist = radius / std::sin(std::atan(double(ro.fill) * tan));
    const double depth = dist - double(c.z - centre.z);
    fx = 0.5 + 0.5 * double(c.x - centre.x) / (depth * tan);
    fy = 0.5 - 0.5 * double(c.y - centre.y) / (depth * tan);
  }
  const int n = int(size);
  const Image panels = SideBySide({RenderCloseUp(rest, ro, n, zoom, fx, fy),
                                   RenderCloseUp(moved_w, ro, n, zoom, fx, fy),
                                   RenderCloseUp(moved_s, ro, n, zoom, fx, fy)},
                                  4, {1.f, 1.f, 1.f});
  Diagnostics write;
  if (!SavePng(image, panels, &write)) {
    std::fputs(write.Format().c_str(), stderr);
    return 1;
  }
  std::printf("wrote %s: rest | waters | smooth, %s at 1\n", image.c_str(),
              muscle >= 0 ? rig.muscle_names()[size_t(muscle)].c_str() : "no muscle");
  return 0;
}

}  // namespace mimetic::tools
