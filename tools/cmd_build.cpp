// tools/cmd_build.cpp: `mimetic build RIG --out FILE.mrig`, the compiled rig.
#include <cstdio>
#include <string>

#include "core/file_util.h"
#include "io/rig_loader.h"
#include "rig/runtime/rig_binary.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {
namespace {

const char* kBuildUsage =
    "usage: mimetic build RIG --out FILE.mrig\n\n"
    "Loads RIG (a .rig.json file, docs/rig-format.md, with its mesh and images), builds it\n"
    "(refinement, muscle tables, wrinkle regions) and writes the result as a compiled rig\n"
    "(docs/mrig-format.md): a versioned little-endian binary that the runtime library loads\n"
    "alone, without JSON, glTF or image code, many times faster than building the rig.\n"
    "`mimetic info`, `eval` and `play` accept the .mrig in place of the .rig.json. The same\n"
    "rig always gives the same bytes.\n\n"
    "options:\n"
    "  --out FILE.mrig   the compiled rig (written atomically; not one of the rig's inputs)\n";

}  // namespace

int CmdBuild(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"out"}, {});
  if (parsed.help) return std::fputs(kBuildUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("build", parsed.error, kBuildUsage);
  if (parsed.positional.size() != 1)
    return UsageError("build", parsed.positional.empty() ? "missing RIG" : "expected one RIG",
                      kBuildUsage);
  const std::string out_path = parsed.Get("out");
  if (out_path.empty()) return UsageError("build", "missing --out FILE.mrig", kBuildUsage);
  const std::string bad_ext = CheckOutputExtension("out", out_path, {".mrig"});
  if (!bad_ext.empty()) return UsageError("build", bad_ext, kBuildUsage);
  const std::string& rig_path = parsed.positional[0];
  if (SameFile(out_path, rig_path))
    return UsageError("build", "--out " + out_path + " is the rig; expected another file name",
                      kBuildUsage);

  LoadedRig loaded;
  Diagnostics diag;
  const bool ok = LoadRig(rig_path, &loaded, &diag);
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
  if (!ok) {
    std::fprintf(stderr, "mimetic build: %s: %zu error(s); nothing was written\n",
                 rig_path.c_str(), diag.ErrorCount());
    return kExitInput;
  }
  for (const std::string& input : {loaded.spec.mesh_path, loaded.spec.thickness.image_path})
    if (!input.empty() && SameFile(out_path, input))
      return UsageError("build", "--out " + out_path + " is " + input +
                                     ", an input of the rig; expected another file name",
                        kBuildUsage);
  RigBinaryInfo info;
  info.units = loaded.spec.units;
  info.source_vertex_count =
      loaded.compiled ? loaded.source_vertex_count : uint32_t(loaded.mesh.vertex_count());
  const std::string bytes = WriteRigBinary(loaded.rig.data(), &info);
  Diagnostics write;
  if (!WriteFileAtomic(out_path, bytes, &write)) {
    std::fputs(write.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic build: nothing was written\n");
    return kExitInput;
  }
  const Rig& rig = loaded.rig;
  std::printf("wrote %s (%zu bytes, format %u.%u: %u points, %u vertices, %u triangles, "
              "%u muscles, %zu wrinkled muscles, %zu curve wrinkles)\n",
              out_path.c_str(), bytes.size(), unsigned(kRigBinaryMajor),
              unsigned(kRigBinaryMinor), rig.point_count(), rig.vertex_count(),
              rig.triangle_count(), rig.muscle_count(), rig.muscle_wrinkles().size(),
              rig.curve_wrinkles().wrinkles.size());
  return 0;
}

}  // namespace mimetic::tools
