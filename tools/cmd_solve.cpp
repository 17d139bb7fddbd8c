// tools/cmd_solve.cpp: `mimetic solve`, the activations that bring a rig closest to a target
// shape (fitting/solve.h), written as an expression file (io/expression_file.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "fitting/compare.h"
#include "fitting/solve.h"
#include "geometry/mesh.h"
#include "io/expression_file.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {

static const char* kSolveUsage =
    "usage: mimetic solve RIG --target SHAPE --out EXPRESSION.json [--muscles A,B,...]\n"
    "                     [--mirror] [--threshold T] [--outside-weight W] [--steps N]\n"
    "                     [--height-weight H] [--name NAME] [--posed MESH]\n\n"
    "Finds the muscle activations (each in [0, 1]) whose evaluated mesh is closest to SHAPE,\n"
    "a mesh with the topology of RIG's own mesh (the same vertices and triangles, e.g. an\n"
    "expression scan of the same head), and writes them as an expression file.\n"
    "Weighted least squares over the target's vertices: weight 1 where SHAPE moves more than T\n"
    "from the rig's rest shape (--threshold, mesh units; default 2% of its largest motion),\n"
    "W elsewhere (--outside-weight, default 0.25). Muscle motion is linear in the activations,\n"
    "so a bounded linear solve on the muscle basis comes first, then N Gauss-Newton steps with\n"
    "every skin layer on (--steps, default 3; docs/model.md §13).\n"
    "--height-weight H counts the error's component along the skin's normal (its height,\n"
    "what shading and a surface distance see) H times as much as the components along the\n"
    "skin (default 1: plain per-vertex least squares; H > 1 trades sliding for shape).\n\n"
    "options:\n"
    "  --muscles A,B,...   solve only these muscles (the others stay 0)\n"
    "  --mirror            solve each NAME_L / NAME_R pair as one value\n"
    "  --name NAME         the expression's name (default: SHAPE's file name)\n"
    "  --posed MESH        also write the rig posed with the result (.obj or .glb)\n";

static std::string Stem(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t dot = name.find('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

int CmdSolve(const Args& args) {
  const ParsedArgs parsed = ParseArgs(
      args, {"target", "out", "muscles", "threshold", "outside-weight", "steps", "name", "posed",
             "height-weight"},
      {"mirror"});
  if (parsed.help) return std::fputs(kSolveUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("solve", parsed.error, kSolveUsage);
  if (parsed.positional.size() != 1)
    return UsageError("solve", parsed.positional.empty() ? "missing RIG" : "expected one RIG",
                      kSolveUsage);
  if (!parsed.Has("target")) return UsageError("solve", "missing --target SHAPE", kSolveUsage);
  if (!parsed.Has("out")) return UsageError("solve", "missing --out EXPRESSION.json", kSolveUsage);
  if (parsed.Has("posed")) {
    const std::string bad_ext = CheckOutputExtension("posed", parsed.Get("posed"), {".obj", ".glb"});
    if (!bad_ext.empty()) return UsageError("solve", bad_ext, kSolveUsage);
  }
  SolveOptions options;
  options.mirror = parsed.flags.count("mirror") > 0;
  double v = 0;
  if (parsed.Has("threshold")) {
    if (!ParseNumber(parsed.Get("threshold"), 0, 1e30, &v))
      return UsageError("solve", "--threshold '" + parsed.Get("threshold") +
                                     "': expected a distance >= 0 (mesh units)",
                        kSolveUsage);
    options.region_threshold = float(v);
  }
  if (parsed.Has("outside-weight")) {
    if (!ParseNumber(parsed.Get("outside-weight"), 0, 1, &v))
      return UsageError("solve", "--outside-weight '" + parsed.Get("outside-weight") +
                                     "': expected a number in [0, 1]",
                        kSolveUsage);
    options.outside_weight = float(v);
  }
  if (parsed.Has("height-weight")) {
    if (!ParseNumber(parsed.Get("height-weight"), 1e-6, 1e6, &v))
      return UsageError("solve", "--height-weight '" + parsed.Get("height-weight") +
                                     "': expected a number in [1e-6, 1e6]",
                        kSolveUsage);
    options.height_weight = v;
  }
  if (parsed.Has("steps")) {
    if (!ParseNumber(parsed.Get("steps"), 0, 100, &v) || v != std::floor(v))
      return UsageError("solve", "--steps '" + parsed.Get("steps") +
                                     "': expected a whole number in [0, 100]",
                        kSolveUsage);
    options.refine_steps = int(v);
  }

  const auto start = std::chrono::steady_clock::now();
  Diagnostics diag;
  LoadedRig loaded;
  if (!LoadRig(parsed.positional[0], &loaded, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  const Rig& rig = loaded.rig;
  const auto loaded_at = std::chrono::steady_clock::now();
  if (parsed.Has("muscles")) {
    std::stringstream list(parsed.Get("muscles"));
    std::string name;
    while (std::getline(list, name, ',')) {
      if (name.empty()) continue;
      const int m = rig.FindMuscle(name);
      if (m < 0) {
        std::string known;
        for (const std::string& n : rig.muscle_names()) known += (known.empty() ? "" : ", ") + n;
        std::fprintf(stderr, "mimetic solve: --muscles: unknown muscle '%s'; the rig has: %s\n",
                     name.c_str(), known.c_str());
        return 1;
      }
      options.muscles.push_back(uint32_t(m));
    }
    if (options.muscles.empty())
      return UsageError("solve", "--muscles: expected a comma-separated list of names", kSolveUsage);
  }
  MeshData target;
  Diagnostics local;
  const std::string target_path = parsed.Get("target");
  if (!ImportMesh(target_path, "", &target, &local)) {
    diag.Append(local, target_path);
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  SolveResult result;
  local.Clear();
  if (!SolveActivations(rig, loaded.mesh, target, options, &result, &local)) {
    diag.Append(local, target_path);
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  const auto solved_at = std::chrono::steady_clock::now();
  const double load_seconds = std::chrono::duration<double>(loaded_at - start).count();
  const double solve_seconds = std::chrono::duration<double>(solved_at - loaded_at).count();

  // How close the result is, by `mimetic compare`'s measures over the same region.
  MeshData posed = loaded.mesh;
  posed.positions = result.posed;
  CompareOptions co;
  co.neutral = &loaded.mesh;
  co.region.kind = CompareRegion::Kind::kMoved;
  co.region.threshold = result.region_threshold;
  CompareResult cmp;
  local.Clear();
  if (!CompareMeshes(posed, target, co, &cmp, &local)) {
    diag.Append(local, target_path);
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }

  Expression e;
  e.name = parsed.Has("name") ? parsed.Get("name") : Stem(target_path);
  for (uint32_t m = 0; m < rig.muscle_count(); ++m)
    e.activations.push_back({rig.muscle_names()[m], result.activations[m]});
  e.solve_strings = {{"rig", parsed.positional[0]}, {"target", target_path}};
  e.solve_numbers = {{"region_threshold", result.region_threshold},
                     {"region_vertices", result.region_count},
                     {"residual", result.residual},
                     {"neutral_residual", result.neutral_residual},
                     {"mean_distance", cmp.b_to_a.mean},
                     {"max_distance", cmp.b_to_a.max},
                     {"neutral_mean_distance", cmp.b_to_neutral.mean},
                     {"ratio", cmp.ratio},
                     {"direction_cosine", cmp.direction_cosine},
                     {"magnitude_ratio", cmp.magnitude_ratio}};
  if (!SaveExpression(parsed.Get("out"), e, &diag)) {
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  if (parsed.Has("posed")) {
    MeshData full;  // the whole output layout, refined vertices too
    if (!PosedMesh(rig, result.activations, {}, &full)) {
      std::fputs("mimetic solve: evaluation failed (internal error: job did not validate)\n", stderr);
      return 1;
    }
    if (!ExportMesh(parsed.Get("posed"), full, &diag)) {
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
  }

  std::printf("solved %s for %s: %u unknowns%s, %u target vertices in the region (moved > %g)\n",
              parsed.positional[0].c_str(), target_path.c_str(), result.unknowns,
              options.mirror ? " (L/R tied)" : "", result.region_count,
              double(result.region_threshold));
  std::vector<uint32_t> order(rig.muscle_count());
  for (uint32_t m = 0; m < rig.muscle_count(); ++m) order[m] = m;
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return result.activations[a] > result.activations[b];
  });
  for (uint32_t m : order)
    if (result.activations[m] > 0.f)
      std::printf("  %-28s %.4f\n", rig.muscle_names()[m].c_str(), double(result.activations[m]));
  std::printf("residual:   %.6g (neutral %.6g; linear solve %.6g, then %d of %d refinement "
              "steps helped)\n",
              result.residual, result.neutral_residual, result.linear_residual,
              result.refine_steps_taken, options.refine_steps);
  std::printf("distance:   mean %.6g, max %.6g (neutral: mean %.6g, max %.6g); ratio %.4g\n",
              cmp.b_to_a.mean, cmp.b_to_a.max, cmp.b_to_neutral.mean, cmp.b_to_neutral.max,
              cmp.ratio);
  std::printf("motion:     cosine %.4f, magnitude %.4f\n", cmp.direction_cosine,
              cmp.magnitude_ratio);
  std::printf("wrote %s (rig loaded in %.2f s, target read and solved in %.2f s)\n",
              parsed.Get("out").c_str(), load_seconds, solve_seconds);
  return 0;
}

}  // namespace mimetic::tools
