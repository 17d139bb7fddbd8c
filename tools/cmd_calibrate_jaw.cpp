// tools/cmd_calibrate_jaw.cpp: `mimetic calibrate-jaw`, how the default template's jaw block
// was found (docs/model.md §18, docs/jaw.md). The template's jaw is placed on
// ICT-FaceKit's neutral (fitting/fit.h PlaceJaw) and compared with ICT's real jawOpen. The jaw
// stage is a closed-form function of the weights, the hinge, the angle and the glide, so no rig
// is built here:
//   1. the glide T at jaw = 1 by least squares on the vertices the real shape moves more than
//      half its largest motion (the chin and the jaw line): for a fixed axis, pivot and angle,
//      T(theta) = mean(Y - c - R(theta)(X - c)); a template without a jaw starts at the
//      least-squares angle too (a 1-D search);
//   2. coordinate descent over the range, the condyle offset (dy, dz) and the weight region's
//      parameters on mimetic compare's ratio over the moved vertices (2% of the largest
//      motion), T refitted for each candidate; then the same with T's (y, z) in the descent.
//      Refused or penalised: a triangle turned over at jaw = 1, lips that part less than 3/4
//      as far as the real shape's (the smallest upper-to-lower lip distance near the mouth).
// Writes the template with the calibrated jaw (--out) and prints the figures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fitting/compare.h"
#include "fitting/fit.h"
#include "fitting/landmarks.h"
#include "geometry/normals.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/template_file.h"
#include "rig/offline/rig_spec.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace mimetic::tools {
namespace {

const char* kCalibrateJawUsage =
    "usage: mimetic calibrate-jaw [--data DIR] [--template FILE] [--landmarks FILE]\n"
    "                             [--shape NAME] [--out FILE] [--rounds N] [--range DEG]\n\n"
    "Calibrates the template's jaw block (docs/model.md §18) on ICT-FaceKit: places the jaw on\n"
    "DIR/ict-facekit/ict_skin_neutral.obj (DIR default ../shared/data; landmarks default\n"
    "tests/data/landmarks/ict_facekit.landmarks.json; template default\n"
    "assets/head/default.template.json, a template without a jaw starts from a seed jaw at\n"
    "landmark 0), fits the condyles' glide by least squares on the vertices the real shape\n"
    "(DIR/ict-facekit/arkit/NAME.obj, default jawOpen) moves most, then the range, the condyle\n"
    "offset, the weight region and the glide by coordinate descent on mimetic compare's ratio\n"
    "over the moved vertices, refusing candidates where a triangle turns over and asking the\n"
    "lips to part at least 3/4 as far as the real shape's. The jaw alone is evaluated in closed\n"
    "form (no muscles, no skin layers). Writes the template with the calibrated jaw to --out\n"
    "(default: nothing written) and prints the figures. N rounds of descent per stage (default\n"
    "3); --range keeps the opening at DEG degrees (only the rest is fitted).\n";

struct Problem {
  MeshData neutral, real;
  std::vector<float3> lm;
  FaceFrame frame;
  std::vector<uint32_t> rigid;  // vertices the real shape moves most
  float threshold = 0;          // the compare region's: 2% of the largest motion
  // The lips near the mouth centre (within 0.15 s of the midpoint of 62 and 66): above it and
  // moved less than a quarter of the largest motion by the real shape (the upper lip), below it
  // and moved more than half of it (the lower lip); the real shape's smallest distance of the
  // two (tests/fitting/jaw_test.cpp measures the same on the built rig).
  std::vector<uint32_t> upper, lower;
  double real_gap = 0;
  std::vector<float3> normals;  // the neutral's unit vertex normals (shared by position)
};

double LipGap(const Problem& p, const std::vector<float3>& x) {
  double best = 1e300;
  for (uint32_t a : p.upper)
    for (uint32_t b : p.lower) best = std::min(best, double(Length(x[a] - x[b])));
  return best;
}

bool g_fixed_glide = false;  // the descent's second stage moves the glide itself

struct Hinge {
  JawSpec spec;
  JawFrame frame;
  double theta = 0;  // radians at jaw = 1
  float3 glide{};    // mesh units at jaw = 1
  double rms = 0;    // over the rigid set, mesh units
};

float3 Turn(float3 v, float3 k, double t) {
  const float c = float(std::cos(t)), s = float(std::sin(t));
  return v * c + Cross(k, v) * s + k * (Dot(k, v) * (1.f - c));
}

// Least-squares glide for the template's hinge (fixed pivot and axis) at the template's
// range, or (free_angle) the least-squares angle and glide.
bool FitHinge(const Problem& p, const TemplateJaw& tj, bool free_angle, Hinge* out) {
  Hinge h;
  PlaceJaw(tj, p.lm, p.frame, &h.spec);
  if (!MakeJawFrame(h.spec, &h.frame)) return false;
  auto residual = [&](double t, float3* glide) {
    double sx = 0, sy = 0, sz = 0;
    for (uint32_t v : p.rigid) {
      const float3 d = p.real.positions[v] - h.frame.pivot -
                       Turn(p.neutral.positions[v] - h.frame.pivot, h.frame.axis, t);
      sx += d.x, sy += d.y, sz += d.z;
    }
    const double n = double(p.rigid.size());
    const float3 g{float(sx / n), float(sy / n), float(sz / n)};
    double e = 0;
    for (uint32_t v : p.rigid) {
      const float3 d = p.real.positions[v] - h.frame.pivot -
                       Turn(p.neutral.positions[v] - h.frame.pivot, h.frame.axis, t) - g;
      e += double(Dot(d, d));
    }
    *glide = g;
    return std::sqrt(e / n);
  };
  const double deg = 3.14159265358979323846 / 180.0;
  double best_t = 0, best_e = 1e300;
  float3 g;
  if (!free_angle) {
    h.theta = double(tj.range_deg) * deg;
    h.rms = residual(h.theta, &h.glide);
    if (g_fixed_glide) h.glide = p.frame.DirectionToWorld(tj.translation) * p.frame.scale;
    h.spec.range_deg = tj.range_deg;
    h.spec.translation = h.glide;
    *out = h;
    return true;
  }
  for (int i = 0; i <= 180; ++i) {
    const double e = residual(i * 0.25 * deg, &g);
    if (e < best_e) best_e = e, best_t = i * 0.25 * deg;
  }
  double lo = std::max(0.0, best_t - 0.25 * deg), hi = best_t + 0.25 * deg;
  for (int it = 0; it < 30; ++it) {
    const double m1 = lo + (hi - lo) * 0.382, m2 = lo + (hi - lo) * 0.618;
    if (residual(m1, &g) < residual(m2, &g)) hi = m2; else lo = m1;
  }
  h.theta = 0.5 * (lo + hi);
  h.rms = residual(h.theta, &h.glide);
  h.spec.range_deg = float(h.theta / deg);
  h.spec.translation = h.glide;
  *out = h;
  return true;
}

// The jaw pose at `jaw` (closed form, docs/model.md §18) of every neutral vertex.
std::vector<float3> Pose(const Problem& p, const Hinge& h, double jaw, std::vector<float>* w_out) {
  std::vector<float3> x(p.neutral.vertex_count());
  std::vector<float> w(x.size());
  for (size_t v = 0; v < x.size(); ++v) {
    w[v] = JawRegionWeight(h.spec, h.frame, p.neutral.positions[v], p.normals[v]);
    x[v] = h.frame.pivot + Turn(p.neutral.positions[v] - h.frame.pivot, h.frame.axis,
                                double(w[v]) * jaw * h.theta) +
           h.glide * float(double(w[v]) * jaw);
  }
  if (w_out) *w_out = std::move(w);
  return x;
}

// Triangles whose posed normal points against the rest normal turned by the mean jaw angle of
// the corners (the rigid part of the motion).
size_t TurnedOver(const Problem& p, const Hinge& h, const std::vector<float3>& x,
                  const std::vector<float>& w, double jaw) {
  size_t n = 0;
  const std::vector<float3>& r = p.neutral.positions;
  const std::vector<uint32_t>& idx = p.neutral.indices;
  for (size_t t = 0; t + 2 < idx.size(); t += 3) {
    const uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
    const float3 n0 = Cross(r[b] - r[a], r[c] - r[a]);
    if (!(Length(n0) > 0.f)) continue;
    const double mean = (w[a] + w[b] + w[c]) / 3.0 * jaw * h.theta;
    const float3 n1 = Cross(x[b] - x[a], x[c] - x[a]);
    if (!(Dot(Turn(n0, h.frame.axis, mean), n1) > 0.f)) ++n;
  }
  return n;
}

CompareResult Measure(const Problem& p, const std::vector<float3>& x) {
  MeshData a = p.neutral;
  a.positions = x;
  CompareOptions co;
  co.neutral = &p.neutral;
  co.region.kind = CompareRegion::Kind::kMoved;
  co.region.threshold = p.threshold;
  CompareResult r;
  Diagnostics diag;
  if (!CompareMeshes(a, p.real, co, &r, &diag)) r.ratio = 1e30;
  return r;
}

struct Score {
  double ratio = 1e30, cosine = 0, objective = 1e30, gap = 0;
  size_t flips = 0;
};

Score Evaluate(const Problem& p, const TemplateJaw& tj, Hinge* hinge, bool free_angle = false) {
  Score s;
  Hinge h;
  if (!FitHinge(p, tj, free_angle, &h)) return s;
  std::vector<float> w;
  const std::vector<float3> x = Pose(p, h, 1.0, &w);
  const CompareResult r = Measure(p, x);
  s.ratio = r.ratio;
  s.cosine = r.direction_cosine;
  s.flips = TurnedOver(p, h, x, w, 1.0);
  s.gap = p.real_gap > 0 ? LipGap(p, x) / p.real_gap : 1.0;
  // The ratio, with the lips parting at least 3/4 as far as the real shape's asked for and
  // turned-over triangles refused.
  s.objective = s.ratio + 2.0 * std::max(0.0, 0.75 - s.gap) + (s.flips ? 1.0 + 0.01 * double(s.flips) : 0.0);
  if (hinge) *hinge = h;
  return s;
}

int Fail(const Diagnostics& diag, const std::string& what) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
  std::fprintf(stderr, "mimetic calibrate-jaw: %s\n", what.c_str());
  return kExitInput;
}

void Print(const char* what, const TemplateJaw& j, const Score& s, const Hinge& h,
           const FaceFrame& f) {
  const float3 g{Dot(h.glide, f.x) / f.scale, Dot(h.glide, f.y) / f.scale,
                 Dot(h.glide, f.z) / f.scale};
  std::printf("%-10s ratio %.4f cosine %.4f flips %zu lip gap %.3f of the real | range %.2f deg glide (%.4f, %.4f, %.4f) s "
              "rms %.4g | offset (%.3f, %.3f, %.3f) lip %.2f cheek %.2f drop %.2f back [%.3f, %.3f] neck [%.1f, %.1f]\n",
              what, s.ratio, s.cosine, s.flips, s.gap, h.spec.range_deg, g.x, g.y, g.z, h.rms,
              j.offset.x, j.offset.y, j.offset.z, j.lip_blend_deg, j.cheek_blend_deg,
              j.cheek_drop_deg, j.back[0], j.back[1], j.neck_deg[0], j.neck_deg[1]);
  std::fflush(stdout);
}

}  // namespace

int CmdCalibrateJaw(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"data", "template", "landmarks", "shape", "out", "rounds", "range"}, {});
  if (parsed.help) return std::fputs(kCalibrateJawUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("calibrate-jaw", parsed.error, kCalibrateJawUsage);
  if (!parsed.positional.empty())
    return UsageError("calibrate-jaw", "takes no positional arguments", kCalibrateJawUsage);
  long long rounds = 3;
  if (parsed.Has("rounds") && !ParseInteger(parsed.Get("rounds"), 0, 20, &rounds))
    return UsageError("calibrate-jaw", "--rounds '" + parsed.Get("rounds") +
                                           "': expected a whole number in [0, 20]",
                      kCalibrateJawUsage);
  const std::string data = parsed.Get("data", "../shared/data");
  const std::string template_path = parsed.Get("template", "assets/head/default.template.json");
  const std::string landmarks_path =
      parsed.Get("landmarks", "tests/data/landmarks/ict_facekit.landmarks.json");
  const std::string shape = parsed.Get("shape", "jawOpen");
  const std::string out_path = parsed.Get("out");
  double fixed_range_deg = 0;
  if (parsed.Has("range") && !ParseNumber(parsed.Get("range"), 1, 90, &fixed_range_deg))
    return UsageError("calibrate-jaw", "--range '" + parsed.Get("range") +
                                           "': expected a number of degrees in [1, 90]",
                      kCalibrateJawUsage);
  const bool fixed_range = fixed_range_deg > 0;
  if (!out_path.empty()) {
    const std::string bad = CheckOutputExtension("out", out_path, {".json"});
    if (!bad.empty()) return UsageError("calibrate-jaw", bad, kCalibrateJawUsage);
  }

  Diagnostics diag, local;
  MuscleTemplate tmpl;
  Landmarks landmarks;
  Problem p;
  const std::string neutral_path = data + "/ict-facekit/ict_skin_neutral.obj";
  const std::string real_path = data + "/ict-facekit/arkit/" + shape + ".obj";
  const bool tmpl_ok = LoadMuscleTemplate(template_path, &tmpl, &diag);
  bool mesh_ok = ImportMesh(neutral_path, "", &p.neutral, &local);
  diag.Append(local, neutral_path);
  local.Clear();
  mesh_ok = ImportMesh(real_path, "", &p.real, &local) && mesh_ok;
  diag.Append(local, real_path);
  const bool lm_ok = LoadLandmarks(landmarks_path, &landmarks, &diag);
  if (!tmpl_ok || !mesh_ok || !lm_ok)
    return Fail(diag, "cannot read the inputs (is --data the folder that holds ict-facekit/?)");
  if (p.real.vertex_count() != p.neutral.vertex_count())
    return Fail(diag, real_path + ": expected the neutral's topology (" +
                          std::to_string(p.neutral.vertex_count()) + " vertices), got " +
                          std::to_string(p.real.vertex_count()));
  local.Clear();
  if (!ResolveLandmarks(landmarks, p.neutral, &p.lm, &local) ||
      !ComputeFaceFrame(p.lm, &p.frame, &local)) {
    diag.Append(local, landmarks_path);
    return Fail(diag, "the landmarks do not fit the ICT neutral");
  }
  double largest = 0;
  for (size_t v = 0; v < p.neutral.vertex_count(); ++v)
    largest = std::max(largest, double(Length(p.real.positions[v] - p.neutral.positions[v])));
  p.threshold = float(0.02 * largest);
  for (uint32_t v = 0; v < p.neutral.vertex_count(); ++v)
    if (Length(p.real.positions[v] - p.neutral.positions[v]) >= 0.5 * largest) p.rigid.push_back(v);
  VertexNormalOptions nopt;
  nopt.share_by_position = true;
  nopt.fallback = {};
  p.normals = ComputeVertexNormals(p.neutral, nopt);
  const float3 mouth = (p.lm[62] + p.lm[66]) * 0.5f;
  const float mouth_y = p.frame.ToLocal(mouth).y;
  for (uint32_t v = 0; v < p.neutral.vertex_count(); ++v) {
    if (Length(p.neutral.positions[v] - mouth) > 0.15f * p.frame.scale) continue;
    const float moved = Length(p.real.positions[v] - p.neutral.positions[v]);
    const bool above = p.frame.ToLocal(p.neutral.positions[v]).y > mouth_y;
    if (above && moved < 0.25 * largest) p.upper.push_back(v);
    if (!above && moved > 0.5 * largest) p.lower.push_back(v);
  }
  p.real_gap = p.upper.empty() || p.lower.empty() ? 0.0 : LipGap(p, p.real.positions);
  std::printf("calibrate-jaw: %s against %s; largest motion %.4g, %zu vertices move more than half "
              "of it (the hinge's least squares)\n",
              template_path.c_str(), real_path.c_str(), largest, p.rigid.size());

  TemplateJaw tj;
  if (tmpl.jaw) {
    tj = *tmpl.jaw;
  } else {
    tj.landmarks = {0};
    tj.weights = {1.f};
    tj.offset = {0.1f, -0.15f, -0.25f};
    tj.range_deg = 25.f;
    tj.neck_deg[0] = 20.f;
    tj.neck_deg[1] = 60.f;
  }
  Hinge hinge;
  // A template's jaw starts the descent where it is; a seed starts at the least-squares angle.
  g_fixed_glide = tmpl.jaw.has_value();  // the template's own glide for the start figures
  Score best = Evaluate(p, tj, &hinge, !tmpl.jaw);
  g_fixed_glide = false;
  tj.range_deg = hinge.spec.range_deg;  // the descent moves it on
  if (fixed_range) {  // or the range as given: only the glide follows it
    tj.range_deg = float(fixed_range_deg);
    best = Evaluate(p, tj, &hinge);
  }
  Print("start", tj, best, hinge, p.frame);
  struct Param {
    float* value;
    float step, lo, hi;
    const char* name;
  };
  for (int round = 0; round < int(rounds) * 2; ++round) {
    if (round == int(rounds)) {  // second stage: the glide joins the descent
      g_fixed_glide = true;
      tj.translation = {Dot(hinge.glide, p.frame.x) / p.frame.scale,
                        Dot(hinge.glide, p.frame.y) / p.frame.scale,
                        Dot(hinge.glide, p.frame.z) / p.frame.scale};
    }
    const int stage_round = round % int(rounds);
    Param params[] = {{&tj.range_deg, 2.f, 1.f, 60.f, "range"},
                      {&tj.offset.y, 0.08f, -2.f, 2.f, "dy"},
                      {&tj.offset.z, 0.08f, -2.f, 2.f, "dz"},
                      {&tj.lip_blend_deg, 1.f, 0.05f, 45.f, "lip"},
                      {&tj.cheek_blend_deg, 3.f, 0.5f, 90.f, "cheek"},
                      {&tj.cheek_drop_deg, 3.f, 0.f, 45.f, "drop"},
                      {&tj.back[0], 0.08f, -1.f, 1.f, "b0"},
                      {&tj.back[1], 0.08f, -1.f, 1.f, "b1"},
                      {&tj.neck_deg[0], 8.f, 0.f, 180.f, "n0"},
                      {&tj.neck_deg[1], 8.f, 0.f, 180.f, "n1"},
                      {&tj.translation.y, g_fixed_glide ? 0.02f : 0.f, -1.f, 1.f, "ty"},
                      {&tj.translation.z, g_fixed_glide ? 0.02f : 0.f, -1.f, 1.f, "tz"}};
    for (Param& prm : params) {
      if (prm.step == 0.f || (fixed_range && prm.value == &tj.range_deg)) continue;
      const float step = prm.step / float(1 << stage_round);
      for (int dir : {1, -1}) {
        for (int k = 0; k < 40; ++k) {
          const float old = *prm.value;
          const float next = old + float(dir) * step;
          if (next < prm.lo || next > prm.hi) break;
          *prm.value = next;
          if (!(tj.back[0] < tj.back[1]) || !(tj.neck_deg[0] < tj.neck_deg[1])) {
            *prm.value = old;
            break;
          }
          Hinge h;
          const Score s = Evaluate(p, tj, &h);
          if (s.objective < best.objective - 1e-5) {
            best = s, hinge = h;
          } else {
            *prm.value = old;
            break;
          }
        }
      }
    }
    char what[32];
    std::snprintf(what, sizeof what, "round %d", round);
    Print(what, tj, best, hinge, p.frame);
  }
  // The calibrated block: the range and the glide from the hinge's fit (face frame, units of s).
  auto round4 = [](double v) { return float(std::round(v * 1e4) / 1e4); };
  tj.range_deg = float(std::round(double(hinge.spec.range_deg) * 100.0) / 100.0);
  tj.translation = {round4(Dot(hinge.glide, p.frame.x) / p.frame.scale),
                    round4(Dot(hinge.glide, p.frame.y) / p.frame.scale),
                    round4(Dot(hinge.glide, p.frame.z) / p.frame.scale)};
  tj.offset = {round4(tj.offset.x), round4(tj.offset.y), round4(tj.offset.z)};
  Print("final", tj, best, hinge, p.frame);
  if (!out_path.empty()) {
    tmpl.jaw = tj;
    local.Clear();
    if (!SaveMuscleTemplate(out_path, tmpl, &local)) {
      diag.Append(local, out_path);
      return Fail(diag, "cannot write " + out_path);
    }
    std::printf("calibrate-jaw: wrote %s\n", out_path.c_str());
  }
  return 0;
}

}  // namespace mimetic::tools
