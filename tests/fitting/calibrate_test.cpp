// CalibrateTemplate (`mimetic calibrate`, docs/model.md §17): recovery of known muscle
// parameters from shapes made by the runtime with them, the anatomical constraints, and the
// refusal of a seed whose muscle pulls against its anatomy (fitting/anatomy.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "content/sample_head.h"
#include "fitting/anatomy.h"
#include "fitting/calibrate.h"
#include "fitting/creases.h"
#include "fitting/fit.h"
#include "geometry/normals.h"
#include "io/template_file.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"

namespace mimetic {
namespace {

const SampleHead& Head() {
  static const SampleHead head = [] {
    SampleHeadOptions o;
    o.columns = 120;
    o.rows = 90;
    return MakeSampleHead(o);
  }();
  return head;
}

Landmarks HeadLandmarks() {
  Landmarks l;
  l.points = Head().landmarks;
  return l;
}

// Two mirrored mouth muscles of the default template's kind (units of s).
std::string TemplateText(float zyg_strength, float zyg_insertion_dy, float dao_attachment_depth) {
  char buf[2048];
  std::snprintf(buf, sizeof buf, R"({"format": "mimetic-muscle-template", "version": 1,
    "muscles": [
      {"name": "zygomaticus_major_L", "type": "linear", "mirror": true, "strength": %g,
       "falloff": "smooth",
       "attachment": {"landmarks": [45], "offset": [0.08, -0.22], "depth": 0.08},
       "insertion": {"landmarks": [54], "offset": [0.03, %g], "depth": 0.02},
       "zone_angle_deg": 30, "falloff_start": 0.6, "falloff_end": 0.9},
      {"name": "depressor_anguli_oris_L", "type": "linear", "mirror": true, "strength": 0.06,
       "falloff": "smooth",
       "attachment": {"landmarks": [10, 11], "offset": [-0.03, 0.04], "depth": %g},
       "insertion": {"landmarks": [54], "offset": [0.02, -0.03], "depth": 0.02},
       "zone_angle_deg": 40, "falloff_start": 0.3, "falloff_end": 0.6}]})",
                double(zyg_strength), double(zyg_insertion_dy), double(dao_attachment_depth));
  return buf;
}

MuscleTemplate Parse(const std::string& text) {
  MuscleTemplate t;
  Diagnostics diag;
  EXPECT_TRUE(ParseMuscleTemplate(text, &t, &diag)) << diag.Format();
  return t;
}

// The head posed by the runtime (EvaluateJob) with `truth` fitted and `activations` set.
MeshData Pose(const MuscleTemplate& truth, const std::vector<float>& activations) {
  RigSpec spec;
  Diagnostics diag;
  EXPECT_TRUE(FitTemplate(truth, Head().mesh, HeadLandmarks(), "mm", &spec, &diag)) << diag.Format();
  Rig rig;
  EXPECT_TRUE(BuildRig(spec, Head().mesh, {}, &rig, &diag)) << diag.Format();
  EvaluateContext ctx(rig);
  std::vector<float3> out(rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = activations;
  job.out_positions = span<float>(&out[0].x, out.size() * 3);
  EXPECT_TRUE(job.Run());
  MeshData posed = Head().mesh;
  for (size_t v = 0; v < posed.vertex_count(); ++v) posed.positions[v] = out[v];
  return posed;
}

TEST(Calibrate, RecoversTheStrengthAndPlacementThatMadeTheShapes) {
  const float true_strength = 0.09f, true_dy = 0.0f;
  const MuscleTemplate truth = Parse(TemplateText(true_strength, true_dy, 0.05f));
  // Rig order: zyg_L, zyg_R, dao_L, dao_R.
  const MeshData smile = Pose(truth, {0.8f, 0.f, 0.f, 0.f});
  const MeshData both = Pose(truth, {0.5f, 0.5f, 0.6f, 0.6f});
  const std::vector<CalibrationShape> shapes = {{"smile", &smile}, {"both", &both}};
  // The seed is off: a weaker zygomaticus with its insertion 0.05 s higher.
  const MuscleTemplate seed = Parse(TemplateText(0.05f, 0.05f, 0.05f));
  CalibrationOptions options;
  options.passes = 6;
  options.muscles = {"zygomaticus_major_L"};
  options.calibrate_motion = false;
  std::vector<double> truth_scores;
  Diagnostics diag;
  ASSERT_TRUE(ScoreTemplate(truth, Head().mesh, HeadLandmarks(), shapes, options, &truth_scores, &diag))
      << diag.Format();
  // The true template reproduces its own shapes: both solves find the activations exactly.
  for (double s : truth_scores) EXPECT_LT(s, 1e-6);
  MuscleTemplate out;
  CalibrationReport report;
  ASSERT_TRUE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), shapes, options, &out, &report, &diag))
      << diag.Format();
  EXPECT_GT(report.objective_before, 0.05);
  std::printf("objective %.6f -> %.6f, %d evaluations\n", report.objective_before, report.objective_after, report.evaluations);
  EXPECT_LT(report.objective_after, 0.02 * report.objective_before);
  ASSERT_EQ(out.muscles.size(), 4u);
  const TemplateMuscle& zl = out.muscles[0];
  const TemplateMuscle& zr = out.muscles[1];
  EXPECT_NEAR(zl.strength, true_strength, 0.1f * true_strength);
  // The insertion's height trades off against the zone's radii and angle (several placements
  // make nearly the same field), so it is not asserted; the fields are: the calibrated
  // template reproduces both shapes to a residual under 0.1% of the neutral's (3% in norm).
  EXPECT_LT(report.objective_after, 1e-3);
  (void)true_dy;
  // The mirror copy follows its source: mirrored landmarks, negated dx, same numbers.
  EXPECT_EQ(zr.name, "zygomaticus_major_R");
  EXPECT_TRUE(zr.mirrored_copy);
  EXPECT_EQ(zr.strength, zl.strength);
  EXPECT_EQ(zr.insertion[0].offset.x, -zl.insertion[0].offset.x);
  EXPECT_EQ(zr.insertion[0].landmarks[0], IbugMirrorLandmark(zl.insertion[0].landmarks[0]));
  // Muscles not named in options.muscles are untouched.
  EXPECT_EQ(out.muscles[2].strength, seed.muscles[2].strength);
  EXPECT_EQ(out.muscles[2].attachment[0].depth, seed.muscles[2].attachment[0].depth);
  // Constraints: attachments on the bone side, insertions in the skin, offsets near the seed.
  for (const TemplateMuscle& m : out.muscles) {
    EXPECT_GE(m.attachment[0].depth, options.min_attachment_depth) << m.name;
    EXPECT_GT(m.attachment[0].depth, m.insertion[0].depth) << m.name;
    EXPECT_LE(m.insertion[0].depth, options.max_insertion_depth) << m.name;
  }
  EXPECT_LE(std::fabs(zl.insertion[0].offset.y - 0.05f), options.offset_reach + 1e-6f);
  // What it measured is what it writes: the result written at the file's 4 digits and read
  // back is the same template, number for number, and scores the objective it reported.
  const MuscleTemplate written = Parse(MuscleTemplateToJson(out));
  ASSERT_EQ(written.muscles.size(), out.muscles.size());
  for (size_t i = 0; i < out.muscles.size(); ++i) {
    const TemplateMuscle &a = out.muscles[i], &b = written.muscles[i];
    EXPECT_EQ(a.strength, b.strength) << a.name;
    EXPECT_EQ(a.falloff_start, b.falloff_start) << a.name;
    EXPECT_EQ(a.falloff_end, b.falloff_end) << a.name;
    EXPECT_EQ(a.zone_angle_deg, b.zone_angle_deg) << a.name;
    EXPECT_EQ(a.attachment[0].depth, b.attachment[0].depth) << a.name;
    EXPECT_EQ(a.insertion[0].depth, b.insertion[0].depth) << a.name;
    EXPECT_EQ(a.attachment[0].offset.x, b.attachment[0].offset.x) << a.name;
    EXPECT_EQ(a.attachment[0].offset.y, b.attachment[0].offset.y) << a.name;
    EXPECT_EQ(a.insertion[0].offset.x, b.insertion[0].offset.x) << a.name;
    EXPECT_EQ(a.insertion[0].offset.y, b.insertion[0].offset.y) << a.name;
  }
  double written_objective = 0.0;
  std::vector<double> written_scores;
  ASSERT_TRUE(ScoreTemplate(written, Head().mesh, HeadLandmarks(), shapes, options, &written_scores, &diag));
  for (double s : written_scores) written_objective += s / double(written_scores.size());
  EXPECT_NEAR(written_objective, report.objective_after, 1e-12 + 1e-9 * report.objective_after);
}

// An attachment that is deeper than its insertion only below the 4 digits a template file
// holds (0.020001 against 0.02) would be written level with it; the calibration refuses it as
// a seed, naming the muscle and both depths.
TEST(Calibrate, RefusesASeedWhoseDepthsPrintLevel) {
  const MuscleTemplate seed = Parse(TemplateText(0.08f, 0.f, 0.020001f));
  ASSERT_GT(seed.muscles[2].attachment[0].depth, seed.muscles[2].insertion[0].depth);
  const MeshData smile = Pose(Parse(TemplateText(0.08f, 0.f, 0.05f)), {0.8f, 0.f, 0.f, 0.f});
  CalibrationOptions options;
  options.min_attachment_depth = 0.01f;
  MuscleTemplate out;
  Diagnostics diag;
  EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"smile", &smile}}, options,
                                 &out, nullptr, &diag));
  EXPECT_TRUE(diag.Contains("depressor_anguli_oris_L")) << diag.Format();
  EXPECT_TRUE(diag.Contains("attachment depth 0.02 is not deeper than the insertion's 0.02")) << diag.Format();
}

// One mirrored linear muscle on the cheek, away from the mouth and the eyes, that pulls the
// cheek up and out; `motion` is inserted as given (e.g. R"("motion": "tangent",)", or empty).
// Its name is in no anatomy rule or fold-over region (fitting/anatomy.h), so only the score
// decides its motion.
MuscleTemplate CheekTemplate(const std::string& motion) {
  return Parse(R"({"format": "mimetic-muscle-template", "version": 1, "muscles": [
      {"name": "cheek_lifter_L", "type": "linear", "mirror": true, "strength": 0.06,
       "falloff": "smooth", )" + motion + R"(
       "attachment": {"landmarks": [45], "offset": [0.15, -0.1], "depth": 0.12},
       "insertion": {"landmarks": [54], "offset": [0.1, 0.25], "depth": 0.02},
       "zone_angle_deg": 30, "falloff_start": 0.3, "falloff_end": 0.6}]})");
}

// A muscle attached below the chin of a head with a short neck: its attachment's ray misses
// the mesh and the fit uses the nearest surface point, up to 0.5 s away. The calibration keeps
// a margin (max_miss, 0.4 s) so that a head a little different still fits its result: a seed
// between the two fits, and the calibration refuses it by name unless the margin is lifted.
TEST(Calibrate, RefusesAPointThatOnlyJustFitsOffTheMesh) {
  auto chin_template = [](float dy) {
    char buf[1024];
    std::snprintf(buf, sizeof buf, R"({"format": "mimetic-muscle-template", "version": 1, "muscles": [
      {"name": "chin_puller_L", "type": "linear", "mirror": true, "strength": 0.04,
       "falloff": "smooth",
       "attachment": {"landmarks": [8], "offset": [0.1, %g], "depth": 0.05},
       "insertion": {"landmarks": [57], "offset": [0.05, -0.1], "depth": 0.02},
       "zone_angle_deg": 30, "falloff_start": 0.2, "falloff_end": 0.5}]})", double(dy));
    return Parse(buf);
  };
  // Walk the attachment down until the fit's miss lies between the margin and the limit.
  float dy = 0.f, miss = 0.f;
  FitReport report;
  for (float y = -0.2f; y > -1.5f; y -= 0.01f) {
    RigSpec spec;
    Diagnostics diag;
    report = FitReport{};
    if (!FitTemplate(chin_template(y), Head().mesh, HeadLandmarks(), "mm", &spec, &diag, &report)) break;
    miss = LargestMiss(report);
    if (miss > 0.42f && miss < 0.48f) {
      dy = y;
      break;
    }
  }
  ASSERT_NE(dy, 0.f) << "no offset put the attachment between 0.42 and 0.48 s off the mesh";
  // LargestMiss against the distance to the nearest vertex (an upper bound of the distance to
  // the surface, and within one edge of it).
  const PlacedPoint* att = nullptr;
  for (const PlacedPoint& p : report.points)
    if (p.muscle == "chin_puller_L" && p.role == "attachment") att = &p;
  ASSERT_NE(att, nullptr);
  EXPECT_FALSE(att->ray_hit);
  float nearest = 1e30f;
  for (const float3& v : Head().mesh.positions) nearest = std::min(nearest, Length(v - att->landmark_point));
  const float s = report.frame.scale;
  EXPECT_LE(miss * s, nearest * 1.0001f);
  EXPECT_GT(miss * s, nearest - 0.05f * s);
  const MuscleTemplate seed = chin_template(dy);
  const MeshData pulled = Pose(seed, {0.8f, 0.8f});
  CalibrationOptions options;
  options.passes = 1;
  MuscleTemplate out;
  Diagnostics diag;
  EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"pulled", &pulled}}, options,
                                 &out, nullptr, &diag));
  EXPECT_TRUE(diag.Contains("chin_puller_L attachment lies off the mesh of the training head")) << diag.Format();
  options.max_miss = 0.5f;
  Diagnostics lifted;
  EXPECT_TRUE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"pulled", &pulled}}, options,
                                &out, nullptr, &lifted))
      << lifted.Format();
}

// The search tries a muscle's other motion only when the seed does not name one: a shape made
// with a tangent muscle pulls an unnamed (chord) seed over to tangent, whose residual is 0,
// while a seed that says "chord" keeps it.
TEST(Calibrate, KeepsAMotionTheSeedNames) {
  const MuscleTemplate truth = CheekTemplate(R"("motion": "tangent",)");
  EXPECT_TRUE(truth.muscles[0].motion_given);
  EXPECT_TRUE(truth.muscles[1].motion_given);  // the mirrored copy says what its source says
  const MeshData lift = Pose(truth, {0.8f, 0.f});
  const std::vector<CalibrationShape> shapes = {{"lift", &lift}};
  CalibrationOptions options;
  options.passes = 1;
  options.normal_weight = 0.f;  // the plain score (the normal weight has its own test below)
  options.crease_fraction = 0.f;  // the crease rule has its own test below
  double after[2] = {0.0, 0.0};  // objective after the run: [unnamed seed, named]
  for (const bool named : {false, true}) {
    const MuscleTemplate seed = CheekTemplate(named ? R"("motion": "chord",)" : "");
    ASSERT_EQ(seed.muscles[0].motion, MuscleMotion::kChord);
    EXPECT_EQ(seed.muscles[0].motion_given, named);
    MuscleTemplate out;
    CalibrationReport report;
    Diagnostics diag;
    ASSERT_TRUE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), shapes, options, &out,
                                  &report, &diag))
        << diag.Format();
    EXPECT_EQ(out.muscles[0].motion, named ? MuscleMotion::kChord : MuscleMotion::kTangent)
        << (named ? "named" : "unnamed");
    EXPECT_EQ(out.muscles[1].motion, out.muscles[0].motion);
    std::printf("%s seed: refused %d objective %.6f -> %.6f\n", named ? "named" : "unnamed",
                report.refused_anatomy, report.objective_before, report.objective_after);
    after[named] = report.objective_after;
  }
  // The shape is tangent motion: the run free to switch fits it far better than chord can.
  EXPECT_LT(after[0], 0.05 * after[1]);
}

// A seed that names a muscle tangent gets its normal-averaging radius tuned (0 to 1 s in steps
// of 0.1): shapes made by the cheek muscle sliding on normals averaged over 0.4 s pull a seed
// that starts at 0.1 s (the same muscle otherwise) to the radius that made them.
TEST(Calibrate, RecoversTheTangentRadiusThatMadeTheShapes) {
  const std::string motion = R"("motion": "tangent", "tangent_radius": )";
  const MuscleTemplate truth = CheekTemplate(motion + "0.4,");
  const MuscleTemplate seed = CheekTemplate(motion + "0.1,");
  ASSERT_FLOAT_EQ(truth.muscles[0].tangent_radius, 0.4f);
  ASSERT_FLOAT_EQ(seed.muscles[0].tangent_radius, 0.1f);
  const MeshData lift = Pose(truth, {0.8f, 0.f});
  const MeshData both = Pose(truth, {0.5f, 0.6f});
  const std::vector<CalibrationShape> shapes = {{"lift", &lift}, {"both", &both}};
  CalibrationOptions options;
  options.passes = 4;
  options.normal_weight = 0.f;
  options.crease_fraction = 0.f;  // the crease rule has its own test below
  std::vector<double> truth_scores, seed_scores;
  Diagnostics diag;
  ASSERT_TRUE(ScoreTemplate(truth, Head().mesh, HeadLandmarks(), shapes, options, &truth_scores, &diag))
      << diag.Format();
  ASSERT_TRUE(ScoreTemplate(seed, Head().mesh, HeadLandmarks(), shapes, options, &seed_scores, &diag))
      << diag.Format();
  for (double s : truth_scores) EXPECT_LT(s, 1e-6);  // the truth reproduces its own shapes
  // The radius matters: the seed's shapes are measurably off.
  EXPECT_GT(seed_scores[0], 1e-3);
  MuscleTemplate out;
  CalibrationReport report;
  ASSERT_TRUE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), shapes, options, &out, &report, &diag))
      << diag.Format();
  std::printf("radius 0.1 -> %g, objective %.6f -> %.6f\n", out.muscles[0].tangent_radius,
              report.objective_before, report.objective_after);
  EXPECT_EQ(out.muscles[0].motion, MuscleMotion::kTangent);
  EXPECT_NEAR(out.muscles[0].tangent_radius, 0.4f, 0.1f + 1e-6f);
  EXPECT_EQ(out.muscles[1].tangent_radius, out.muscles[0].tangent_radius);  // the mirror follows
  EXPECT_LT(report.objective_after, 0.1 * report.objective_before);
}

// The score with a normal weight k (docs/model.md §17): the solve is the plain weighted least
// squares, the residual is measured with w (|r|^2 + k (r . n)^2). A shape made by the cheek
// muscle at 0.8 plus a bump along the neutral's normals where the muscle does not reach: the
// solve still finds 0.8 (the bump is orthogonal to every column), the residual is the bump, and
// the score is computed here from its definition, vertex by vertex.
TEST(Calibrate, NormalWeightCountsTheResidualAlongTheNormal) {
  const MuscleTemplate tmpl = CheekTemplate("");
  const MeshData& head = Head().mesh;
  const MeshData lift = Pose(tmpl, {0.8f, 0.f});
  const std::vector<float3> normals =
      ComputeVertexNormals(head, VertexNormalOptions{.share_by_position = true});
  // The bump: 0.4 mm along the normal on the forehead, which the cheek muscle leaves still.
  MeshData shape = lift;
  size_t bumped = 0;
  for (size_t v = 0; v < head.vertex_count(); ++v) {
    const float3 d = lift.positions[v] - head.positions[v];
    if (d.x != 0.f || d.y != 0.f || d.z != 0.f) continue;
    if (head.positions[v].y < 40.f || head.positions[v].z < 40.f) continue;
    shape.positions[v] = head.positions[v] + 0.4f * normals[v];
    ++bumped;
  }
  ASSERT_GT(bumped, 20u);
  double expected[2] = {0.0, 0.0};  // k = 0, k = 3
  const double ks[2] = {0.0, 3.0};
  {
    std::vector<double> t(3 * head.vertex_count());
    double largest = 0.0;
    for (size_t v = 0; v < head.vertex_count(); ++v) {
      const float3 d = shape.positions[v] - head.positions[v];
      t[3 * v] = d.x, t[3 * v + 1] = d.y, t[3 * v + 2] = d.z;
      largest = std::max(largest, double(Length(d)));
    }
    for (int i = 0; i < 2; ++i) {
      double num = 0.0, den = 0.0;
      for (size_t v = 0; v < head.vertex_count(); ++v) {
        const double* d = &t[3 * v];
        const double len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        const double w = std::sqrt(len2) > 0.02 * largest ? 1.0 : 0.25;
        const float3 n = normals[v];
        const double dn = d[0] * n.x + d[1] * n.y + d[2] * n.z;
        den += w * (len2 + ks[i] * dn * dn);
        const float3 muscle = lift.positions[v] - head.positions[v];
        if (muscle.x != 0.f || muscle.y != 0.f || muscle.z != 0.f) continue;
        const float3 r = shape.positions[v] - lift.positions[v];  // the bump: the residual
        const double rn = double(Dot(r, n));
        num += w * (double(Dot(r, r)) + ks[i] * rn * rn);
      }
      expected[i] = num / den;
    }
  }
  EXPECT_GT(expected[1], 1.2 * expected[0]);  // the bump is all normal: k = 3 sees it more
  for (int i = 0; i < 2; ++i) {
    CalibrationOptions options;
    options.normal_weight = float(ks[i]);
    std::vector<double> scores;
    Diagnostics diag;
    ASSERT_TRUE(ScoreTemplate(tmpl, head, HeadLandmarks(), {{"lift+bump", &shape}}, options,
                              &scores, &diag))
        << diag.Format();
    ASSERT_EQ(scores.size(), 1u);
    std::printf("k = %g: score %.6f, by hand %.6f\n", ks[i], scores[0], expected[i]);
    EXPECT_NEAR(scores[0], expected[i], 1e-4 * expected[i]) << "k = " << ks[i];
  }
}

// The crease rule (CalibrationOptions::crease_fraction, docs/model.md §2-3): each muscle's
// crease number may reach the fraction of the largest with Waters' fall-offs, or, where the
// seed's is above that, may not grow. Shapes made by the cheek muscle at three times the
// seed's strength: free, the search triples the muscle's crease number; with the rule at 0.2,
// under the seed's ratio (its crease number over its own with Waters'), the result creases no
// more than the seed; at 1, where every muscle is within the cap, the rule changes nothing.
// Measured here the other way, on rigs built from the templates (MeasureCreases) on the head
// split as the rule splits it (each triangle into four at its edges' midpoints, which lie on
// the triangles, so the fit places the muscles as on the head itself); the rig welds seams
// the rule's split keeps apart, hence a tolerance of 15% between the two measures.
MeshData SplitAtMidpoints(const MeshData& m) {
  MeshData out;
  out.positions = m.positions;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
  auto at = [&](uint32_t a, uint32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, fresh] = mid.try_emplace({key.first, key.second}, uint32_t(out.positions.size()));
    if (fresh) out.positions.push_back(0.5f * (m.positions[a] + m.positions[b]));
    return it->second;
  };
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    const uint32_t ab = at(a, b), bc = at(b, c), ca = at(c, a);
    for (uint32_t v : {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca}) out.indices.push_back(v);
  }
  return out;
}

struct RigCrease {
  double own = 0.0, waters = 0.0;
  double ratio() const { return own / waters; }
};
RigCrease MeasureRig(const MuscleTemplate& t) {
  static const MeshData split = SplitAtMidpoints(Head().mesh);
  double max[2];
  for (int i = 0; i < 2; ++i) {
    MuscleTemplate u = t;
    if (i) for (TemplateMuscle& m : u.muscles) m.falloff = MuscleFalloff::kWaters;
    RigSpec spec;
    Diagnostics diag;
    EXPECT_TRUE(FitTemplate(u, split, HeadLandmarks(), "mm", &spec, &diag)) << diag.Format();
    spec.refinement.enabled = false;
    Rig rig;
    EXPECT_TRUE(BuildRig(spec, split, {}, &rig, &diag)) << diag.Format();
    max[i] = MeasureCreases(rig).max_degrees;
  }
  return {max[0], max[1]};
}

TEST(Calibrate, TheCreaseRuleHoldsEachMuscleUnderItsCap) {
  const MuscleTemplate seed = CheekTemplate("");
  MuscleTemplate truth = seed;
  truth.muscles[0].strength = truth.muscles[1].strength = 3.f * seed.muscles[0].strength;
  const MeshData lift = Pose(truth, {0.8f, 0.f});
  const MeshData both = Pose(truth, {0.5f, 0.6f});
  const std::vector<CalibrationShape> shapes = {{"lift", &lift}, {"both", &both}};
  const RigCrease s = MeasureRig(seed);
  std::printf("seed: %.3f of %.3f degrees, ratio %.4f\n", s.own, s.waters, s.ratio());
  ASSERT_GT(s.ratio(), 0.25);  // the seed is above 0.2
  const float fractions[3] = {0.f, 0.2f, 1.f};
  RigCrease out[3];
  MuscleTemplate result[3];
  int refused[3];
  for (int run = 0; run < 3; ++run) {
    CalibrationOptions options;
    options.passes = 4;
    options.normal_weight = 0.f;
    options.calibrate_motion = false;
    options.crease_fraction = fractions[run];
    CalibrationReport report;
    Diagnostics diag;
    ASSERT_TRUE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), shapes, options,
                                  &result[run], &report, &diag))
        << diag.Format();
    out[run] = MeasureRig(result[run]);
    refused[run] = report.refused_anatomy;
    std::printf("fraction %.3f: strength %.4f -> %.4f, crease %.3f of %.3f (ratio %.4f), "
                "objective %.5f -> %.5f, %d refused\n", double(fractions[run]),
                double(seed.muscles[0].strength), double(result[run].muscles[0].strength),
                out[run].own, out[run].waters, out[run].ratio(), report.objective_before,
                report.objective_after, report.refused_anatomy);
    if (run == 0) {
      EXPECT_TRUE(report.crease_ratio_before.empty());
      continue;
    }
    // The rule's own ratios against the built rigs'.
    ASSERT_EQ(report.crease_ratio_before.size(), 1u);  // the training head only
    ASSERT_EQ(report.crease_ratio_after.size(), 1u);
    EXPECT_NEAR(report.crease_ratio_before[0], s.ratio(), 0.15 * s.ratio());
    EXPECT_NEAR(report.crease_ratio_after[0], out[run].ratio(), 0.15 * out[run].ratio());
  }
  EXPECT_GT(out[0].own, 2.0 * s.own);  // free, the muscle creases more than twice the seed;
  EXPECT_GT(refused[1], refused[0]);   // at 0.2 the rule refuses changes
  EXPECT_LE(out[1].own, 1.05 * s.own);  // and the result creases no more than the seed.
  // At 1 nothing is over the cap: the same search as without the rule.
  EXPECT_EQ(refused[2], refused[0]);
  EXPECT_EQ(result[2].muscles[0].strength, result[0].muscles[0].strength);
  EXPECT_EQ(result[2].muscles[0].falloff_end, result[0].muscles[0].falloff_end);
}

TEST(Calibrate, RefusesASeedWhoseMusclePullsAgainstItsAnatomy) {
  // A "zygomaticus major" attached below the mouth corner pulls it down, not up.
  std::string text = TemplateText(0.08f, 0.f, 0.05f);
  const std::string from = R"("landmarks": [45], "offset": [0.08, -0.22], "depth": 0.08)";
  text.replace(text.find(from), from.size(), R"("landmarks": [54], "offset": [0.3, -0.4], "depth": 0.08)");
  const MuscleTemplate seed = Parse(text);
  const MuscleTemplate truth = Parse(TemplateText(0.08f, 0.f, 0.05f));
  const MeshData smile = Pose(truth, {0.8f, 0.f, 0.f, 0.f});
  CalibrationOptions options;
  MuscleTemplate out;
  Diagnostics diag;
  EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"smile", &smile}}, options,
                                 &out, nullptr, &diag));
  EXPECT_TRUE(diag.Contains("zygomaticus_major_L pulls the mouth corner up and out, but moves its probe"))
      << diag.Format();
}

// docs/model.md §16: a muscle strong enough to push the mouth corner through its neighbours
// turns triangles over; the calibration refuses such a seed, naming the muscles and triangle.
TEST(Calibrate, RefusesASeedThatTurnsATriangleOver) {
  const MuscleTemplate seed = Parse(TemplateText(0.9f, 0.f, 0.05f));
  const MuscleTemplate truth = Parse(TemplateText(0.08f, 0.f, 0.05f));
  const MeshData smile = Pose(truth, {0.8f, 0.f, 0.f, 0.f});
  CalibrationOptions options;
  MuscleTemplate out;
  Diagnostics diag;
  EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"smile", &smile}}, options,
                                 &out, nullptr, &diag));
  EXPECT_TRUE(diag.Contains("zygomaticus_major_L")) << diag.Format();
  EXPECT_TRUE(diag.Contains("over or nearly (normal dot")) << diag.Format();
}

// Every muscle at 1 is checked too, not only the corners of the regions a muscle belongs to:
// the cheek muscle above is in no region of fitting/anatomy.h, so without that check nothing
// would stop it folding the cheek.
TEST(Calibrate, RefusesASeedThatFoldsWithEveryMuscleAtOne) {
  MuscleTemplate seed = CheekTemplate("");
  seed.muscles[0].strength = seed.muscles[1].strength = 1.5f;
  const MeshData lift = Pose(CheekTemplate(""), {0.8f, 0.f});
  CalibrationOptions options;
  MuscleTemplate out;
  Diagnostics diag;
  EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"lift", &lift}}, options,
                                 &out, nullptr, &diag));
  EXPECT_TRUE(diag.Contains("at 1 (all muscles) turns triangle")) << diag.Format();
  // At the seed's own strength the same muscle passes.
  Diagnostics ok;
  CalibrationOptions one_pass;
  one_pass.passes = 1;
  EXPECT_TRUE(CalibrateTemplate(CheekTemplate(""), Head().mesh, HeadLandmarks(), {{"lift", &lift}},
                                one_pass, &out, nullptr, &ok))
      << ok.Format();
}

TEST(Calibrate, BadInputsAreNamed) {
  const MuscleTemplate seed = Parse(TemplateText(0.08f, 0.f, 0.05f));
  CalibrationOptions options;
  MuscleTemplate out;
  {
    Diagnostics diag;
    EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {}, options, &out, nullptr, &diag));
    EXPECT_TRUE(diag.Contains("no training shape")) << diag.Format();
  }
  {
    Diagnostics diag;
    const MeshData same = Head().mesh;
    EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"still", &same}}, options,
                                   &out, nullptr, &diag));
    EXPECT_TRUE(diag.Contains("does not move")) << diag.Format();
  }
  {
    Diagnostics diag;
    MeshData other = Head().mesh;
    other.indices.resize(other.indices.size() - 3);
    EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"other", &other}}, options,
                                   &out, nullptr, &diag));
    EXPECT_TRUE(diag.Contains("another topology")) << diag.Format();
  }
  {
    Diagnostics diag;
    const MeshData smile = Pose(seed, {0.8f, 0.f, 0.f, 0.f});
    options.muscles = {"zygomaticus_major_R"};  // a mirrored copy: changes with its source
    EXPECT_FALSE(CalibrateTemplate(seed, Head().mesh, HeadLandmarks(), {{"smile", &smile}}, options,
                                   &out, nullptr, &diag));
    EXPECT_TRUE(diag.Contains("no source muscle named \"zygomaticus_major_R\"")) << diag.Format();
  }
}

}  // namespace
}  // namespace mimetic
