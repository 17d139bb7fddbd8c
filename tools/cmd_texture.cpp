// tools/cmd_texture.cpp: `mimetic texture`, the fine-scale wrinkle maps of a rig (docs/model.md
// §20-22): two 16-bit height maps (one per direction field), their merge and the 8-bit
// tangent-space normal map.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>

#include "core/image.h"
#include "io/image.h"
#include "io/rig_file.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "wrinkles/offline/fine_scale.h"

namespace mimetic::tools {
namespace {

const char* const kTextureUsage =
    "usage: mimetic texture RIG --size N --out DIR [--seed S] [--threads 1|2] [--update-rig]\n"
    "                       [--quiet]\n\n"
    "Carves the fine-scale wrinkle furrows of RIG's `fine_scale` block (docs/rig-format.md)\n"
    "along its two direction fields and writes, in DIR (created when missing):\n"
    "  fine_height_1.png, fine_height_2.png  16-bit grey height maps, one per field (white =\n"
    "                                        no furrow); a renderer scales each by its\n"
    "                                        per-vertex amplitude (EvaluateJob out_fine_amplitudes)\n"
    "  fine_height.png                       16-bit: their minimum, with k_noise\n"
    "  fine_normal.png                       8-bit tangent-space normal map (k_bump)\n\n"
    "  --size N       maps of N x N pixels, N in [16, 8192]\n"
    "  --out DIR      output folder\n"
    "  --seed S       random seed (default 1): the same seed gives the same bytes\n"
    "  --threads T    1 or 2 (one field per thread; the same bytes), default 1\n"
    "  --update-rig   write the maps' paths into RIG's fine_scale.maps (RIG is rewritten)\n"
    "  --quiet        no progress bar and no summary (errors are still printed)\n\n"
    "A progress bar is drawn on stderr when it is a terminal (and --quiet is not given).\n";

void PrintDiagnostics(const Diagnostics& diag) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
}

Gray16Image ToGray16(const std::vector<float>& h, int size) {
  Gray16Image img;
  img.width = img.height = size;
  img.pixels.resize(h.size());
  for (size_t i = 0; i < h.size(); ++i) {
    const float v = h[i] < 0.f ? 0.f : (h[i] > 1.f ? 1.f : h[i]);
    img.pixels[i] = uint16_t(std::lround(v * 65535.f));
  }
  return img;
}

}  // namespace

int CmdTexture(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"size", "out", "seed", "threads"}, {"quiet", "update-rig"});
  if (parsed.help) return std::fputs(kTextureUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("texture", parsed.error, kTextureUsage);
  if (parsed.positional.size() != 1)
    return UsageError("texture", parsed.positional.empty() ? "missing RIG" : "expected one RIG",
                      kTextureUsage);
  long long size = 0, seed = 1, threads = 1;
  if (!parsed.Has("size")) return UsageError("texture", "missing --size N", kTextureUsage);
  if (!ParseInteger(parsed.Get("size"), 16, kMaxFineScaleSize, &size))
    return UsageError("texture", "--size " + parsed.Get("size") + ": expected a whole number of "
                      "pixels in [16, " + std::to_string(kMaxFineScaleSize) + "]", kTextureUsage);
  const std::string out_dir = parsed.Get("out");
  if (out_dir.empty()) return UsageError("texture", "missing --out DIR", kTextureUsage);
  if (parsed.Has("seed") && !ParseInteger(parsed.Get("seed"), 0, (1ll << 53), &seed))
    return UsageError("texture", "--seed " + parsed.Get("seed") + ": expected a whole number in "
                      "[0, 2^53]", kTextureUsage);
  if (parsed.Has("threads") && !ParseInteger(parsed.Get("threads"), 1, 2, &threads))
    return UsageError("texture", "--threads " + parsed.Get("threads") + ": expected 1 or 2",
                      kTextureUsage);
  const bool quiet = parsed.flags.count("quiet") != 0;
  const std::string& rig_path = parsed.positional[0];
  if (IsCompiledRigPath(rig_path)) {
    std::fprintf(stderr, "mimetic texture: %s: a compiled rig keeps no direction fields; "
                         "expected the rig file (.rig.json) it was built from\n",
                 rig_path.c_str());
    return kExitInput;
  }

  Diagnostics diag;
  LoadedRig loaded;
  BuildOptions build;
  build.fine_scale_probes = false;  // the maps solve the fields themselves (MakeFineScaleMaps)
  if (!LoadRig(rig_path, &loaded, &diag, build)) {
    PrintDiagnostics(diag);
    std::fprintf(stderr, "mimetic texture: nothing was written\n");
    return kExitInput;
  }
  if (!loaded.spec.fine_scale) {
    std::fprintf(stderr, "%s: fine_scale: the rig has no fine_scale block (its two direction "
                         "fields, docs/rig-format.md); nothing was written\n", rig_path.c_str());
    return kExitInput;
  }
  PrintDiagnostics(diag);
  const FineScaleSpec& spec = *loaded.spec.fine_scale;
  FineScaleRigMesh mesh;
  Diagnostics fdiag;
  const uint32_t file_vertices = loaded.source_vertex_count ? loaded.source_vertex_count
                                                            : uint32_t(loaded.mesh.vertex_count());
  if (!MakeFineScaleRigMesh(spec, loaded.rig.data(), file_vertices, &mesh, &fdiag)) {
    std::fputs(fdiag.Format().c_str(), stderr);
    return kExitInput;
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (!std::filesystem::is_directory(out_dir)) {
    std::fprintf(stderr, "mimetic texture: --out %s: cannot create the folder%s%s\n",
                 out_dir.c_str(), ec ? ": " : "", ec ? ec.message().c_str() : "");
    return kExitInput;
  }

  Progress progress(100, !quiet, "%");
  std::mutex progress_mutex;
  FineScaleTextureOptions options;
  options.size = int(size);
  options.seed = uint64_t(seed);
  options.threads = int(threads);
  long long shown = -1;
  options.progress = [&](float f) {
    std::lock_guard<std::mutex> lock(progress_mutex);
    const long long pct = std::lround(100.f * f);
    if (pct != shown) progress.Update(shown = pct);
  };
  FineScaleMaps maps;
  if (!MakeFineScaleMaps(spec, mesh.view(), mesh.anchor_points, options, &maps, &fdiag)) {
    progress.Abort();
    std::fputs(fdiag.Format().c_str(), stderr);
    return kExitInput;
  }
  const std::string names[3] = {"fine_height_1.png", "fine_height_2.png", "fine_height.png"};
  const std::vector<float>* heights[3] = {&maps.height[0], &maps.height[1], &maps.merged};
  Diagnostics wdiag;
  for (int i = 0; i < 3; ++i)
    if (!SavePng16((std::filesystem::path(out_dir) / names[i]).string(),
                   ToGray16(*heights[i], maps.size), &wdiag))
      break;
  const std::string normal_path = (std::filesystem::path(out_dir) / "fine_normal.png").string();
  if (!wdiag.HasErrors()) {
    Image normal;
    normal.width = normal.height = maps.size;
    normal.rgb = maps.normal;
    SavePng(normal_path, normal, &wdiag);
  }
  if (!wdiag.HasErrors() && parsed.flags.count("update-rig")) {
    RigSpec updated;
    if (LoadRigSpec(rig_path, &updated, &wdiag) && updated.fine_scale) {
      for (int f = 0; f < 2; ++f)
        updated.fine_scale->height_maps[f] =
            std::filesystem::absolute(std::filesystem::path(out_dir) / names[f]).string();
      updated.fine_scale->normal_map = std::filesystem::absolute(normal_path).string();
      SaveRigSpec(rig_path, updated, &wdiag);
    }
  }
  if (wdiag.HasErrors()) {
    std::fputs(wdiag.Format().c_str(), stderr);
    return kExitInput;
  }
  if (!quiet)
    std::printf("wrote %s/{fine_height_1,fine_height_2,fine_height,fine_normal}.png (%lld x %lld, "
                "seed %lld)\n", out_dir.c_str(), size, size, seed);
  return 0;
}

}  // namespace mimetic::tools
