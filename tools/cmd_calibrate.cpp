// tools/cmd_calibrate.cpp: `mimetic calibrate`, the offline calibration of a muscle template
// on ICT-FaceKit's real expression shapes (fitting/calibrate.h, docs/fidelity.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "fitting/calibrate.h"
#include "geometry/mesh.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/template_file.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/ict_shapes.h"

namespace mimetic::tools {
namespace {

const char* kCalibrateUsage =
    "usage: mimetic calibrate --out FILE [--seed FILE] [--data DIR] [--landmarks FILE]\n"
    "                         [--train A,B,...] [--muscles A,B,...] [--passes N]\n"
    "                         [--normal-weight K] [--crease-fraction F]\n\n"
    "Calibrates a muscle template on real expression shapes: fits the seed template (default\n"
    "assets/calibration/seed.template.json) to ICT-FaceKit's neutral head (DIR/ict-facekit/\n"
    "ict_skin_neutral.obj, DIR default ../shared/data; landmarks default\n"
    "tests/data/landmarks/ict_facekit.landmarks.json), then changes one muscle parameter at a\n"
    "time (strength, fall-off radii, zone angle or sheet size, the offsets of its attachment\n"
    "and insertion, their depths, its motion, a tangent muscle's normal radius) while the\n"
    "mean score over the training shapes\n"
    "drops (score = the muscles-alone solve's residual over the neutral's; docs/model.md §17).\n"
    "Mirrored muscles change together; attachments stay on the bone side, insertions in the\n"
    "skin, and a change that makes a muscle pull against its anatomy is refused\n"
    "(fitting/anatomy.h), and so is one that turns a triangle over (docs/model.md §16); both\n"
    "are checked on the ICT head and MakeHuman (DIR/makehuman), the fold-over rule on the\n"
    "sample head too, and with --crease-fraction one after which a muscle folds the skin\n"
    "along its zone's edges more than that allows, on all three heads; a point whose ray\n"
    "misses a head (an attachment below a short neck) may lie at most 0.4 s from the\n"
    "surface, under the fit's 0.5. Numbers are kept at the 4 digits the file holds. Writes\n"
    "the calibrated template to --out (atomically).\n\n"
    "options:\n"
    "  --train A,B,...    training shapes (default: the brow raise, browDown_L and the _L mouth\n"
    "                     shapes; `mimetic fidelity` reports the others as held out)\n"
    "  --muscles A,B,...  change only these source muscles (default every one)\n"
    "  --passes N         coordinate-search sweeps (default 3, 1..20; it stops early when a\n"
    "                     sweep changes nothing)\n"
    "  --normal-weight K  the score counts each vertex's residual along the neutral's normal\n"
    "                     1 + K times (default 1; 0..100): the surface distance that\n"
    "                     `mimetic compare` reports sees that part, the plain residual\n"
    "                     weighs sliding and sinking alike (docs/model.md §17)\n"
    "  --crease-fraction F  on each head, each muscle's crease number (`mimetic creases`:\n"
    "                     alone at 1, its own fall-off) may reach F times the largest the\n"
    "                     muscles make with Waters' fall-offs; one above that in the seed may\n"
    "                     not grow (default 0 = off; 0.333 is the fidelity target; 0..1; a run\n"
    "                     with the rule takes about twice as long; docs/model.md §17)\n"
    "Run from the repository root. A pass takes about a minute and a half on one core\n"
    "(the default template is made with --passes 8 --crease-fraction 0.333: about 19\n"
    "minutes).\n";

int Fail(const Diagnostics& diag, const std::string& what) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
  std::fprintf(stderr, "mimetic calibrate: %s\n", what.c_str());
  return 1;
}

std::vector<std::string> SplitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream list(s);
  std::string item;
  while (std::getline(list, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int CmdCalibrate(const Args& args) {
  const ParsedArgs parsed = ParseArgs(
      args, {"out", "seed", "data", "landmarks", "train", "muscles", "passes", "normal-weight",
             "crease-fraction"}, {});
  if (parsed.help) return std::fputs(kCalibrateUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("calibrate", parsed.error, kCalibrateUsage);
  if (!parsed.positional.empty())
    return UsageError("calibrate", "takes no positional arguments", kCalibrateUsage);
  if (!parsed.Has("out")) return UsageError("calibrate", "--out FILE is required", kCalibrateUsage);
  const std::string out_path = parsed.Get("out");
  const std::string data = parsed.Get("data", "../shared/data");
  const std::string seed_path = parsed.Get("seed", "assets/calibration/seed.template.json");
  const std::string landmarks_path =
      parsed.Get("landmarks", "tests/data/landmarks/ict_facekit.landmarks.json");
  CalibrationOptions options;
  // A numeric option in [lo, hi] (whole: a whole number), into *out when given; "" or the
  // usage error's message.
  auto number = [&](const char* name, double lo, double hi, bool whole, double* out) {
    if (!parsed.Has(name)) return std::string();
    const std::string text = parsed.Get(name);
    if (ParseNumber(text, lo, hi, out) && (!whole || *out == std::floor(*out))) return std::string();
    char range[64];
    std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
    return "--" + std::string(name) + " '" + text + "': expected a " +
           (whole ? "whole number" : "number") + " in " + range;
  };
  double passes = options.passes, normal_weight = options.normal_weight,
         crease_fraction = options.crease_fraction;
  for (const std::string& why : {number("passes", 1, 20, true, &passes),
                                 number("normal-weight", 0, 100, false, &normal_weight),
                                 number("crease-fraction", 0, 1, false, &crease_fraction)})
    if (!why.empty()) return UsageError("calibrate", why, kCalibrateUsage);
  options.passes = int(passes);
  options.normal_weight = float(normal_weight);
  options.crease_fraction = float(crease_fraction);
  if (parsed.Has("muscles")) options.muscles = SplitList(parsed.Get("muscles"));
  std::vector<const IctShape*> train;
  if (parsed.Has("train")) {
    for (const std::string& name : SplitList(parsed.Get("train"))) {
      const IctShape* s = FindIctShape(name.c_str());
      if (!s || s->why_not) {
        std::string known;
        for (const IctShape& k : IctShapes())
          if (!k.why_not) known += (known.empty() ? "" : ", ") + std::string(k.name);
        return UsageError("calibrate", "--train: '" + name + "' is not a shape the rig claims; "
                                       "known: " + known, kCalibrateUsage);
      }
      train.push_back(s);
    }
  } else {
    for (const IctShape& s : IctShapes())
      if (s.trained) train.push_back(&s);
  }
  if (train.empty()) return UsageError("calibrate", "--train: no shape given", kCalibrateUsage);

  const auto start = std::chrono::steady_clock::now();
  Diagnostics diag, local;
  MuscleTemplate seed;
  MeshData neutral;
  Landmarks landmarks;
  const std::string neutral_path = data + "/ict-facekit/ict_skin_neutral.obj";
  const bool seed_ok = LoadMuscleTemplate(seed_path, &seed, &diag);
  const bool mesh_ok = ImportMesh(neutral_path, "", &neutral, &local);
  diag.Append(local, neutral_path);
  const bool lm_ok = LoadLandmarks(landmarks_path, &landmarks, &diag);
  if (!seed_ok || !mesh_ok || !lm_ok)
    return Fail(diag, "cannot read the inputs (is --data the folder that holds ict-facekit/?)");
  std::vector<MeshData> meshes(train.size());
  std::vector<CalibrationShape> shapes;
  for (size_t i = 0; i < train.size(); ++i) {
    const std::string path = data + "/" + train[i]->file;
    local.Clear();
    if (!ImportMesh(path, "", &meshes[i], &local)) {
      diag.Append(local, path);
      return Fail(diag, std::string("cannot read the training shape ") + train[i]->name);
    }
  }
  for (size_t i = 0; i < train.size(); ++i) shapes.push_back({train[i]->name, &meshes[i]});
  // The constraints also hold on the sample head and on MakeHuman (generalisation).
  MeshData sample, makehuman;
  Landmarks sample_lm, makehuman_lm;
  local.Clear();
  if (!ImportMesh("assets/head/sample_head.glb", "", &sample, &local) ||
      !LoadLandmarks("assets/head/sample_head.landmarks.json", &sample_lm, &local)) {
    diag.Append(local);
    return Fail(diag, "cannot read the sample head (run from the repository root)");
  }
  // The sample head's coarse nose misses some probes (the fit tests check the anatomy on ICT
  // and MakeHuman): the fold-over rule only there.
  options.check_heads.push_back({"the sample head", &sample, &sample_lm, false});
  const std::string mh_path = data + "/makehuman/makehuman_head_hm08_crop.obj";
  local.Clear();
  if (ImportMesh(mh_path, "", &makehuman, &local) &&
      LoadLandmarks("tests/data/landmarks/makehuman_hm08.landmarks.json", &makehuman_lm, &local)) {
    options.check_heads.push_back({"MakeHuman", &makehuman, &makehuman_lm});
  } else {
    std::printf("note: %s not read; the constraints are checked on the ICT and sample heads only\n",
                mh_path.c_str());
  }
  std::printf("calibrate: %s on %s, %zu training shapes\n", seed_path.c_str(),
              neutral_path.c_str(), shapes.size());
  std::fflush(stdout);
  options.progress = [](const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  };
  MuscleTemplate calibrated;
  CalibrationReport report;
  local.Clear();
  if (!CalibrateTemplate(seed, neutral, landmarks, shapes, options, &calibrated, &report, &local)) {
    diag.Append(local, seed_path);
    return Fail(diag, "the calibration failed; nothing was written");
  }
  std::printf("\n%-20s %8s %8s\n", "shape", "before", "after");
  for (size_t i = 0; i < report.shapes.size(); ++i)
    std::printf("%-20s %8.4f %8.4f\n", report.shapes[i].c_str(), report.score_before[i],
                report.score_after[i]);
  std::printf("%-20s %8.4f %8.4f\n", "mean", report.objective_before, report.objective_after);
  for (size_t h = 0; h < report.crease_ratio_before.size(); ++h)
    std::printf("crease ratio on %s: %.3f -> %.3f\n",
                h ? options.check_heads[h - 1].name.c_str() : "the training head",
                report.crease_ratio_before[h], report.crease_ratio_after[h]);
  calibrated.description = seed.description;
  local.Clear();
  if (!SaveMuscleTemplate(out_path, calibrated, &local)) {
    diag.Append(local, out_path);
    return Fail(diag, "cannot write the calibrated template");
  }
  std::printf("wrote %s: %d changes in %d evaluations (%d refused: anatomy, fold-over or crease), %.0f s\n",
              out_path.c_str(), report.accepted, report.evaluations, report.refused_anatomy,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace mimetic::tools
