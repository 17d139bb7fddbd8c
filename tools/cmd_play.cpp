// tools/cmd_play.cpp: `mimetic play`: a clip (docs/expressions.md) sampled and played on a rig,
// written as one mesh or as an OBJ sequence.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/file_util.h"
#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"
#include "geometry/mesh.h"
#include "io/clip_file.h"
#include "io/expression_file.h"
#include "io/expression_library.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "io/companion_meshes.h"
#include "tools/play_bake.h"
#include "tools/play_golden.h"
#include "tools/play_inputs.h"

namespace mimetic::tools {
namespace {

const char* kPlayUsage =
    "usage: mimetic play RIG CLIP [--expression FILE]... [--library FILE]... --time T --out FILE\n"
    "       mimetic play RIG CLIP [--expression FILE]... [--library FILE]... --fps F\n"
    "                    --out DIR/frame_%04d.obj | --out FILE.glb\n"
    "                    [--no-thickness] [--no-muscle-wrinkles] [--no-curve-wrinkles]\n"
    "                    [--no-normals] [--tension] [--threads N] [--quiet]\n\n"
    "Samples CLIP (a mimetic-clip file, docs/expressions.md) and poses RIG with the\n"
    "activations it gives (as `mimetic eval` does), at one time or at every frame.\n\n"
    "options:\n"
    "  --expression FILE       a mimetic-expression file for the clip's expression channels\n"
    "                          (repeatable; the clip names them by their \"name\")\n"
    "  --library FILE          a mimetic-expression-library file (io/expression_library.h,\n"
    "                          e.g. assets/expressions/default.library.json): its expressions\n"
    "                          too (repeatable; a name given twice is an error)\n"
    "  --time T                one pose at T seconds (the clip's end rule applies: clamp holds\n"
    "                          the last pose, loop wraps); --out is then a .obj or .glb file\n"
    "  --fps F                 every frame at F frames per second (0 < F <= 1000): frame i at\n"
    "                          i / F s, from 0 to the duration (loop: up to, not including,\n"
    "                          the duration); --out is then a name with one %d or %0Nd\n"
    "                          (the frame number) ending in .obj, %% for a percent sign;\n"
    "                          or one .glb: the bake (docs/expressions.md \"Bake\"): the neutral\n"
    "                          mesh, one morph target per frame (sparse where few vertices\n"
    "                          move) and a weights animation standard glTF viewers play\n"
    "  --out FILE|PATTERN      where to write; folders are made as needed\n"
    "  --no-thickness          skip the volume-preserving thickness layer (docs/model.md §4)\n"
    "  --no-muscle-wrinkles    skip muscle-derived wrinkles (docs/model.md §6)\n"
    "  --no-curve-wrinkles     skip curve wrinkles (docs/model.md §7-8)\n"
    "  --no-normals            bake only: no NORMAL attribute and no normal deltas (smaller\n"
    "                          file; viewers then compute flat normals)\n"
    "  --tension               bake only: each frame's tension for engine shaders\n"
    "                          (docs/tension.md \"Baking\"): a _TENSION attribute (r - 1, eps)\n"
    "                          per vertex with its deltas in every morph target, and, when the\n"
    "                          rig has tension regions, their weights per frame in\n"
    "                          FILE.regions.json beside FILE.glb\n"
    "  --threads N             bake only: frames evaluated on N threads (default: the\n"
    "                          machine's, at most 8); the frames are the same bits\n"
    "  --quiet                 no progress bar and no summary (errors are still printed)\n\n"
    "A progress bar is drawn on stderr when it is a terminal (and --quiet is not given).\n";

// At most this many frames in a sequence.
constexpr long long kMaxFrames = 100000;
// At most this many frames in a bake: its weights animation holds #frames^2 floats.
constexpr long long kMaxBakeFrames = 2000;

void PrintDiagnostics(const Diagnostics& diag) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
}

// The expressions the clip's expression channels may name: each --expression file, then
// every expression of each --library file (the builder refuses a name given twice).
bool LoadPlayExpressions(const ParsedArgs& parsed, std::vector<Expression>* out,
                         Diagnostics* diag) {
  bool ok = true;
  if (const auto it = parsed.values.find("expression"); it != parsed.values.end())
    for (const std::string& path : it->second) {
      Expression e;
      if (LoadExpression(path, &e, diag)) out->push_back(std::move(e));
      else ok = false;
    }
  if (const auto it = parsed.values.find("library"); it != parsed.values.end())
    for (const std::string& path : it->second) {
      std::vector<Expression> library;
      if (LoadExpressionLibrary(path, &library, diag))
        for (Expression& e : library) out->push_back(std::move(e));
      else ok = false;
    }
  return ok;
}

}  // namespace

bool LoadPlayInputs(const ParsedArgs& parsed, const char* nothing_written, LoadedRig* loaded,
                    CompiledClip* clip, Diagnostics* diag) {
  return LoadClipInputs("play", parsed.positional[0], parsed.positional[1], parsed,
                        nothing_written, loaded, clip, diag);
}

bool LoadClipInputs(const std::string& command, const std::string& rig_path,
                    const std::string& clip_path, const ParsedArgs& parsed,
                    const char* nothing_written, LoadedRig* loaded, CompiledClip* clip,
                    Diagnostics* diag) {
  const bool rig_ok = LoadRig(rig_path, loaded, diag);
  if (IsCompiledClipPath(clip_path)) {
    std::string why;
    const bool clip_ok = LoadClipBinaryFile(clip_path, clip, &why);
    if (!clip_ok) diag->Error(clip_path, why.substr(std::min(why.size(), clip_path.size() + 2)));
    if (rig_ok && clip_ok && clip->muscle_count() != loaded->rig.muscle_count()) {
      diag->Error(clip_path, "was compiled for a rig of " + std::to_string(clip->muscle_count()) +
                                 " muscles; " + rig_path + " has " +
                                 std::to_string(loaded->rig.muscle_count()) +
                                 " (compile the clip for this rig: mimetic build CLIP.clip.json "
                                 "--rig " + rig_path + " --out FILE.mclip)");
    }
    if (diag->ErrorCount()) {
      PrintDiagnostics(*diag);
      std::fprintf(stderr, "mimetic %s: %zu error(s); %s\n", command.c_str(), diag->ErrorCount(),
                   nothing_written);
      return false;
    }
    if (parsed.Has("expression") || parsed.Has("library"))
      diag->Warning(clip_path, "is a compiled clip: it holds the expressions it uses, so "
                               "--expression and --library are not used");
  } else {
    ClipSpec spec;
    const bool clip_ok = LoadClip(clip_path, &spec, diag);
    std::vector<Expression> expressions;
    const bool expressions_ok = LoadPlayExpressions(parsed, &expressions, diag);
    if (!rig_ok || !clip_ok || !expressions_ok) {
      PrintDiagnostics(*diag);
      std::fprintf(stderr, "mimetic %s: %zu error(s); %s\n", command.c_str(), diag->ErrorCount(),
                   nothing_written);
      return false;
    }
    Diagnostics build;
    if (!BuildClip(spec, loaded->rig.muscle_names(), expressions, clip, &build)) {
      diag->Append(build, clip_path);
      PrintDiagnostics(*diag);
      std::fprintf(stderr, "mimetic %s: %s does not play on %s: %zu error(s); %s\n",
                   command.c_str(), clip_path.c_str(), rig_path.c_str(), build.ErrorCount(),
                   nothing_written);
      return false;
    }
  }
  if (clip->animates_jaw() && loaded->rig.jaw().empty())
    diag->Warning(clip_path, "animates the jaw, but " + rig_path + " has none (its \"jaw\" "
                             "values do nothing; docs/rig-format.md \"jaw\")");
  return true;
}

namespace {

// A frame-name pattern: `prefix %0Nd suffix` with %% for '%'. Empty `error` when it parses.
struct FramePattern {
  std::string prefix, suffix;
  int width = 0;
  std::string error;
  std::string Name(long long frame) const {
    std::string digits = std::to_string(frame);
    if (int(digits.size()) < width) digits.insert(0, size_t(width) - digits.size(), '0');
    return prefix + digits + suffix;
  }
};

FramePattern ParsePattern(const std::string& text) {
  FramePattern p;
  int conversions = 0;
  std::string* part = &p.prefix;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      *part += text[i];
      continue;
    }
    if (i + 1 < text.size() && text[i + 1] == '%') {
      *part += '%';
      ++i;
      continue;
    }
    size_t j = i + 1;
    int width = 0;
    if (j < text.size() && text[j] == '0') ++j;
    while (j < text.size() && text[j] >= '0' && text[j] <= '9' && width < 100)
      width = width * 10 + (text[j++] - '0');
    if (j >= text.size() || text[j] != 'd' || width > 9) {
      p.error = "--out " + text + ": '%' at character " + std::to_string(i + 1) +
                " is not %d, %0Nd (N at most 9) or %%";
      return p;
    }
    if (++conversions > 1) {
      p.error = "--out " + text + ": more than one frame number (%d); expected exactly one";
      return p;
    }
    p.width = width;
    part = &p.suffix;
    i = j;
  }
  if (conversions == 0)
    p.error = "--out " + text + ": no frame number; expected a name with %d or %0Nd, e.g. "
              "out/frame_%04d.obj";
  return p;
}


}  // namespace

int CmdPlay(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"expression", "library", "time", "fps", "out", "threads", "write-golden", "frames"},
                {"no-thickness", "no-muscle-wrinkles", "no-curve-wrinkles", "no-normals",
                 "tension", "quiet"});
  if (parsed.help) return std::fputs(kPlayUsage, stdout), std::fputs(kPlayGoldenUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("play", parsed.error, kPlayUsage);
  if (parsed.positional.size() != 2)
    return UsageError("play",
                      parsed.positional.empty()       ? "missing RIG and CLIP"
                      : parsed.positional.size() == 1 ? "missing CLIP"
                                                      : "expected one RIG and one CLIP",
                      kPlayUsage);
  if (parsed.Has("write-golden")) return PlayWriteGolden(parsed);
  const bool at_time = parsed.Has("time"), sequence = parsed.Has("fps");
  if (at_time == sequence)
    return UsageError("play", at_time ? "--time and --fps together; expected one of them"
                                      : "missing --time T or --fps F",
                      kPlayUsage);
  const std::string out = parsed.Get("out");
  if (out.empty()) return UsageError("play", "missing --out", kPlayUsage);
  double time = 0.0, fps = 0.0;
  FramePattern pattern;
  const bool quiet = parsed.flags.count("quiet") != 0;
  const bool bake = sequence && CheckOutputExtension("out", out, {".glb"}).empty();
  for (const char* bake_only : {"no-normals", "tension", "threads"})
    if (!bake && parsed.Has(bake_only))
      return UsageError("play", std::string("--") + bake_only +
                                    " is for a bake only (--fps F --out FILE.glb)", kPlayUsage);
  long long threads = 0;
  if (parsed.Has("threads") && !ParseInteger(parsed.Get("threads"), 1, 64, &threads))
    return UsageError("play", "--threads " + parsed.Get("threads") +
                                  ": expected a whole number of threads in [1, 64]", kPlayUsage);
  if (at_time) {
    if (!ParseNumber(parsed.Get("time"), -1e30, 1e30, &time))
      return UsageError("play", "--time " + parsed.Get("time") + ": expected a number of seconds",
                        kPlayUsage);
    const std::string bad_ext = CheckOutputExtension("out", out, {".obj", ".glb"});
    if (!bad_ext.empty()) return UsageError("play", bad_ext, kPlayUsage);
  } else {
    if (!ParseNumber(parsed.Get("fps"), 0.0, 1000.0, &fps) || !(fps > 0.0))
      return UsageError("play", "--fps " + parsed.Get("fps") + ": expected a number of frames "
                                "per second in (0, 1000]", kPlayUsage);
    if (bake && out.find('%') != std::string::npos)
      return UsageError("play", "--out " + out + ": a .glb bake is one file, not a frame "
                                "pattern; expected a name without '%' (or frame_%04d.obj for "
                                "an OBJ sequence)", kPlayUsage);
    if (!bake) {
      pattern = ParsePattern(out);
      if (!pattern.error.empty()) return UsageError("play", pattern.error, kPlayUsage);
      const std::string bad_ext = CheckOutputExtension("out", out, {".obj", ".glb"});
      if (!bad_ext.empty()) return UsageError("play", bad_ext, kPlayUsage);
    }
  }

  // Inputs: the rig, the clip, the expressions; every problem of each is printed.
  const std::string& rig_path = parsed.positional[0];
  const std::string& clip_path = parsed.positional[1];
  Diagnostics diag;
  LoadedRig loaded;
  CompiledClip clip;
  if (!LoadPlayInputs(parsed, "nothing was written", &loaded, &clip, &diag)) return kExitInput;
  const Rig& rig = loaded.rig;
  PrintDiagnostics(diag);  // warnings (a rig's winding, ...)

  // The frames: times and file names.
  std::vector<double> times;
  std::vector<std::string> names;
  if (at_time) {
    times.push_back(time);
    names.push_back(out);
  } else {
    const double span_frames = double(clip.duration()) * fps;
    const long long count =
        clip.end() == ClipEnd::kLoop
            ? std::max(1LL, (long long)std::ceil(span_frames - 1e-9))
            : (long long)std::floor(span_frames + 1e-9) + 1;
    const long long max_frames = bake ? kMaxBakeFrames : kMaxFrames;
    if (count > max_frames) {
      std::fprintf(stderr, "error: %s: the clip lasts %g s: %lld frames at %g fps; expected at "
                           "most %lld frames%s (lower --fps)\n", clip_path.c_str(),
                   double(clip.duration()), count, fps, max_frames, bake ? " in a bake" : "");
      return kExitInput;
    }
    for (long long i = 0; i < count; ++i) {
      times.push_back(double(i) / fps);
      names.push_back(bake ? out : pattern.Name(i));
    }
    if (bake) names.resize(1);
    if (bake && parsed.Has("tension")) names.push_back(RegionWeightsPath(out));
  }
  // No output replaces an input.
  std::vector<std::string> inputs = {rig_path, clip_path, loaded.spec.mesh_path,
                                     loaded.spec.thickness.image_path};
  for (const char* key : {"expression", "library"})
    if (const auto it = parsed.values.find(key); it != parsed.values.end())
      inputs.insert(inputs.end(), it->second.begin(), it->second.end());
  for (const std::string& name : names)
    for (const std::string& input : inputs)
      if (!input.empty() && SameFile(name, input))
        return UsageError("play", "--out " + out + ": " + name + " is " + input +
                                      ", an input; expected another file name", kPlayUsage);

  // Per frame: sample, evaluate, write. All per-frame buffers are made once here.
  const SkinLayers layers{.thickness = !parsed.flags.count("no-thickness"),
                          .muscle_wrinkles = !parsed.flags.count("no-muscle-wrinkles"),
                          .curve_wrinkles = !parsed.flags.count("no-curve-wrinkles")};
  if (bake) {
    PlayBakeRequest request;
    request.rig = &rig;
    request.spec = &loaded.spec;
    request.clip = &clip;
    request.times = times;
    request.layers = layers;
    request.out = out;
    request.rig_path = rig_path;
    request.clip_path = clip_path;
    request.fps = fps;
    const double unit = MetresPerUnit(loaded.spec.units);
    request.metres_per_unit = unit > 0 ? unit : 0.001;
    request.normals = !parsed.flags.count("no-normals");
    request.tension = parsed.flags.count("tension") != 0;
    if (request.tension && rig.tension_region_count() > 0)
      request.regions_out = RegionWeightsPath(out);
    request.quiet = quiet;
    request.threads = unsigned(threads);
    return PlayBake(request);
  }
  MeshData posed = RestMesh(rig);
  posed.normals.resize(posed.positions.size());
  EvaluateContext context(rig);
  std::vector<float> activations(rig.muscle_count(), 0.f);
  float jaw = 0.f;
  ClipSampleJob sample;
  sample.clip = &clip;
  sample.out_activations = activations;
  sample.out_jaw = span<float>(&jaw, 1);
  EvaluateJob evaluate;
  evaluate.rig = &rig;
  evaluate.context = &context;
  evaluate.activations = activations;
  evaluate.out_positions = span<float>(&posed.positions[0].x, posed.positions.size() * 3);
  evaluate.out_normals = span<float>(&posed.normals[0].x, posed.normals.size() * 3);
  evaluate.layers = layers;
  const double metres = MetresPerUnit(loaded.spec.units);
  // The mesh file's other meshes (the sample head's eyeballs) go along unchanged.
  CompanionMeshes companions;
  if (!LoadCompanionMeshes(loaded, &companions, &diag)) {
    PrintDiagnostics(diag);
    return kExitInput;
  }
  std::error_code ec;
  Progress progress(static_cast<long long>(times.size()), !quiet);
  for (size_t f = 0; f < times.size(); ++f) {
    sample.time = float(times[f]);
    const bool sampled = sample.Run();
    evaluate.jaw = jaw;
    if (!sampled || !evaluate.Run()) {
      progress.Abort();
      std::fprintf(stderr, "mimetic play: evaluation failed (internal error: job did not "
                           "validate)\n");
      return kExitInput;
    }
    if (Diagnostics bad; !CheckPosedFinite(rig, loaded.spec, activations, layers, posed, &bad)) {
      progress.Abort();
      diag.Append(bad, rig_path);
      PrintDiagnostics(diag);
      std::fprintf(stderr, "mimetic play: the posed mesh of frame %zu (t = %g s) is not finite; "
                           "%zu frame(s) were written\n", f, times[f], f);
      return kExitInput;
    }
    const std::string dir = DirectoryOf(names[f]);
    if (!dir.empty()) std::filesystem::create_directories(dir, ec);
    Diagnostics write;
    if (!WritePosedWithCompanions(names[f], posed, companions, &write, metres > 0 ? metres : 0.001)) {
      progress.Abort();
      PrintDiagnostics(write);
      std::fprintf(stderr, "mimetic play: %zu of %zu frame(s) were written\n", f, times.size());
      return kExitInput;
    }
    progress.Update(static_cast<long long>(f + 1));
  }

  const char* end = clip.end() == ClipEnd::kLoop ? "loop" : "clamp";
  if (quiet) return 0;
  if (at_time) {
    std::printf("played %s (%g s, %s) on %s at t = %g s (clip time %g s)\n", clip_path.c_str(),
                double(clip.duration()), end, rig_path.c_str(), time,
                double(ClipLocalTime(clip, float(time))));
    std::printf("wrote %s (%u vertices, %u triangles)\n", out.c_str(), rig.vertex_count(),
                rig.triangle_count());
  } else {
    std::printf("played %s (%g s, %s) on %s at %g fps\n", clip_path.c_str(),
                double(clip.duration()), end, rig_path.c_str(), fps);
    std::printf("wrote %zu frames: %s .. %s (%u vertices, %u triangles each)\n", names.size(),
                names.front().c_str(), names.back().c_str(), rig.vertex_count(),
                rig.triangle_count());
  }
  return 0;
}

}  // namespace mimetic::tools
