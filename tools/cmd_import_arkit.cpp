// tools/cmd_import_arkit.cpp: `mimetic import-arkit`: a face-capture take (ARKit blendshape
// weights per frame, CSV or JSON) through an ARKit map into a clip of muscle channels
// (docs/arkit.md, "Importing a take").
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "expressions/offline/arkit_import.h"
#include "io/arkit_map.h"
#include "io/arkit_take.h"
#include "io/clip_file.h"
#include "io/rig_loader.h"
#include "io/rig_file.h"
#include "expressions/runtime/clip.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {
namespace {

const char* kImportUsage =
    "usage: mimetic import-arkit TAKE.csv|TAKE.json --rig RIG --out CLIP.clip.json\n"
    "                            [--map MAP] [--fps F] [--name NAME]\n\n"
    "Turns a face-capture take into a clip (docs/arkit.md, \"Importing a take\"): per frame, each\n"
    "muscle's activation is clamp(sum over the take's ARKit channels of weight * the map's\n"
    "activation, 0, 1); one linear muscle channel per muscle the take moves, keys a linear\n"
    "interpolation reproduces within 1e-4 dropped. Channels that are not ARKit names or that the\n"
    "map marks \"none\" are listed in one warning.\n\n"
    "  TAKE.csv                a header row (Timecode HH:MM:SS:FF[.fff] or Time / Seconds in\n"
    "                          seconds, optionally BlendShapeCount, one column per blendshape:\n"
    "                          jawOpen or Live Link Face's JawOpen), then one row per frame\n"
    "  TAKE.json               [{\"time\": s, \"blendshapes\": {\"jawOpen\": 0.3, ...}}, ...]\n"
    "  --rig RIG               the rig the clip is for (its muscles name the channels)\n"
    "  --out CLIP              the clip to write (atomically), a .json file\n"
    "  --map MAP               the ARKit map (default assets/arkit/default.arkit.json beside\n"
    "                          the rig's folder's assets, else the one in the source tree)\n"
    "  --fps F                 the frame rate of the CSV timecodes (default 60)\n"
    "  --name NAME             the clip's name (default: the take's file name)\n";

std::string Stem(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  const size_t dot = name.find('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

}  // namespace

int CmdImportArkit(const Args& args) {
  const ParsedArgs parsed = ParseArgs(args, {"rig", "out", "map", "fps", "name"}, {});
  if (parsed.help) return std::fputs(kImportUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("import-arkit", parsed.error, kImportUsage);
  if (parsed.positional.size() != 1)
    return UsageError("import-arkit", parsed.positional.empty() ? "missing TAKE"
                                                                 : "expected one TAKE",
                      kImportUsage);
  const std::string take_path = parsed.positional[0];
  const std::string rig_path = parsed.Get("rig"), out = parsed.Get("out");
  if (rig_path.empty()) return UsageError("import-arkit", "missing --rig RIG", kImportUsage);
  if (out.empty()) return UsageError("import-arkit", "missing --out CLIP", kImportUsage);
  if (const std::string bad = CheckOutputExtension("out", out, {".json"}); !bad.empty())
    return UsageError("import-arkit", bad, kImportUsage);
  if (const std::string bad = CheckOutputExtension("take", take_path, {".csv", ".json"});
      !bad.empty())
    return UsageError("import-arkit", "TAKE " + take_path + ": expected a .csv or .json file",
                      kImportUsage);
  double fps = 60.0;
  if (parsed.Has("fps") && (!ParseNumber(parsed.Get("fps"), 0.0, 1000.0, &fps) || !(fps > 0)))
    return UsageError("import-arkit", "--fps " + parsed.Get("fps") +
                                          ": expected frames per second in (0, 1000]",
                      kImportUsage);
  const std::string map_path = parsed.Has("map") ? parsed.Get("map") : DefaultArkitMap(rig_path);
  for (const std::string& input : {take_path, rig_path, map_path})
    if (SameFile(out, input))
      return UsageError("import-arkit", "--out " + out + " is " + input +
                                            ", an input; expected another file name",
                        kImportUsage);

  Diagnostics diag;
  ArkitTake take;
  const bool take_ok = LoadArkitTake(take_path, fps, &take, &diag);
  std::vector<ArkitShape> map;
  const bool map_ok = LoadArkitMap(map_path, &map, &diag);
  // The rig's muscle names (the spec is enough: no mesh is built).
  RigSpec rig;
  const bool rig_ok = LoadRigSpec(rig_path, &rig, &diag);
  if (!take_ok || !map_ok || !rig_ok) {
    std::fputs(diag.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic import-arkit: %zu error(s); nothing was written\n",
                 diag.ErrorCount());
    return kExitInput;
  }
  std::vector<std::string> muscles;
  for (const MuscleSpec& m : rig.muscles) muscles.push_back(m.name);
  if (rig.jaw) muscles.push_back(kJawInputName);  // the jaw opening, a channel like a muscle
  if (!CheckArkitMuscles(map, muscles, map_path, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic import-arkit: %s names muscles %s does not have; nothing "
                         "was written\n", map_path.c_str(), rig_path.c_str());
    return kExitInput;
  }
  std::vector<ArkitShapeActivations> shapes;
  for (const ArkitShape& s : map)
    shapes.push_back({s.name, s.how == ArkitShape::How::kNone, s.activations});
  ArkitImport result;
  Diagnostics import;
  const bool ok = ImportArkitTake(take, shapes, muscles,
                                  parsed.Has("name") ? parsed.Get("name") : Stem(take_path),
                                  &result, &import);
  diag.Append(import, take_path);
  const std::string warning = ArkitUnmappedWarning(result.unmapped);
  if (!warning.empty()) diag.Warning(take_path, warning);
  if (!ok) {
    std::fputs(diag.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic import-arkit: nothing was written\n");
    return kExitInput;
  }
  std::error_code ec;
  if (const std::string dir = std::filesystem::path(out).parent_path().string(); !dir.empty())
    std::filesystem::create_directories(dir, ec);
  if (!SaveClip(out, result.clip, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return kExitInput;
  }
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
  size_t keys = 0;
  for (const ClipChannelSpec& c : result.clip.channels) keys += c.keys.size();
  std::printf("imported %s: %zu frames, %zu channels (%zu mapped) over %g s\n", take_path.c_str(),
              take.times.size(), take.names.size(),
              take.names.size() - result.unmapped.size(), double(take.times.back()));
  std::printf("wrote %s: %zu muscle channels, %zu keys (of %zu before the reduction)\n",
              out.c_str(), result.clip.channels.size(), keys,
              result.clip.channels.size() * take.times.size());
  return 0;
}

}  // namespace mimetic::tools
