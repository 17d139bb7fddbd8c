// tools/cmd_creases.cpp: `mimetic creases`, the crease number of each muscle
// (fitting/creases.h), for the rig's own fall-offs or with every muscle switched to one kind.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fitting/creases.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {

static const char* kCreasesUsage =
    "usage: mimetic creases RIG [--falloff waters|smooth] [--rings N]\n\n"
    "How sharply each muscle of RIG, alone at activation 1, folds the skin along the edges of\n"
    "its zone: the largest change of dihedral angle from rest (degrees) over the edges in a\n"
    "band around the zone's boundary, the boundary ring grown by N rings (--rings, default 2;\n"
    "docs/model.md §2-3). --falloff rebuilds the rig with every muscle's fall-off set to one\n"
    "kind, to compare Waters' cosines with the smooth (squared) ones on the same rig.\n";

int CmdCreases(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"falloff", "rings"}, {});
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
  const std::string falloff = parsed.Get("falloff");
  if (parsed.Has("falloff") && falloff != "waters" && falloff != "smooth")
    return UsageError("creases", "--falloff '" + falloff + "': expected waters or smooth",
                      kCreasesUsage);
  Diagnostics diag;
  LoadedRig loaded;
  if (!LoadRig(parsed.positional[0], &loaded, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  if (parsed.Has("falloff")) {
    for (MuscleSpec& m : loaded.spec.muscles)
      m.falloff = falloff == "smooth" ? MuscleFalloff::kSmooth : MuscleFalloff::kWaters;
    Diagnostics build;
    Rig rebuilt;
    if (!BuildRig(loaded.spec, loaded.mesh, {}, &rebuilt, &build)) {
      diag.Append(build, parsed.positional[0]);
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
    loaded.rig = std::move(rebuilt);
  }
  const Rig& rig = loaded.rig;
  const CreaseReport report = MeasureCreases(rig, int(rings));
  std::printf("creases of %s (%s fall-offs, band of %d rings), degrees:\n",
              parsed.positional[0].c_str(),
              parsed.Has("falloff") ? falloff.c_str() : "the rig's own", int(rings));
  for (uint32_t m = 0; m < rig.muscle_count(); ++m)
    std::printf("  %-28s %-6s %7.3f  (%u edges)\n", rig.muscle_names()[m].c_str(),
                MuscleFalloffName(loaded.spec.muscles[m].falloff), report.muscle_degrees[m],
                report.band_edges[m]);
  std::printf("crease number: %.3f degrees (%s)\n", report.max_degrees,
              rig.muscle_count() ? rig.muscle_names()[report.worst_muscle].c_str() : "no muscles");
  return 0;
}

}  // namespace mimetic::tools
