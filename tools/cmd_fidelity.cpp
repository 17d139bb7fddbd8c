// tools/cmd_fidelity.cpp: `mimetic fidelity`, the reproducible fidelity report: fit the muscle
// template to ICT-FaceKit's neutral, solve every real expression shape the rig claims it can
// make (fitting/solve.h), measure it (fitting/compare.h) with every skin layer and with the
// muscles alone, render real | rig | distance, and write docs/fidelity.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/file_util.h"
#include "fitting/compare.h"
#include "fitting/creases.h"
#include "fitting/fit.h"
#include "fitting/solve.h"
#include "geometry/mesh.h"
#include "io/image.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/template_file.h"
#include "rig/offline/rig_builder.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/ict_shapes.h"
#include "tools/render/close_up.h"
#include "tools/render/heat_map.h"

namespace mimetic::tools {
namespace {

const char* kFidelityUsage =
    "usage: mimetic fidelity [--data DIR] [--template FILE] [--landmarks FILE]\n"
    "                        [--report FILE.md] [--images DIR] [--only A,B,...] [--meshes DIR]\n"
    "                        [--size N]\n\n"
    "The fidelity report: fits the muscle template (default assets/head/default.template.json)\n"
    "to ICT-FaceKit's neutral head (DIR/ict-facekit/ict_skin_neutral.obj, DIR default\n"
    "../shared/data; landmarks default tests/data/landmarks/ict_facekit.landmarks.json), then\n"
    "for every real expression shape the rig claims it can make solves the activations\n"
    "(`mimetic solve`, every skin layer on, and again with the muscles alone) and measures the\n"
    "result (`mimetic compare`, over the vertices the real shape moves more than 2% of its\n"
    "largest motion), and solves once more with the muscles alone and no bounds on the\n"
    "activations (what any activations of these muscles could make). Writes the table, where\n"
    "each shape's residual lies (along the skin's normal, by part of the face), why each\n"
    "missed target is missed (the muscles' reach, the bounds [0, 1] or the skin layers) and\n"
    "what would make it, what each skin layer adds to the ratio at the solved activations,\n"
    "the targets met when the solve weighs height more (--height-weight\n"
    "4 and 16 of `mimetic solve`), and the rig's crease numbers with Waters' and with smooth fall-offs\n"
    "to --report (default docs/fidelity.md) and one picture per shape, real | rig | distance\n"
    "(blue 0, red = half the shape's largest motion), to --images (default\n"
    "docs/images/fidelity), N pixels a panel (--size, default 240).\n"
    "--only solves just the named shapes (the report then lists only them); --meshes writes\n"
    "each posed rig (the input mesh's vertices) as DIR/SHAPE.obj, the muscles alone as\n"
    "DIR/SHAPE.muscles.obj and their unbounded optima as DIR/SHAPE.reach.obj (the whole\n"
    "motion) and DIR/SHAPE.height.obj (its height), and the every-layer activations posed\n"
    "with a layer off as DIR/SHAPE.no_thickness.obj, .no_muscle_wrinkles.obj,\n"
    ".no_curve_wrinkles.obj and .no_layers.obj. Run from the repository root.\n";

struct Row {
  const IctShape* shape = nullptr;
  CompareResult on, off;     // every skin layer / muscles alone
  ResidualSplit split;       // where the residual lies, every skin layer
  std::string top_muscles;   // the largest activations, layers on
  // The muscles alone with any activations (SolveOptions::reach): the measures, where what is
  // left lies, and the unbounded activations.
  CompareResult reach, height;  // the unbounded optimum of the whole motion / of its height
  ResidualSplit reach_split, height_split;
  // Every layer, solved with the height weighted (kHeightWeights; SolveOptions::height_weight).
  std::vector<CompareResult> weighted;
  SolveReach reach_solve;
  // At the every-layer solve's activations: the measures with one skin layer off at a time
  // (kLayerCases: thickness, muscle wrinkles, curve wrinkles) and with all three off.
  std::vector<float> on_activations;
  float on_threshold = 0.f;
  CompareResult without[4];
  double solve_seconds = 0;
  std::string image;         // relative to the report
};

// The layer cases of Row::without, and their file suffixes under --meshes.
constexpr SkinLayers kLayerCases[4] = {
    {false, true, true}, {true, false, true}, {true, true, false}, {false, false, false}};
constexpr const char* kLayerSuffix[4] = {".no_thickness.obj", ".no_muscle_wrinkles.obj",
                                         ".no_curve_wrinkles.obj", ".no_layers.obj"};

int Fail(const Diagnostics& diag, const std::string& what) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
  std::fprintf(stderr, "mimetic fidelity: %s\n", what.c_str());
  return 1;
}

std::string Fixed(double v, int digits) {
  if (!std::isfinite(v)) return "inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// A difference to 3 decimals with its sign: "+0.012", "-0.004", and "0.000" when it rounds to
// zero either way.
std::string Signed3(double v) {
  const std::string s = Fixed(v, 3);
  if (s == "-0.000" || s == "0.000") return "0.000";
  return (v > 0 ? "+" : "") + s;
}

// Parts of the face for the residual's split: each vertex takes the part of its nearest iBUG
// landmark.
constexpr const char* kParts[] = {"jaw line and cheeks", "brows and forehead", "nose", "eyes",
                                  "mouth"};
constexpr uint32_t kPartCount = 5;
uint8_t PartOfLandmark(size_t i) {
  return i < 17 ? 0 : i < 27 ? 1 : i < 36 ? 2 : i < 48 ? 3 : 4;
}
std::vector<uint8_t> FaceParts(const MeshData& mesh, const std::vector<float3>& landmarks) {
  std::vector<uint8_t> parts(mesh.vertex_count(), 0);
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    float best = -1.f;
    for (size_t i = 0; i < landmarks.size(); ++i) {
      const float3 d = mesh.positions[v] - landmarks[i];
      const float dd = Dot(d, d);
      if (best < 0.f || dd < best) best = dd, parts[v] = PartOfLandmark(i);
    }
  }
  return parts;
}

// The solve's objective traded toward height: the weights the report also solves with.
constexpr double kHeightWeights[] = {4.0, 16.0};

// The targets (docs/fidelity.md's legend) and, for one missed, what misses it first: the
// skin layers when the muscles alone (bounded) meet it, the bounds [0, 1] when the muscles
// with any activations meet it, else the muscles' reach (no activation makes it).
bool RatioMet(const CompareResult& c) { return c.ratio <= 0.5; }
bool CosineMet(const CompareResult& c) { return c.direction_cosine >= 0.8; }
bool MagnitudeMet(const CompareResult& c) { return std::fabs(c.magnitude_ratio - 1.0) <= 0.25; }
bool AllMet(const CompareResult& c) { return RatioMet(c) && CosineMet(c) && MagnitudeMet(c); }
enum class Cause { kMet, kLayers, kBounds, kReach };
Cause CauseOf(bool (*met)(const CompareResult&), const CompareResult& on, const CompareResult& off,
              const CompareResult& reach, const CompareResult& height) {
  return met(on) ? Cause::kMet : met(off) ? Cause::kLayers
                             : met(reach) || met(height) ? Cause::kBounds : Cause::kReach;
}

// The muscles whose unbounded activation lies beyond [0, 1] by more than 0.05, the farthest
// first (at most three): "name value, ...".
std::string BeyondBounds(const Rig& rig, const std::vector<float>& a, bool above) {
  std::vector<uint32_t> order;
  for (uint32_t m = 0; m < a.size(); ++m)
    if (above ? a[m] > 1.05f : a[m] < -0.05f) order.push_back(m);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t x, uint32_t y) { return above ? a[x] > a[y] : a[x] < a[y]; });
  std::string out;
  for (size_t i = 0; i < order.size() && i < 3; ++i)
    out += (i ? ", " : "") + rig.muscle_names()[order[i]] + " " + Fixed(a[order[i]], 2);
  return out.empty() ? "-" : out;
}

uint32_t LargestPart(const ResidualSplit& split) {
  uint32_t best = 0;
  for (uint32_t k = 1; k < split.part_share.size(); ++k)
    if (split.part_share[k] > split.part_share[best]) best = k;
  return best;
}

// Relative path from directory `from` to `to` (both as given, made absolute).
std::string Relative(const std::string& to, const std::string& from) {
  std::error_code ec;
  const auto rel = std::filesystem::relative(std::filesystem::absolute(to),
                                             std::filesystem::absolute(from), ec);
  return ec ? to : rel.string();
}

}  // namespace

int CmdFidelity(const Args& args) {
  const ParsedArgs parsed = ParseArgs(
      args, {"data", "template", "landmarks", "report", "images", "only", "meshes", "size"}, {});
  if (parsed.help) return std::fputs(kFidelityUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("fidelity", parsed.error, kFidelityUsage);
  if (!parsed.positional.empty())
    return UsageError("fidelity", "takes no positional arguments", kFidelityUsage);
  const std::string data = parsed.Get("data", "../shared/data");
  const std::string template_path = parsed.Get("template", "assets/head/default.template.json");
  const std::string landmarks_path =
      parsed.Get("landmarks", "tests/data/landmarks/ict_facekit.landmarks.json");
  const std::string report_path = parsed.Get("report", "docs/fidelity.md");
  const std::string images_dir = parsed.Get("images", "docs/images/fidelity");
  const std::string meshes_dir = parsed.Get("meshes");
  int size = 240;
  if (parsed.Has("size")) {
    double v = 0;
    if (!ParseNumber(parsed.Get("size"), 64, 2048, &v) || v != double(int(v)))
      return UsageError("fidelity", "--size '" + parsed.Get("size") +
                                        "': expected a whole number of pixels in [64, 2048]",
                        kFidelityUsage);
    size = int(v);
  }
  std::vector<const IctShape*> shapes;
  if (parsed.Has("only")) {
    std::stringstream list(parsed.Get("only"));
    std::string name;
    while (std::getline(list, name, ',')) {
      const IctShape* found = nullptr;
      for (const IctShape& s : IctShapes())
        if (name == s.name) found = &s;
      if (!found) {
        std::string known;
        for (const IctShape& s : IctShapes()) known += (known.empty() ? "" : ", ") + std::string(s.name);
        return UsageError("fidelity", "--only: unknown shape '" + name + "'; known: " + known,
                          kFidelityUsage);
      }
      shapes.push_back(found);
    }
  } else {
    for (const IctShape& s : IctShapes()) shapes.push_back(&s);
  }

  // The rig: the template fitted to the ICT neutral.
  Diagnostics diag, local;
  IctRig ict;
  std::string what;
  if (!FitIctRig(data, template_path, landmarks_path, &ict, &diag, &what)) return Fail(diag, what);
  const MeshData& neutral = ict.neutral;
  const std::string& neutral_path = ict.neutral_path;
  const std::string& units = ict.units;
  const Rig& rig = ict.rig;
  std::printf("fidelity: %s fitted to %s (%u muscles, %u output vertices) in %.1f s\n",
              template_path.c_str(), neutral_path.c_str(), rig.muscle_count(), rig.vertex_count(),
              ict.seconds);

  const std::vector<uint8_t> parts = FaceParts(neutral, ict.landmarks);

  std::error_code ec;
  std::filesystem::create_directories(images_dir, ec);
  if (!meshes_dir.empty()) std::filesystem::create_directories(meshes_dir, ec);
  const std::string report_dir = std::filesystem::path(report_path).parent_path().string();
  std::vector<Row> rows;
  std::vector<const IctShape*> not_claimed, missing;
  size_t done = 0;
  const size_t claimed_count = size_t(std::count_if(shapes.begin(), shapes.end(),
                                                    [](const IctShape* s) { return !s->why_not; }));
  for (const IctShape* shape : shapes) {
    if (shape->why_not) {
      not_claimed.push_back(shape);
      continue;
    }
    const std::string path = data + "/" + shape->file;
    MeshData target;
    local.Clear();
    if (!ImportMesh(path, "", &target, &local)) {
      missing.push_back(shape);
      continue;
    }
    Row row;
    row.shape = shape;
    const auto t0 = std::chrono::steady_clock::now();
    MeshData posed[2] = {neutral, neutral}, reach_mesh = neutral, height_mesh = neutral;
    // The measured region: the vertices the real shape moves more than the solve's threshold.
    auto MovedRegion = [&](float threshold) {
      CompareOptions co;
      co.neutral = &neutral;
      co.region.kind = CompareRegion::Kind::kMoved;
      co.region.threshold = threshold;
      return co;
    };
    for (int layers = 1; layers >= 0; --layers) {
      SolveOptions options;
      options.skin_layers = layers == 1;
      options.reach = layers == 0;
      SolveResult result;
      local.Clear();
      if (!SolveActivations(rig, neutral, target, options, &result, &local)) {
        diag.Append(local, path);
        return Fail(diag, std::string("cannot solve ") + shape->name);
      }
      posed[layers].positions = result.posed;
      CompareOptions co = MovedRegion(result.region_threshold);
      local.Clear();
      if (!CompareMeshes(posed[layers], target, co, layers ? &row.on : &row.off, &local)) {
        diag.Append(local, path);
        return Fail(diag, std::string("cannot measure ") + shape->name);
      }
      if (!layers) {
        // What any activations of these muscles could make (no bounds, muscles alone).
        row.reach_solve = std::move(result.reach);
        reach_mesh.positions = row.reach_solve.posed;
        height_mesh.positions = row.reach_solve.height_posed;
        local.Clear();
        if (!CompareMeshes(reach_mesh, target, co, &row.reach, &local) ||
            !CompareMeshes(height_mesh, target, co, &row.height, &local) ||
            !SplitResidual(height_mesh, target, neutral, row.height.in_region,
                           row.height.b_distance, parts, kPartCount, &row.height_split, &local) ||
            !SplitResidual(reach_mesh, target, neutral, row.reach.in_region, row.reach.b_distance,
                           parts, kPartCount, &row.reach_split, &local)) {
          diag.Append(local, path);
          return Fail(diag, std::string("cannot measure the muscles' reach for ") + shape->name);
        }
      }
      if (layers) {
        row.on_activations = result.activations;
        row.on_threshold = result.region_threshold;
        local.Clear();
        if (!SplitResidual(posed[1], target, neutral, row.on.in_region, row.on.b_distance,
                           parts, kPartCount, &row.split, &local)) {
          diag.Append(local, path);
          return Fail(diag, std::string("cannot split the residual of ") + shape->name);
        }
        std::vector<uint32_t> order(rig.muscle_count());
        for (uint32_t m = 0; m < rig.muscle_count(); ++m) order[m] = m;
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
          return result.activations[a] > result.activations[b];
        });
        for (size_t i = 0; i < 3 && i < order.size() && result.activations[order[i]] >= 0.05f; ++i)
          row.top_muscles += (i ? ", " : "") + rig.muscle_names()[order[i]] + " " +
                             Fixed(result.activations[order[i]], 2);
      }
    }
    // The same solve (every layer) with the height weighted more.
    for (double hw : kHeightWeights) {
      SolveOptions options;
      options.height_weight = hw;
      SolveResult result;
      CompareResult measured;
      MeshData weighted_mesh = neutral;
      local.Clear();
      if (!SolveActivations(rig, neutral, target, options, &result, &local)) {
        diag.Append(local, path);
        return Fail(diag, std::string("cannot solve ") + shape->name + " with the height weighted");
      }
      weighted_mesh.positions = result.posed;
      if (!CompareMeshes(weighted_mesh, target, MovedRegion(result.region_threshold), &measured,
                         &local)) {
        diag.Append(local, path);
        return Fail(diag, std::string("cannot measure ") + shape->name);
      }
      row.weighted.push_back(std::move(measured));
    }
    // What each skin layer adds: the every-layer solve's activations with the layers off.
    MeshData ablated[4] = {neutral, neutral, neutral, neutral};
    for (int k = 0; k < 4; ++k) {
      MeshData m;
      local.Clear();
      if (!PosedMesh(rig, row.on_activations, kLayerCases[k], &m) ||
          m.vertex_count() < neutral.vertex_count()) {
        diag.Append(local, path);
        return Fail(diag, std::string("cannot pose ") + shape->name + " with the layers off");
      }
      ablated[k].positions.assign(m.positions.begin(),
                                  m.positions.begin() + std::ptrdiff_t(neutral.vertex_count()));
      if (!CompareMeshes(ablated[k], target, MovedRegion(row.on_threshold), &row.without[k],
                         &local)) {
        diag.Append(local, path);
        return Fail(diag, std::string("cannot measure ") + shape->name + " with the layers off");
      }
    }
    row.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!meshes_dir.empty()) {
      auto write = [&](const MeshData& mesh, const char* suffix) {
        MeshData out = mesh;
        out.normals.clear();
        return ExportMesh(meshes_dir + "/" + shape->name + suffix, out, &local);
      };
      local.Clear();
      bool ok = write(posed[1], ".obj") && write(posed[0], ".muscles.obj") &&
                write(reach_mesh, ".reach.obj") && write(height_mesh, ".height.obj");
      for (int k = 0; k < 4 && ok; ++k) ok = write(ablated[k], kLayerSuffix[k]);
      if (!ok) {
        diag.Append(local);
        return Fail(diag, "cannot write the posed mesh");
      }
    }
    // real | rig | distance of the real shape to the rig's surface.
    RenderOptions ro;
    ro.supersample = 2;
    MeshData real = target, rig_mesh = posed[1];
    real.normals.clear();
    rig_mesh.normals.clear();
    const double zoom = 2.5, fx = 0.5, fy = 0.44;  // the face of the ICT head and shoulders
    double largest = 0.0;
    for (size_t v = 0; v < target.vertex_count(); ++v)
      largest = std::max(largest, double(Length(target.positions[v] - neutral.positions[v])));
    const std::vector<float3> colors =
        HeatColors(row.on.b_distance, float(0.5 * largest), &row.on.in_region);
    RenderOptions heat = ro;
    heat.vertex_colors = &colors;
    Image panels = SideBySide({RenderCloseUp(real, ro, size, zoom, fx, fy),
                               RenderCloseUp(rig_mesh, ro, size, zoom, fx, fy),
                               RenderCloseUp(real, heat, size, zoom, fx, fy)},
                              4, {1.f, 1.f, 1.f});
    std::string file = shape->name;
    for (char& c : file)
      if (c == ' ' || c == '(' || c == ')' || c == '+') c = '_';
    const std::string image_path = images_dir + "/" + file + ".png";
    local.Clear();
    if (!SavePng(image_path, panels, &local)) {
      diag.Append(local);
      return Fail(diag, "cannot write the picture");
    }
    row.image = Relative(image_path, report_dir.empty() ? "." : report_dir);
    ++done;
    std::printf("  [%zu/%zu] %-18s ratio %s (muscles alone %s, any activations %s), cosine %s, "
                "magnitude %s  %.1f s\n",
                done, claimed_count, shape->name, Fixed(row.on.ratio, 3).c_str(),
                Fixed(row.off.ratio, 3).c_str(), Fixed(row.reach.ratio, 3).c_str(),
                Fixed(row.on.direction_cosine, 2).c_str(), Fixed(row.on.magnitude_ratio, 2).c_str(),
                row.solve_seconds);
    std::fflush(stdout);
    rows.push_back(std::move(row));
  }

  // Where the residual is (every layer): along the normal, and by part of the face.
  std::string where =
      "## Where the residual is\n\n"
      "Over the measured region, every layer on (`fitting/compare.h` `SplitResidual`): "
      "**largest parts**, the share of the ratio's numerator (the real shape's distance to the "
      "rig's surface) that each part of the face holds, a vertex taking the part of its nearest "
      "landmark (iBUG 68: jaw line and cheeks 0-16, brows and forehead 17-26, nose 27-35, eyes "
      "36-47, mouth 48-67); **height share**, of the per-vertex error r = rig - real, the share "
      "of the sum of |r|^2 along the neutral's normals (1: the skin is only too high or too "
      "deep; near 0: it mostly slides to the wrong place within the surface, which the ratio "
      "does not see).\n\n| shape | ratio | largest parts | height share |\n|---|---|---|---|\n";
  for (const Row& r : rows) {
    std::vector<uint32_t> order(kPartCount);
    for (uint32_t k = 0; k < kPartCount; ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      return r.split.part_share[a] > r.split.part_share[b];
    });
    std::string largest;
    for (size_t i = 0; i < 2 && r.split.part_share[order[i]] >= 0.05; ++i)
      largest += (i ? ", " : "") + std::string(kParts[order[i]]) + " " +
                 Fixed(r.split.part_share[order[i]], 2);
    where += "| " + std::string(r.shape->name) + " | " + Fixed(r.on.ratio, 3) + " | " + largest +
             " | " + Fixed(r.split.normal_share, 2) + " |\n";
  }
  where += "\n";

  // Why each missed target is missed (the muscles' reach, the bounds, the skin layers) and
  // what would make it.
  std::string why =
      "## Why a target is missed, and what would make it\n\n"
      "Each missed target is put down to the first of three things that misses it, from three "
      "solves of the same shape: **the skin layers** when the muscles alone (activations in "
      "[0, 1], the **off** column) meet it; **the bounds** when the muscles alone with any "
      "activations, negative and above 1 included, meet it (either of two linear least-squares "
      "optima on the muscle basis without bounds, `SolveOptions::reach`, docs/model.md §13: of "
      "the whole per-vertex motion, and of its height alone, the part along the skin's normal "
      "that the ratio's surface distance sees); else **out of reach**: no activation of these "
      "muscles makes that motion, and only a muscle that moves the skin there (or a new "
      "placement) would. Columns: **any activations** / **height first**, ratio / cosine / "
      "magnitude of the two unbounded optima; **out of reach**, the share of the real motion (its weighted sum of squares over the solve's weights) that the unbounded "
      "optimum leaves; **bounds' cost**, the share the bounds [0, 1] add to it; **wants above "
      "1** / **below 0**, the unbounded activations outside [0, 1] (of the height-first optimum "
      "when only it meets a target; above 1: a stronger muscle; "
      "below 0: a push against that muscle's pull, which a muscle cannot make); **where**, the "
      "largest part of the face in the unbounded optimum's surface distance and the height "
      "share of its per-vertex error (as in the previous section; low: the missing motion "
      "slides along the skin).\n\n"
      "| shape | missed: by | any activations | height first | out of reach | bounds' cost | "
      "wants above 1 | wants below 0 | where | what would make it |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  size_t causes[4] = {0, 0, 0, 0};  // by Cause
  for (const Row& r : rows) {
    struct Target { const char* name; bool (*met)(const CompareResult&); };
    const Target targets[] = {{"ratio", RatioMet}, {"cosine", CosineMet}, {"magnitude", MagnitudeMet}};
    std::string missed, make;
    bool ratio_reach = false, motion_reach = false, needs_bounds = false, by_height = false;
    for (const Target& t : targets) {
      const Cause c = CauseOf(t.met, r.on, r.off, r.reach, r.height);
      ++causes[int(c)];
      if (c == Cause::kMet) continue;
      by_height |= c == Cause::kBounds && !t.met(r.reach);
      missed += std::string(missed.empty() ? "" : "; ") + t.name + ": " +
                (c == Cause::kLayers ? "the skin layers" : c == Cause::kBounds ? "the bounds"
                                                                                : "out of reach");
      (t.met == RatioMet ? ratio_reach : motion_reach) |= c == Cause::kReach;
      needs_bounds |= c == Cause::kBounds;
    }
    const bool layers_worse = r.on.ratio > r.off.ratio + 1e-9;
    if (layers_worse) {
      missed += std::string(missed.empty() ? "" : "; ") + "layers: the skin layers";
      ++causes[int(Cause::kLayers)];
    }
    if (missed.empty()) continue;
    // The activations beyond [0, 1] of the optimum that meets a target the bounds miss (the
    // height-first one when only it does).
    const std::vector<float>& wants =
        by_height ? r.reach_solve.height_activations : r.reach_solve.activations;
    const std::string above = BeyondBounds(rig, wants, true), below = BeyondBounds(rig, wants, false);
    const uint32_t part = LargestPart(r.reach_split);
    // The ratio sees height: where the height-first optimum's surface distance lies; the
    // cosine and magnitude see the whole motion: where the other optimum's error lies.
    const uint32_t height_part = LargestPart(r.height_split);
    if (ratio_reach && motion_reach && height_part == part)
      make += std::string("a muscle (or placement) that moves the ") + kParts[part] +
              ", in height and along the skin, as the real shape does";
    else if (ratio_reach)
      make += std::string("a muscle (or placement) that lifts or sinks the ") +
              kParts[height_part] + " as the real shape does";
    if (motion_reach && !(ratio_reach && height_part == part))
      make += std::string(make.empty() ? "" : "; ") + "a muscle (or placement) that moves the " +
              kParts[part] + (r.reach_split.normal_share < 0.5 ? " along the skin" : " in height") +
              " as the real shape does";
    if (needs_bounds) {
      if (above != "-") make += std::string(make.empty() ? "" : "; ") + "stronger muscles (" + above + ")";
      if (below != "-") make += std::string(make.empty() ? "" : "; ") + "an antagonist of " + below;
    }
    if (layers_worse)
      make += std::string(make.empty() ? "" : "; ") + "skin layers that do not add " +
              Fixed(r.on.ratio - r.off.ratio, 3) + " to the ratio";
    const double motion = r.reach_solve.motion > 0 ? r.reach_solve.motion : 1.0;
    why += "| " + std::string(r.shape->name) + " | " + missed + " | " + Fixed(r.reach.ratio, 3) +
           " / " + Fixed(r.reach.direction_cosine, 2) + " / " + Fixed(r.reach.magnitude_ratio, 2) +
           " | " + Fixed(r.height.ratio, 3) + " / " + Fixed(r.height.direction_cosine, 2) + " / " +
           Fixed(r.height.magnitude_ratio, 2) +
           " | " + Fixed(r.reach_solve.residual / motion, 2) + " | " +
           Fixed((r.reach_solve.bounded_residual - r.reach_solve.residual) / motion, 2) + " | " +
           above + " | " + below + " | " + kParts[part] + ", height " +
           Fixed(r.reach_split.normal_share, 2) + " | " + make + " |\n";
  }
  why += "\nMissed targets by what misses them first (ratio, cosine and magnitude of every shape, "
         "and the layers' target): out of reach " + std::to_string(causes[int(Cause::kReach)]) +
         ", the bounds " + std::to_string(causes[int(Cause::kBounds)]) + ", the skin layers " +
         std::to_string(causes[int(Cause::kLayers)]) + ".\n\n";

  // What each skin layer costs, at the every-layer solve's activations.
  std::string costs =
      "## What each skin layer costs\n\n"
      "The every-layer solve's activations posed again with one skin layer off at a time and "
      "with all three off (the same activations: not a new solve; the first table's **off** "
      "is the muscles alone solved on their own). A layer whose removal lowers the ratio moves "
      "the skin where the real shape does not: a fold, bulge or furrow the real shape lacks or "
      "places elsewhere. **adds**: every layer's ratio minus the ratio without that layer.\n\n"
      "| shape | every layer | no thickness (adds) | no muscle wrinkles (adds) | no curve "
      "wrinkles (adds) | none (adds) | off (solved) |\n|---|---|---|---|---|---|---|\n";
  double added[4] = {0, 0, 0, 0};
  size_t worse = 0;
  std::string worse_names;  // "SHAPE by D" of each, D to 4 decimals
  for (const Row& r : rows) {
    costs += "| " + std::string(r.shape->name) + " | " + Fixed(r.on.ratio, 3);
    for (int k = 0; k < 4; ++k) {
      const double add = r.on.ratio - r.without[k].ratio;
      added[k] += add;
      costs += " | " + Fixed(r.without[k].ratio, 3) + " (" + Signed3(add) + ")";
    }
    costs += " | " + Fixed(r.off.ratio, 3) + " |\n";
    if (r.on.ratio > r.off.ratio + 1e-9) {
      ++worse;
      worse_names += std::string(worse_names.empty() ? "" : ", ") + r.shape->name + " by " +
                     Fixed(r.on.ratio - r.off.ratio, 4);
    }
  }
  if (!rows.empty()) {
    costs += "\nMean over the " + std::to_string(rows.size()) + " shapes, what each layer adds "
             "to the ratio: thickness " + Signed3(added[0] / double(rows.size())) +
             ", muscle wrinkles " + Signed3(added[1] / double(rows.size())) +
             ", curve wrinkles " + Signed3(added[2] / double(rows.size())) + ", all three " +
             Signed3(added[3] / double(rows.size())) + "; the layers make the solved ratio "
             "worse than the muscles alone on " + std::to_string(worse) +
             (worse_names.empty() ? std::string() : " (" + worse_names + ")") + ".\n\n";
  }

  // Creases of the fall-offs on this rig (docs/model.md §2-3): every muscle Waters', then smooth.
  std::string creases;
  {
    CreaseReport report[2];
    for (int k = 0; k < 2; ++k) {
      const MuscleFalloff kind = k == 0 ? MuscleFalloff::kWaters : MuscleFalloff::kSmooth;
      // The fitted rig itself when every muscle already has that fall-off (the default
      // template's are all smooth): no second build.
      const bool as_fitted = std::all_of(ict.spec.muscles.begin(), ict.spec.muscles.end(),
                                         [&](const MuscleSpec& m) { return m.falloff == kind; });
      Rig built;
      local.Clear();
      if (!as_fitted && !BuildRigWithFalloff(ict.spec, neutral, kind, &built, &local)) {
        diag.Append(local, template_path);
        return Fail(diag, "cannot build the rig for the crease numbers");
      }
      report[k] = MeasureCreases(as_fitted ? rig : built);
    }
    auto name = [&](const CreaseReport& c) {
      return rig.muscle_count() ? rig.muscle_names()[c.worst_muscle] : std::string("none");
    };
    const double ratio = report[0].max_degrees > 0.f
                             ? double(report[1].max_degrees) / double(report[0].max_degrees)
                             : 0.0;
    creases = "## Creases of the fall-offs\n\nThe crease number (docs/model.md §2-3, "
              "`mimetic creases`; each muscle alone at 1, slivers left out) of this rig with "
              "every muscle on Waters' fall-offs: " + Fixed(report[0].max_degrees, 1) +
              " degrees (" + name(report[0]) + "); on the smooth ones: " +
              Fixed(report[1].max_degrees, 1) + " degrees (" + name(report[1]) +
              "); smooth / Waters' = **" + Fixed(ratio, 2) + "** (target: at most 1/3; " +
              (ratio <= 1.0 / 3.0 ? "met" : "not met") +
              "). Why, and the sample head's numbers: docs/calibration.md.\n\n";
    std::printf("creases: Waters %.1f (%s), smooth %.1f (%s), ratio %.2f\n",
                report[0].max_degrees, name(report[0]).c_str(), report[1].max_degrees,
                name(report[1]).c_str(), ratio);
  }

  // The report.
  std::string md;
  md += "# Fidelity: the rig against real expression shapes\n\n";
  md += "Made by `./build/mimetic fidelity` (run from the repository root with ICT-FaceKit in "
        "`../shared/data`; `--help` lists the options). Do not edit by hand: rerun it.\n\n";
  md += "The default template (`" + template_path + "`) is fitted to ICT-FaceKit's neutral head "
        "(" + std::to_string(neutral.vertex_count()) + " vertices, " + units + "; " +
        std::to_string(rig.muscle_count()) + " muscles). For each real shape, `mimetic solve` "
        "finds the activations in [0, 1] closest to it, once with every skin layer on and once "
        "with the muscles alone, and `mimetic compare` measures the result over the vertices "
        "the real shape moves more than 2% of its largest motion (docs/model.md §13):\n\n";
  md += "- **rig** / **neutral**: mean distance from those vertices of the real shape to the "
        "rig's surface / to the neutral's (" + units + ");\n"
        "- **ratio** = rig / neutral (target: at most 0.5); **off**: the same with the skin "
        "layers off (the layers must never make it worse);\n"
        "- **cosine**: displacement-weighted direction cosine of the rig's motion against the "
        "real one (target: at least 0.8); **magnitude**: the rig's motion over the real one "
        "(target: 0.75 to 1.25).\n\n";
  // Per set (the calibration's training shapes and the held-out rest): how many meet each target.
  struct Count { size_t shapes = 0, ratio = 0, cosine = 0, magnitude = 0, all = 0, layers = 0; };
  Count sets[2];  // 0 = trained, 1 = held out
  md += "| shape | set | rig | neutral | ratio | off | cosine | magnitude | largest activations |\n";
  md += "|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    const bool ratio_ok = RatioMet(r.on), cosine_ok = CosineMet(r.on),
               magnitude_ok = MagnitudeMet(r.on);
    Count& c = sets[r.shape->trained ? 0 : 1];
    ++c.shapes;
    c.ratio += ratio_ok;
    c.cosine += cosine_ok;
    c.magnitude += magnitude_ok;
    c.all += AllMet(r.on);
    c.layers += r.on.ratio <= r.off.ratio + 1e-9;
    md += "| " + std::string(r.shape->name) + " | " + (r.shape->trained ? "train" : "held out") +
          " | " + Fixed(r.on.b_to_a.mean, 3) + " | " +
          Fixed(r.on.b_to_neutral.mean, 3) + " | " + Fixed(r.on.ratio, 3) + " | " +
          Fixed(r.off.ratio, 3) + " | " + Fixed(r.on.direction_cosine, 2) + " | " +
          Fixed(r.on.magnitude_ratio, 2) + " | " + r.top_muscles + " |\n";
  }
  const size_t met = sets[0].all + sets[1].all;
  md += "\nTargets met (shapes of the set):\n\n| set | shapes | ratio <= 0.5 | cosine >= 0.8 | "
        "magnitude 0.75-1.25 | all three | layers keep or improve the ratio |\n"
        "|---|---|---|---|---|---|---|\n";
  for (int k = 0; k < 2; ++k) {
    const Count& c = sets[k];
    if (c.shapes == 0) continue;
    md += std::string("| ") + (k == 0 ? "train" : "held out") + " | " + std::to_string(c.shapes) +
          " | " + std::to_string(c.ratio) + " | " + std::to_string(c.cosine) + " | " +
          std::to_string(c.magnitude) + " | " + std::to_string(c.all) + " | " +
          std::to_string(c.layers) + " |\n";
  }
  md += "\n\"train\" marks the shapes `mimetic calibrate` fitted the default template on; the "
        "others it never saw. Where the residual is and why each missed target is missed: the "
        "sections of those names below; the calibration's own account: docs/calibration.md. The jaw (not a muscle; calibrated on "
        "ICT's jawOpen, its figures and renders): docs/jaw.md.\n\n";
  if (!not_claimed.empty()) {
    md += "## Shapes the rig does not claim\n\n| shape | why |\n|---|---|\n";
    for (const IctShape* s : not_claimed) md += "| " + std::string(s->name) + " | " + s->why_not + " |\n";
    md += "\n";
  }
  if (!missing.empty()) {
    md += "Not in the data set here: ";
    for (size_t i = 0; i < missing.size(); ++i) md += (i ? ", " : "") + std::string(missing[i]->name);
    md += ".\n\n";
  }
  // The objective's trade: targets met when the solve weighs height more.
  std::string trade =
      "## The solve's objective\n\n"
      "The solves above minimise the per-vertex error, which counts sliding along the skin as "
      "much as height; the ratio sees almost only height. Solved again with the error's "
      "component along the skin's normal counted H times (`mimetic solve --height-weight H`, "
      "docs/model.md §13), every layer on, the same shapes:\n\n"
      "| height weight H | mean ratio | ratio <= 0.5 | cosine >= 0.8 | magnitude 0.75-1.25 | "
      "all three |\n|---|---|---|---|---|---|\n";
  size_t best = 0, base = 0;
  double best_h = 1.0;
  for (size_t w = 0; w <= std::size(kHeightWeights) && !rows.empty(); ++w) {
    double sum = 0.0;
    size_t ratio = 0, cosine = 0, magnitude = 0, all = 0;
    for (const Row& r : rows) {
      const CompareResult& c = w == 0 ? r.on : r.weighted[w - 1];
      sum += c.ratio;
      ratio += RatioMet(c);
      cosine += CosineMet(c);
      magnitude += MagnitudeMet(c);
      all += AllMet(c);
    }
    if (w == 0) base = all;
    if (all > best) best = all, best_h = w == 0 ? 1.0 : kHeightWeights[w - 1];
    trade += "| " + (w == 0 ? std::string("1 (the table above)") : Fixed(kHeightWeights[w - 1], 0)) +
             " | " + Fixed(sum / double(rows.size()), 3) + " | " + std::to_string(ratio) + " | " +
             std::to_string(cosine) + " | " + std::to_string(magnitude) + " | " +
             std::to_string(all) + " |\n";
  }
  trade += "\nOf the weights tried, the most shapes meeting all three targets: " +
           std::to_string(best) + " (H = " + Fixed(best_h, 0) + "), against " +
           std::to_string(base) + " with the plain solve. The report keeps the plain solve "
           "(what `mimetic solve` does by default).\n\n";

  md += where;
  md += why;
  md += costs;
  md += trade;
  md += creases;
  md += "## Pictures: real | rig (every layer) | distance of the real shape to the rig\n\n"
        "Distance from blue (0) to red (half the shape's largest motion); grey outside the measured "
        "region.\n\n";
  for (const Row& r : rows) md += "**" + std::string(r.shape->name) + "**\n\n![" + r.shape->name + "](" + r.image + ")\n\n";
  local.Clear();
  if (!report_dir.empty()) std::filesystem::create_directories(report_dir, ec);
  if (!WriteFileAtomic(report_path, md, &local)) {
    diag.Append(local);
    return Fail(diag, "cannot write the report");
  }
  std::printf("wrote %s: %zu shapes solved, targets met on %zu; %zu not claimed\n",
              report_path.c_str(), rows.size(), met, not_claimed.size());
  return 0;
}

}  // namespace mimetic::tools
