// tools/cmd_build.cpp: `mimetic build RIG --out FILE.mrig`, the compiled rig, and
// `mimetic build CLIP --rig RIG --out FILE.mclip`, the compiled clip.
#include <cstdio>
#include <string>

#include "core/file_util.h"
#include "expressions/runtime/clip_binary.h"
#include "io/rig_loader.h"
#include "rig/runtime/rig_binary.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/play_inputs.h"

namespace mimetic::tools {
namespace {

const char* kBuildUsage =
    "usage: mimetic build RIG --out FILE.mrig\n"
    "       mimetic build CLIP --rig RIG [--expression FILE]... [--library FILE]... --out "
    "FILE.mclip\n\n"
    "Loads RIG (a .rig.json file, docs/rig-format.md, with its mesh and images), builds it\n"
    "(refinement, muscle tables, wrinkle regions) and writes the result as a compiled rig\n"
    "(docs/mrig-format.md): a versioned little-endian binary that the runtime library loads\n"
    "alone, without JSON, glTF or image code, many times faster than building the rig.\n"
    "`mimetic info`, `eval` and `play` accept the .mrig in place of the .rig.json. The same\n"
    "rig always gives the same bytes.\n\n"
    "With --out FILE.mclip: loads CLIP (a mimetic-clip file, docs/expressions.md), resolves it\n"
    "against RIG's muscles and the expressions of the --expression and --library files (as\n"
    "`mimetic play` does) and writes the compiled clip (docs/mclip-format.md), which `play`\n"
    "and the runtime read without JSON. It plays on rigs of RIG's muscles only.\n\n"
    "options:\n"
    "  --out FILE        FILE.mrig: the compiled rig; FILE.mclip: the compiled clip (written\n"
    "                    atomically; not one of the inputs)\n"
    "  --rig RIG         the rig a clip is compiled for (.rig.json or .mrig; clips only)\n"
    "  --expression FILE, --library FILE\n"
    "                    the expressions the clip's expression channels name (clips only,\n"
    "                    repeatable)\n";

int BuildClipFile(const ParsedArgs& parsed, const std::string& out_path) {
  const std::string& clip_path = parsed.positional[0];
  const std::string rig_path = parsed.Get("rig");
  if (rig_path.empty())
    return UsageError("build", "missing --rig RIG (a clip is compiled for one rig's muscles)",
                      kBuildUsage);
  for (const std::string& input : {clip_path, rig_path})
    if (SameFile(out_path, input))
      return UsageError("build", "--out " + out_path + " is " + input +
                                     ", an input; expected another file name",
                        kBuildUsage);
  LoadedRig loaded;
  CompiledClip clip;
  Diagnostics diag;
  if (!LoadClipInputs("build", rig_path, clip_path, parsed, "nothing was written", &loaded,
                      &clip, &diag))
    return kExitInput;
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
  const std::string bytes = WriteClipBinary(clip);
  Diagnostics write;
  if (!WriteFileAtomic(out_path, bytes, &write)) {
    std::fputs(write.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic build: nothing was written\n");
    return kExitInput;
  }
  std::printf("wrote %s (%zu bytes, format %u.%u: clip \"%s\", %g s, %u channels, %zu keys, "
              "%u expressions, for %u muscles)\n",
              out_path.c_str(), bytes.size(), unsigned(kClipBinaryMajor),
              unsigned(kClipBinaryMinor), clip.name().c_str(), double(clip.duration()),
              clip.channel_count(), clip.key_times().size(), clip.expression_count(),
              clip.muscle_count());
  return 0;
}

}  // namespace

int CmdBuild(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"out", "rig", "expression", "library"}, {});
  if (parsed.help) return std::fputs(kBuildUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("build", parsed.error, kBuildUsage);
  if (parsed.positional.size() != 1)
    return UsageError("build",
                      parsed.positional.empty() ? "missing RIG or CLIP" : "expected one RIG or CLIP",
                      kBuildUsage);
  const std::string out_path = parsed.Get("out");
  if (out_path.empty())
    return UsageError("build", "missing --out FILE.mrig or --out FILE.mclip", kBuildUsage);
  const std::string bad_ext = CheckOutputExtension("out", out_path, {".mrig", ".mclip"});
  if (!bad_ext.empty()) return UsageError("build", bad_ext, kBuildUsage);
  if (CheckOutputExtension("out", out_path, {".mclip"}).empty())
    return BuildClipFile(parsed, out_path);
  for (const char* clip_only : {"rig", "expression", "library"})
    if (parsed.Has(clip_only))
      return UsageError("build", std::string("--") + clip_only +
                                     " is for a clip (--out FILE.mclip); a rig takes none",
                        kBuildUsage);
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
