// tools/cmd_library.cpp: `mimetic make-library`, the reproducible expression library and ARKit
// map of the default template (docs/facs.md, docs/arkit.md): fit the template to ICT-FaceKit's
// neutral (as `mimetic fidelity` does), solve every entry that has a matching real shape
// (fitting/solve.h; a bilateral entry on the sum of the _L and _R displacements with the sides
// tied), take the others from the anatomy tables below, and write
// assets/expressions/default.library.json and assets/arkit/default.arkit.json.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "expressions/runtime/clip.h"
#include "fitting/compare.h"
#include "fitting/fit.h"
#include "fitting/solve.h"
#include "geometry/mesh.h"
#include "io/arkit_map.h"
#include "io/expression_library.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/template_file.h"
#include "rig/offline/rig_builder.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/ict_shapes.h"

namespace mimetic::tools {
namespace {

const char* kLibraryUsage =
    "usage: mimetic make-library [--data DIR] [--template FILE] [--landmarks FILE]\n"
    "                            [--library FILE] [--arkit FILE] [--only NAME,...]\n\n"
    "The expression library and the ARKit map of a muscle template (docs/facs.md,\n"
    "docs/arkit.md). Fits the template (default assets/head/default.template.json) to\n"
    "ICT-FaceKit's neutral head (DIR/ict-facekit/ict_skin_neutral.obj, DIR default\n"
    "../shared/data; landmarks default tests/data/landmarks/ict_facekit.landmarks.json), solves\n"
    "each entry that has a matching ICT shape (`mimetic solve`, every skin layer on; a\n"
    "bilateral action unit on the sum of the _L and _R shapes with NAME_L and NAME_R tied),\n"
    "takes the others from the anatomy tables in tools/cmd_library.cpp, and writes the\n"
    "library (--library, default assets/expressions/default.library.json) and the map\n"
    "(--arkit, default assets/arkit/default.arkit.json). Activations are rounded to 3\n"
    "decimals; muscles below 0.01 are left out (the distances are measured as stored).\n"
    "Deterministic: a rerun writes the same files.\n"
    "--only NAME,...: solve only these library expressions and ARKit shapes; every other\n"
    "solved entry is kept as the existing --library and --arkit files have it (they must\n"
    "exist); a quick check that the committed files are what the command writes.\n"
    "Run from the repository root.\n";

using Activations = std::vector<std::pair<std::string, float>>;

// Both sides of each named muscle ("zygomaticus_major" -> _L and _R) at `value`.
Activations Both(std::initializer_list<std::pair<const char*, float>> muscles) {
  Activations out;
  for (const char* side : {"_L", "_R"})
    for (const auto& [m, v] : muscles) out.push_back({std::string(m) + side, v});
  return out;
}
Activations Side(const char* side, std::initializer_list<std::pair<const char*, float>> muscles) {
  Activations out;
  for (const auto& [m, v] : muscles) out.push_back({std::string(m) + side, v});
  return out;
}

// A solve: ICT shapes (under DIR/ict-facekit/arkit/) whose displacements are summed, and
// whether NAME_L / NAME_R are tied.
struct SolveSpec {
  std::vector<std::string> shapes;
  bool mirror = false;
};

struct LibraryEntry {
  const char* name;
  const char* description;
  const char* sources;
  SolveSpec solve;       // empty: set by hand
  Activations by_hand;
};

const char* kZhang = "Zhang, Sim and Tan 2005, §3 (the expressions of Figs. 9-10 and the muscles "
                     "each activates)";
const char* kBando = "Bando, Kuratate and Nishita 2003 (Japanese), Figs. 7-10";
const char* kFacs = "Ekman and Friesen, FACS manual (1978; 2002 edition with Hager): the action "
                    "unit and its muscle";

std::vector<LibraryEntry> LibraryTable() {
  return {
      {"neutral", "Every muscle at rest.", "", {}, {}},
      {"Surprise",
       "Brows raised, forehead furrowed: the three frontalis sheets of both sides at 0.9 "
       "(values set by hand).",
       kZhang, {},
       Both({{"frontalis_inner", 0.9f}, {"frontalis_major", 0.9f}, {"frontalis_outer", 0.9f}})},
      {"Frowning",
       "Brows drawn together and down, furrows between them: both corrugators at 0.9 (set by "
       "hand).",
       kZhang, {}, Both({{"corrugator_supercilii", 0.9f}})},
      {"Fear",
       "Inner brows raised and drawn toward the centre: frontalis inner at 0.8 with the "
       "corrugator at 0.6 (set by hand).",
       kZhang, {}, Both({{"frontalis_inner", 0.8f}, {"corrugator_supercilii", 0.6f}})},
      {"Thinking",
       "Brows raised, milder than surprise: frontalis inner and major at 0.6, outer at 0.4 (set "
       "by hand; Bando's Fig. 7 'thinking: raise the brows').",
       kBando, {},
       Both({{"frontalis_inner", 0.6f}, {"frontalis_major", 0.6f}, {"frontalis_outer", 0.4f}})},
      {"Puzzled",
       "Brows knit: corrugators at 0.7 and procerus at 0.5 (set by hand; Bando's Fig. 8 "
       "'puzzled: knit the brows').",
       kBando, {}, Both({{"corrugator_supercilii", 0.7f}, {"procerus", 0.5f}})},
      {"Disgust",
       "Nose and upper lip raised, brows lowered: levator labii superioris alaeque nasi 0.8, "
       "levator labii superioris 0.4, procerus 0.6, corrugator 0.4 (set by hand; Bando's Fig. 9 "
       "'disgust: raise the nose, lower the brows').",
       kBando, {},
       Both({{"levator_labii_alaeque_nasi", 0.8f}, {"levator_labii_superioris", 0.4f},
             {"procerus", 0.6f}, {"corrugator_supercilii", 0.4f}})},
      {"Smile",
       "Mouth corners and cheeks raised: zygomaticus major 0.8, zygomaticus minor 0.4 (set by "
       "hand; Bando's Fig. 10 'smile: raise the cheeks, narrow the eyes'; the eyes' narrowing "
       "is orbicularis oculi, which the rig does not have).",
       kBando, {}, Both({{"zygomaticus_major", 0.8f}, {"zygomaticus_minor", 0.4f}})},
      {"AU1", "Inner brow raiser (frontalis, pars medialis), solved on ICT-FaceKit's "
              "browInnerUp_L + browInnerUp_R.",
       kFacs, {{"browInnerUp_L", "browInnerUp_R"}, true}, {}},
      {"AU2", "Outer brow raiser (frontalis, pars lateralis), solved on browOuterUp_L + "
              "browOuterUp_R.",
       kFacs, {{"browOuterUp_L", "browOuterUp_R"}, true}, {}},
      {"AU4", "Brow lowerer (corrugator supercilii, procerus, depressor supercilii), solved on "
              "browDown_L + browDown_R.",
       kFacs, {{"browDown_L", "browDown_R"}, true}, {}},
      {"AU9",
       "Nose wrinkler (levator labii superioris alaeque nasi): LLSAN at 0.8 with procerus at 0.3 "
       "(set by hand from anatomy: no noseSneer shape in the ICT data here).",
       kFacs, {}, Both({{"levator_labii_alaeque_nasi", 0.8f}, {"procerus", 0.3f}})},
      {"AU10", "Upper lip raiser (levator labii superioris), solved on mouthUpperUp_L + "
               "mouthUpperUp_R.",
       kFacs, {{"mouthUpperUp_L", "mouthUpperUp_R"}, true}, {}},
      {"AU11", "Nasolabial deepener (zygomaticus minor) at 0.8 (set by hand from anatomy: no "
               "matching ICT shape).",
       kFacs, {}, Both({{"zygomaticus_minor", 0.8f}})},
      {"AU12", "Lip corner puller (zygomaticus major), solved on mouthSmile_L + mouthSmile_R.",
       kFacs, {{"mouthSmile_L", "mouthSmile_R"}, true}, {}},
      {"AU14", "Dimpler (buccinator), solved on mouthDimple_L + mouthDimple_R.",
       kFacs, {{"mouthDimple_L", "mouthDimple_R"}, true}, {}},
      {"AU15", "Lip corner depressor (depressor anguli oris) at 0.8 (set by hand from anatomy: "
               "no mouthFrown shape in the ICT data here).",
       kFacs, {}, Both({{"depressor_anguli_oris", 0.8f}})},
      {"AU16", "Lower lip depressor (depressor labii inferioris), solved on mouthLowerDown_L + "
               "mouthLowerDown_R.",
       kFacs, {{"mouthLowerDown_L", "mouthLowerDown_R"}, true}, {}},
      {"AU17", "Chin raiser (mentalis) at 0.8 (set by hand from anatomy: no mouthShrugLower "
               "shape in the ICT data here).",
       kFacs, {}, Both({{"mentalis", 0.8f}})},
      {"AU20", "Lip stretcher (risorius, with platysma), solved on mouthStretch_L + "
               "mouthStretch_R.",
       kFacs, {{"mouthStretch_L", "mouthStretch_R"}, true}, {}},
      {"AU25",
       "Lips part without the jaw: depressor labii inferioris 0.6 lowers the lower lip, levator "
       "labii superioris 0.3 lifts the upper (set by hand from anatomy; FACS names depressor "
       "labii inferioris or a relaxed mentalis / orbicularis oris for AU25, and the jaw for "
       "AU26/27).",
       kFacs, {}, Both({{"depressor_labii_inferioris", 0.6f}, {"levator_labii_superioris", 0.3f}})},
      {"AU26",
       "Jaw drop: the jaw at 0.5 of its opening, the muscles at rest (set by hand from anatomy; "
       "FACS: the mandible lowered by relaxing the masseter and temporalis, the lips parted by "
       "it; the jaw input, docs/model.md §18).",
       kFacs, {}, {{kJawInputName, 0.5f}}},
      {"AU27",
       "Mouth stretch: the jaw at its full opening, the muscles at rest (set by hand from "
       "anatomy; FACS: the mandible pulled far down by the lateral pterygoid and digastric; "
       "the jaw input, docs/model.md §18).",
       kFacs, {}, {{kJawInputName, 1.f}}},
      {"AU38", "Nostril dilator (nasalis, pars alaris) at 0.8 (set by hand from anatomy: no "
               "matching ICT shape).",
       kFacs, {}, Both({{"nasalis", 0.8f}})},
  };
}

struct ArkitEntry {
  std::string name;
  ArkitShape::How how;
  SolveSpec solve;       // kSolved
  Activations by_hand;   // kAnatomy
  const char* note;      // kAnatomy / kNone: the reason; kSolved: "" (made from the numbers)
};

constexpr const char* kOculi =
    "orbicularis oculi, a sphincter, and the eyelids: the rig has neither";
constexpr const char* kLook = "the eyeballs turn and the lids follow: no eyes or lids in the rig";
constexpr const char* kWide = "levator palpebrae lifts the upper lid: no lids in the rig";
constexpr const char* kJawOpen =
    "the jaw stage (\"jaw\", docs/model.md §18) opens the mouth: the default template's jaw is "
    "calibrated on ICT-FaceKit's jawOpen (docs/jaw.md; ratio 0.38)";
constexpr const char* kJawOther =
    "the jaw glides only with the opening: no separate protrusion or lateral input yet "
    "(docs/model.md §18)";
constexpr const char* kMouthClose =
    "closes the lips over an open jaw: the lip seal is orbicularis oris, a sphincter";
constexpr const char* kOris =
    "orbicularis oris, a sphincter: the rig has linear and sheet muscles only";

std::vector<ArkitEntry> ArkitTable() {
  using H = ArkitShape::How;
  std::vector<ArkitEntry> t;
  for (const std::string s : {"Left", "Right"}) {
    t.push_back({"eyeBlink" + s, H::kNone, {}, {}, kOculi});
    t.push_back({"eyeLookDown" + s, H::kNone, {}, {}, kLook});
    t.push_back({"eyeLookIn" + s, H::kNone, {}, {}, kLook});
    t.push_back({"eyeLookOut" + s, H::kNone, {}, {}, kLook});
    t.push_back({"eyeLookUp" + s, H::kNone, {}, {}, kLook});
    t.push_back({"eyeSquint" + s, H::kNone, {}, {}, kOculi});
    t.push_back({"eyeWide" + s, H::kNone, {}, {}, kWide});
  }
  for (const char* j : {"jawForward", "jawLeft", "jawRight"})
    t.push_back({j, H::kNone, {}, {}, kJawOther});
  t.push_back({"jawOpen", H::kAnatomy, {}, {{kJawInputName, 1.f}}, kJawOpen});
  t.push_back({"mouthClose", H::kNone, {}, {}, kMouthClose});
  for (const char* o : {"mouthFunnel", "mouthPucker", "mouthRollLower", "mouthRollUpper",
                        "mouthPressLeft", "mouthPressRight"})
    t.push_back({o, H::kNone, {}, {}, kOris});
  t.push_back({"mouthLeft", H::kSolved, {{"mouthLeft"}, false}, {}, ""});
  t.push_back({"mouthRight", H::kSolved, {{"mouthRight"}, false}, {}, ""});
  for (const char* base : {"mouthSmile", "mouthDimple", "mouthStretch", "mouthLowerDown",
                           "mouthUpperUp", "browDown", "browOuterUp"}) {
    const std::string b = base;
    t.push_back({b + "Left", H::kSolved, {{b + "_L"}, false}, {}, ""});
    t.push_back({b + "Right", H::kSolved, {{b + "_R"}, false}, {}, ""});
  }
  t.push_back({"browInnerUp", H::kSolved, {{"browInnerUp_L", "browInnerUp_R"}, true}, {}, ""});
  t.push_back({"mouthShrugUpper", H::kSolved, {{"mouthShrugUpper"}, true}, {}, ""});
  t.push_back({"mouthFrownLeft", H::kAnatomy, {}, Side("_L", {{"depressor_anguli_oris", 0.8f}}),
               "depressor anguli oris pulls the mouth corner down (FACS AU15); set by hand: no "
               "mouthFrown shape in the ICT data here"});
  t.push_back({"mouthFrownRight", H::kAnatomy, {}, Side("_R", {{"depressor_anguli_oris", 0.8f}}),
               "depressor anguli oris pulls the mouth corner down (FACS AU15); set by hand: no "
               "mouthFrown shape in the ICT data here"});
  t.push_back({"mouthShrugLower", H::kAnatomy, {}, Both({{"mentalis", 0.8f}}),
               "mentalis raises the chin and pushes the lower lip up (FACS AU17); set by hand: "
               "no mouthShrugLower shape in the ICT data here"});
  t.push_back({"noseSneerLeft", H::kAnatomy, {},
               Side("_L", {{"levator_labii_alaeque_nasi", 0.8f}, {"procerus", 0.3f}}),
               "levator labii superioris alaeque nasi raises the ala and wrinkles the nose "
               "(FACS AU9), procerus lowers the glabella; set by hand: no noseSneer shape in "
               "the ICT data here"});
  t.push_back({"noseSneerRight", H::kAnatomy, {},
               Side("_R", {{"levator_labii_alaeque_nasi", 0.8f}, {"procerus", 0.3f}}),
               "levator labii superioris alaeque nasi raises the ala and wrinkles the nose "
               "(FACS AU9), procerus lowers the glabella; set by hand: no noseSneer shape in "
               "the ICT data here"});
  t.push_back({"cheekPuff", H::kNone, {}, {},
               "air pressure pushes the cheeks out: no muscle pulls them there"});
  t.push_back({"cheekSquintLeft", H::kNone, {}, {}, kOculi});
  t.push_back({"cheekSquintRight", H::kNone, {}, {}, kOculi});
  t.push_back({"tongueOut", H::kNone, {}, {}, "the tongue: the rig is the skin of the face"});
  return t;
}

struct Solved {
  Activations activations;  // rounded to 3 decimals, zeros left out
  CompareResult cmp;
  std::string target;       // relative to the data folder ("a.obj + b.obj")
};

int Fail(const Diagnostics& diag, const std::string& what) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
  std::fprintf(stderr, "mimetic make-library: %s\n", what.c_str());
  return 1;
}

std::string Fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

Activations Rounded(const Activations& a) {
  Activations out;
  for (const auto& [m, v] : a) {
    const float r = float(std::round(double(v) * 1000.0) / 1000.0);
    if (r >= 0.01f) out.push_back({m, r});  // below 0.01: no visible motion; left out
  }
  return out;
}

// A read-back entry's activations in the rig's muscle order, the order a solve writes them.
void InRigOrder(const Rig& rig, Activations* a) {
  std::stable_sort(a->begin(), a->end(), [&](const auto& x, const auto& y) {
    return unsigned(rig.FindMuscle(x.first)) < unsigned(rig.FindMuscle(y.first));
  });
}

}  // namespace

int CmdMakeLibrary(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"data", "template", "landmarks", "library", "arkit", "only"}, {});
  if (parsed.help) return std::fputs(kLibraryUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("make-library", parsed.error, kLibraryUsage);
  if (!parsed.positional.empty())
    return UsageError("make-library", "takes no positional arguments", kLibraryUsage);
  const std::string data = parsed.Get("data", "../shared/data");
  const std::string template_path = parsed.Get("template", "assets/head/default.template.json");
  const std::string landmarks_path =
      parsed.Get("landmarks", "tests/data/landmarks/ict_facekit.landmarks.json");
  const std::string library_path = parsed.Get("library", "assets/expressions/default.library.json");
  const std::string arkit_path = parsed.Get("arkit", "assets/arkit/default.arkit.json");

  // --only: the entries to solve; the rest come from the existing files.
  std::set<std::string> only;
  std::vector<Expression> old_library;
  std::vector<ArkitShape> old_shapes;
  if (parsed.Has("only")) {
    std::stringstream list(parsed.Get("only"));
    for (std::string item; std::getline(list, item, ',');)
      if (!item.empty()) only.insert(item);
    std::set<std::string> known;
    for (const LibraryEntry& e : LibraryTable()) known.insert(e.name);
    for (const char* name : ArkitShapeNames()) known.insert(name);
    for (const std::string& name : only)
      if (!known.count(name))
        return UsageError("make-library", "--only " + parsed.Get("only") + ": \"" + name +
                                              "\" is neither a library expression nor an ARKit "
                                              "shape name", kLibraryUsage);
    if (only.empty())
      return UsageError("make-library", "--only: expected one or more names", kLibraryUsage);
    Diagnostics old;
    const bool library_ok = LoadExpressionLibrary(library_path, &old_library, &old);
    const bool arkit_ok = LoadArkitMap(arkit_path, &old_shapes, &old);
    if (!library_ok || !arkit_ok)
      return Fail(old, "--only keeps the other entries of --library and --arkit, which must be "
                       "readable");
  }
  auto kept = [&](const std::string& name) { return !only.empty() && !only.count(name); };

  // The rig: the template fitted to the ICT neutral (as mimetic fidelity does).
  const auto start = std::chrono::steady_clock::now();
  Diagnostics diag, local;
  IctRig ict;
  std::string what;
  if (!FitIctRig(data, template_path, landmarks_path, &ict, &diag, &what)) return Fail(diag, what);
  const MeshData& neutral = ict.neutral;
  const std::string& neutral_path = ict.neutral_path;
  const Rig& rig = ict.rig;
  std::printf("make-library: %s fitted to %s (%u muscles) in %.1f s\n", template_path.c_str(),
              neutral_path.c_str(), rig.muscle_count(), ict.seconds);

  std::map<std::string, Solved> cache;  // by target + mirror
  auto solve = [&](const SolveSpec& s, Solved* out) -> bool {
    std::string key = s.mirror ? "mirror:" : "";
    for (const std::string& n : s.shapes) key += n + ",";
    if (auto it = cache.find(key); it != cache.end()) return *out = it->second, true;
    MeshData target = neutral;
    Solved r;
    for (const std::string& name : s.shapes) {
      const std::string rel = "ict-facekit/arkit/" + name + ".obj";
      MeshData shape;
      local.Clear();
      if (!ImportMesh(data + "/" + rel, "", &shape, &local) ||
          shape.vertex_count() != neutral.vertex_count()) {
        diag.Append(local, data + "/" + rel);
        diag.Error(data + "/" + rel, "cannot read it, or not the neutral's topology");
        return false;
      }
      for (size_t v = 0; v < neutral.vertex_count(); ++v)
        target.positions[v] += shape.positions[v] - neutral.positions[v];
      r.target += (r.target.empty() ? "" : " + ") + rel;
    }
    SolveOptions options;
    options.mirror = s.mirror;
    SolveResult result;
    local.Clear();
    if (!SolveActivations(rig, neutral, target, options, &result, &local)) {
      diag.Append(local, r.target);
      return false;
    }
    Activations raw;
    for (uint32_t m = 0; m < rig.muscle_count(); ++m)
      raw.push_back({rig.muscle_names()[m], result.activations[m]});
    r.activations = Rounded(raw);
    // Measured as stored (rounded), with every skin layer, as the map's readers will pose it.
    std::vector<float> stored(rig.muscle_count(), 0.f);
    for (const auto& [m, v] : r.activations) stored[uint32_t(rig.FindMuscle(m))] = v;
    MeshData posed_full;
    if (!PosedMesh(rig, stored, {}, &posed_full)) {
      diag.Error(r.target, "evaluation failed (internal error: job did not validate)");
      return false;
    }
    MeshData posed = neutral;
    for (size_t v = 0; v < neutral.vertex_count(); ++v) posed.positions[v] = posed_full.positions[v];
    CompareOptions co;
    co.neutral = &neutral;
    co.region.kind = CompareRegion::Kind::kMoved;
    co.region.threshold = result.region_threshold;
    local.Clear();
    if (!CompareMeshes(posed, target, co, &r.cmp, &local)) {
      diag.Append(local, r.target);
      return false;
    }
    std::printf("  %-48s mean %.4f, neutral %.4f, ratio %.2f, cosine %.2f\n", r.target.c_str(),
                r.cmp.b_to_a.mean, r.cmp.b_to_neutral.mean, r.cmp.ratio, r.cmp.direction_cosine);
    std::fflush(stdout);
    cache[key] = r;
    *out = std::move(r);
    return true;
  };

  std::vector<Expression> library;
  for (const LibraryEntry& e : LibraryTable()) {
    if (!e.solve.shapes.empty() && kept(e.name)) {
      const auto it = std::find_if(old_library.begin(), old_library.end(),
                                   [&](const Expression& x) { return x.name == e.name; });
      if (it == old_library.end())
        return Fail(diag, library_path + " has no expression " + e.name + " to keep (--only)");
      library.push_back(*it);
      InRigOrder(rig, &library.back().activations);
      continue;
    }
    Expression x;
    x.name = e.name;
    x.description = e.description;
    x.sources = e.sources;
    if (!e.solve.shapes.empty()) {
      Solved s;
      if (!solve(e.solve, &s)) return Fail(diag, std::string("cannot solve ") + e.name);
      x.activations = s.activations;
      x.description += " Mean distance to it " + Fixed(s.cmp.b_to_a.mean, 4) + " cm against " +
                       Fixed(s.cmp.b_to_neutral.mean, 4) + " cm for the neutral (ratio " +
                       Fixed(s.cmp.ratio, 2) + "), motion cosine " +
                       Fixed(s.cmp.direction_cosine, 2) + ".";
      x.sources += std::string(x.sources.empty() ? "" : "; ") +
                   "mimetic make-library: mimetic solve on " + s.target +
                   " (ICT-FaceKit), the default template fitted to its neutral";
    } else {
      x.activations = Rounded(e.by_hand);
    }
    library.push_back(std::move(x));
  }

  std::vector<ArkitShape> shapes;
  std::vector<ArkitEntry> table = ArkitTable();
  for (const char* name : ArkitShapeNames()) {
    const auto it = std::find_if(table.begin(), table.end(),
                                 [&](const ArkitEntry& e) { return e.name == name; });
    if (it == table.end()) return Fail(diag, std::string("internal: no table entry for ") + name);
    if (it->how == ArkitShape::How::kSolved && kept(name)) {
      const auto old = std::find_if(old_shapes.begin(), old_shapes.end(),
                                    [&](const ArkitShape& x) { return x.name == name; });
      if (old == old_shapes.end())
        return Fail(diag, arkit_path + " has no shape " + name + " to keep (--only)");
      shapes.push_back(*old);
      InRigOrder(rig, &shapes.back().activations);
      continue;
    }
    ArkitShape s;
    s.name = name;
    s.how = it->how;
    s.note = it->note;
    if (it->how == ArkitShape::How::kSolved) {
      Solved r;
      if (!solve(it->solve, &r)) return Fail(diag, std::string("cannot solve ") + name);
      s.activations = r.activations;
      s.target = r.target;
      s.mean_distance = r.cmp.b_to_a.mean;
      s.neutral_mean_distance = r.cmp.b_to_neutral.mean;
      s.ratio = r.cmp.ratio;
      s.note = std::string(it->solve.mirror ? "solved with the sides tied" : "solved") +
               "; motion cosine " + Fixed(r.cmp.direction_cosine, 2) + ", magnitude " +
               Fixed(r.cmp.magnitude_ratio, 2);
      if (r.cmp.ratio >= 1.0)
        s.note += "; the surface distance is no better than the neutral's (skin sliding along "
                  "the surface is invisible to it, and the rig cannot make the real surface's "
                  "shape: docs/calibration.md)";
    } else {
      s.activations = Rounded(it->by_hand);
    }
    shapes.push_back(std::move(s));
  }

  std::error_code ec;
  for (const std::string& p : {library_path, arkit_path}) {
    const auto dir = std::filesystem::path(p).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  }
  if (!CheckLibraryMuscles(library, rig.muscle_names(), library_path, &diag) ||
      !CheckArkitMuscles(shapes, rig.muscle_names(), arkit_path, &diag))
    return Fail(diag, "internal: a table names a muscle the template does not have");
  if (!SaveExpressionLibrary(library_path, library, &diag) || !SaveArkitMap(arkit_path, shapes, &diag))
    return Fail(diag, "cannot write the outputs");
  std::printf("wrote %s (%zu expressions) and %s (52 ARKit shapes) in %.1f s\n",
              library_path.c_str(), library.size(), arkit_path.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace mimetic::tools
