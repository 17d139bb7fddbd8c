// tools/play_golden.cpp: `mimetic play ... --write-golden DIR` (tools/play_golden.h).
#include "tools/play_golden.h"

#include "tools/play_inputs.h"

#include <cstdio>
#include <filesystem>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "core/file_util.h"
#include "io/golden_file.h"
#include "io/rig_loader.h"

namespace mimetic::tools {

const char* kPlayGoldenUsage =
    "       mimetic play RIG CLIP [--expression FILE]... --write-golden DIR [--frames T1,T2,...]\n"
    "  --write-golden DIR      write the playback golden DIR/<clip file name without\n"
    "                          .clip.json or .mclip>.golden: the outputs at the --frames times\n"
    "                          (default: a quarter, half and all of the duration), every skin\n"
    "                          layer on (tests/golden/README.md); only when a change of outputs\n"
    "                          is meant\n";

namespace {

int Usage(const std::string& error) {
  std::fprintf(stderr, "mimetic play: %s\n%s", error.c_str(), kPlayGoldenUsage);
  return kExitUsage;
}

std::string GoldenName(const std::string& clip_path) {
  std::string name = std::filesystem::path(clip_path).filename().string();
  for (const char* ext : {".clip.json", ".mclip", ".json"})
    if (name.size() > std::strlen(ext) && name.ends_with(ext)) {
      name.resize(name.size() - std::strlen(ext));
      break;
    }
  return name + ".golden";
}

}  // namespace

int PlayWriteGolden(const ParsedArgs& parsed) {
  if (parsed.Has("time") || parsed.Has("fps") || parsed.Has("out"))
    return Usage("--write-golden takes no --time, --fps or --out (it writes DIR/NAME.golden at "
                 "--frames)");
  const std::string dir = parsed.Get("write-golden");
  if (dir.empty()) return Usage("--write-golden: expected a folder");
  std::vector<double> frames;
  if (parsed.Has("frames")) {
    std::stringstream list(parsed.Get("frames"));
    std::string item;
    while (std::getline(list, item, ',')) {
      double t = 0;
      if (!ParseNumber(item, 0.0, 1e6, &t))
        return Usage("--frames " + parsed.Get("frames") + ": \"" + item +
                     "\" is not a time; expected seconds >= 0, comma-separated");
      frames.push_back(t);
    }
    if (frames.empty() || frames.size() > 16)
      return Usage("--frames " + parsed.Get("frames") + ": expected 1 to 16 times");
  }
  Diagnostics diag;
  LoadedRig loaded;
  CompiledClip clip;
  if (!LoadPlayInputs(parsed, "no golden was written", &loaded, &clip, &diag)) return kExitInput;
  const std::string& clip_path = parsed.positional[1];
  if (frames.empty()) {
    const double d = double(clip.duration());
    frames = {0.25 * d, 0.5 * d, d};
  }
  std::vector<float> times(frames.begin(), frames.end());
  Golden golden;
  if (!MakeGolden(loaded.rig, clip, times, &golden, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return kExitInput;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  const std::string path = JoinPath(dir, GoldenName(clip_path));
  Diagnostics write;
  if (!SaveGolden(path, golden, &write)) {
    std::fputs(write.Format().c_str(), stderr);
    return kExitInput;
  }
  std::printf("wrote %s: %zu frames of %zu sampled vertices (of %u), %zu bytes\n", path.c_str(),
              golden.frames.size(), golden.indices.size(), golden.vertex_count,
              GoldenToBytes(golden).size());
  return 0;
}

}  // namespace mimetic::tools
