// No fold-overs (issue #10 item 4, docs/model.md §16): on the default rig
// (assets/head/sample_head.rig.json) and on the default template fitted to the ICT-FaceKit
// neutral, no triangle of the output turns over against its rest orientation at any
// activation in [0, 1]. Sampled: every corner of the activation cube of each region (the
// muscles of one brow, of one side of the mouth, across the midline of the brows and of the
// chin, where muscles of both sides overlap), and 300 random poses of all muscles (a fixed
// seed, uniform in [0, 1]^M, M the rig's muscles). A triangle flips when dot(n_posed, n_rest) <= 0 (unit face
// normals); the test reports the worst (smallest) dot product seen. The muscle stage (the sum
// of the muscles, skin layers off) must never flip one, nor every layer with EvaluateJob's
// fold limiter (docs/model.md §16), which the same poses without it show to be needed.
// Lives in tests/fitting (not tests/rig) because it reads the rig file (io) and fits the
// template (fitting); the link lists in tests/CMakeLists.txt keep tests/rig off io.
#include <gtest/gtest.h>

#include <map>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "fitting/anatomy.h"
#include "fitting/fit.h"
#include "fitting/landmarks.h"
#include "fitting/muscle_template.h"
#include "geometry/mesh.h"
#include "io/expression_library.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "io/template_file.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "expressions/runtime/clip.h"
#include "test_support.h"
// Global allocation counter: the worklist's frames allocate nothing.
#include "alloc_counter.h"

namespace mimetic {
namespace {

// The regions whose activation cube corners are sampled: fitting/anatomy.h's (each muscle
// must exist in the rig).
struct Region {
  std::string name;
  std::vector<std::string> muscles;
};

std::vector<Region> Regions() {
  std::vector<Region> out;
  for (const MuscleRegion& r : DefaultMuscleRegions()) out.push_back({r.name, r.muscles});
  return out;
}

// Worst face-normal agreement over the poses, with where it happened.
struct Worst {
  double dot = 1;
  uint32_t triangle = 0;
  float3 at{};  // the triangle's rest centroid
  std::string pose;
  size_t flips = 0;  // (pose, triangle) pairs with dot <= 0
  size_t poses = 0;
};

class FoldOverChecker {
 public:
  explicit FoldOverChecker(const Rig& rig)
      : rig_(rig), context_(rig), positions_(size_t(rig.vertex_count()) * 3) {
    const MeshData rest = RestMesh(rig);
    rest_positions_ = rest.positions;
    indices_ = rest.indices;
    rest_normals_.resize(indices_.size() / 3);
    for (size_t t = 0; t < rest_normals_.size(); ++t) {
      const float3 a = rest.positions[indices_[3 * t]], b = rest.positions[indices_[3 * t + 1]],
                   c = rest.positions[indices_[3 * t + 2]];
      rest_normals_[t] = UnitCross(a, b, c);
    }
  }

  void Check(const std::vector<float>& activations, const SkinLayers& layers,
             const std::string& pose, Worst* worst, bool limit_folds = true) {
    EvaluateJob job;
    job.rig = &rig_;
    job.context = &context_;
    job.activations = activations;
    job.out_positions = positions_;
    job.layers = layers;
    job.limit_folds = limit_folds;
    ASSERT_TRUE(job.Run());
    ++worst->poses;
    auto at = [&](uint32_t v) {
      return float3{positions_[3 * size_t(v)], positions_[3 * size_t(v) + 1], positions_[3 * size_t(v) + 2]};
    };
    for (size_t t = 0; t < rest_normals_.size(); ++t) {
      const std::array<double, 3> n =
          UnitCross(at(indices_[3 * t]), at(indices_[3 * t + 1]), at(indices_[3 * t + 2]));
      const std::array<double, 3>& r = rest_normals_[t];
      const double dot = n[0] * r[0] + n[1] * r[1] + n[2] * r[2];
      if (dot <= 0) ++worst->flips;
      if (dot < worst->dot) {
        worst->dot = dot;
        worst->triangle = uint32_t(t);
        worst->at = (rest_positions_[indices_[3 * t]] + rest_positions_[indices_[3 * t + 1]] +
                     rest_positions_[indices_[3 * t + 2]]) * (1.f / 3.f);
        worst->pose = pose;
      }
    }
  }

 private:
  static std::array<double, 3> UnitCross(float3 a, float3 b, float3 c) {
    const double u[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double w[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    std::array<double, 3> n = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                               u[0] * w[1] - u[1] * w[0]};
    const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& x : n) x = l > 0 ? x / l : 0;  // a collapsed triangle counts as dot 0: a flip
    return n;
  }

  const Rig& rig_;
  EvaluateContext context_;
  std::vector<float> positions_;
  std::vector<float3> rest_positions_;
  std::vector<uint32_t> indices_;
  std::vector<std::array<double, 3>> rest_normals_;
};

// The poses: every cube corner of every region, 300 random poses, everything at 1.
std::vector<std::pair<std::string, std::vector<float>>> Poses(const Rig& rig) {
  std::vector<std::pair<std::string, std::vector<float>>> poses;
  const uint32_t n = rig.muscle_count();
  for (const Region& region : Regions()) {
    std::vector<int> ids;
    for (const std::string& name : region.muscles) {
      const int m = rig.FindMuscle(name);
      EXPECT_GE(m, 0) << "no muscle " << name;
      if (m < 0) return {};
      ids.push_back(m);
    }
    for (uint32_t corner = 1; corner < (1u << ids.size()); ++corner) {
      std::vector<float> a(n, 0.f);
      std::string pose = region.name + std::string(" corner");
      for (size_t k = 0; k < ids.size(); ++k) {
        if (!(corner >> k & 1u)) continue;
        a[size_t(ids[k])] = 1.f;
        pose += " " + region.muscles[k];
      }
      poses.emplace_back(pose, a);
    }
  }
  // Random poses: uniform in [0, 1] from the raw 32-bit output of mt19937 (the engine's
  // sequence is fixed by the standard; std's distributions are not).
  std::mt19937 rng(20261201u);
  for (int i = 0; i < 300; ++i) {
    std::vector<float> a(n);
    for (float& x : a) x = float(rng() >> 8) * (1.f / 16777216.f);
    a[size_t(i) % n] = 1.f;  // one muscle at its full strength in each
    poses.emplace_back("random pose " + std::to_string(i), a);
  }
  poses.emplace_back("all muscles at 1", std::vector<float>(n, 1.f));
  if (test::Sanitized()) {  // every 8th pose (and the last, every muscle at 1): ASan is ~10x slower
    std::vector<std::pair<std::string, std::vector<float>>> some;
    for (size_t i = 0; i < poses.size(); ++i)
      if (i % 8 == 0 || i + 1 == poses.size()) some.push_back(poses[i]);
    return some;
  }
  return poses;
}

Worst Sample(const Rig& rig, const SkinLayers& layers, const char* label, const char* what) {
  FoldOverChecker checker(rig);
  Worst worst;
  for (const auto& [pose, a] : Poses(rig)) checker.Check(a, layers, pose, &worst);
  std::printf("%s, %s: %zu poses, %u triangles; worst dot(n_posed, n_rest) %.4f (%s, output "
              "triangle %u at %.4g %.4g %.4g); %zu flipped (pose, triangle) pairs\n",
              label, what, worst.poses, uint32_t(rig.vertex_indices().size() / 3), worst.dot,
              worst.pose.c_str(), worst.triangle, worst.at.x, worst.at.y, worst.at.z, worst.flips);
  return worst;
}

SkinLayers MusclesOnly() {
  SkinLayers l;
  l.thickness = l.muscle_wrinkles = l.curve_wrinkles = false;
  return l;
}

// The muscle stage: the summed displacement of every sampled pose keeps every triangle's
// orientation (docs/model.md §16: the calibration refuses a template whose region corners
// fold, so no saturation is needed; the tightest pose, every muscle at 1, comes close).
void CheckMuscleSums(const Rig& rig, const char* label, double min_dot) {
  const Worst w = Sample(rig, MusclesOnly(), label, "muscles");
  EXPECT_EQ(w.flips, 0u) << label << ": worst " << w.pose;
  EXPECT_GT(w.dot, min_dot) << label << ": worst " << w.pose;
}

// Every skin layer on: the fold limiter (docs/model.md §16) keeps every triangle's
// orientation. And it is the limiter that does: with it off, the same poses turn triangles
// over (the layers' raw offsets along the normals of a creased skin; the first 40 random
// poses suffice to show it).
void CheckSkinLayers(const Rig& rig, const char* label) {
  const Worst w = Sample(rig, SkinLayers{}, label, "every layer, fold limiter on");
  EXPECT_EQ(w.flips, 0u) << label << ": worst " << w.pose;
  EXPECT_GT(w.dot, 0.0) << label << ": worst " << w.pose;
  FoldOverChecker checker(rig);
  Worst raw;
  int seen = 0;
  for (const auto& [pose, a] : Poses(rig)) {
    if (pose.rfind("random pose", 0) != 0 || seen++ >= 40) continue;
    checker.Check(a, SkinLayers{}, pose, &raw, /*limit_folds=*/false);
  }
  std::printf("%s, every layer, fold limiter off: %zu poses; worst dot %.4f (%s); %zu flipped "
              "(pose, triangle) pairs\n",
              label, raw.poses, raw.dot, raw.pose.c_str(), raw.flips);
  EXPECT_GT(raw.flips, 0u) << label << ": without the limiter nothing folds, so this test "
                                       "no longer shows that the limiter is needed";
}

const Rig& DefaultRig() {
  static const LoadedRig* head = [] {
    auto* h = new LoadedRig;
    Diagnostics diag;
    EXPECT_TRUE(LoadRig(test::SourceDir() + "/assets/head/sample_head.rig.json", h, &diag))
        << diag.Format();
    return h;
  }();
  return head->rig;
}

// The default template fitted to the ICT-FaceKit neutral (docs/fitting.md), or null when
// ../shared is absent.
const Rig* IctRig() {
  static const Rig* rig = []() -> const Rig* {
    const std::string shared = test::SharedDir();
    MeshData mesh;
    Diagnostics diag;
    if (shared.empty() ||
        !ImportMesh(shared + "/data/ict-facekit/ict_skin_neutral.obj", "", &mesh, &diag))
      return nullptr;
    MuscleTemplate tmpl;
    Landmarks landmarks;
    EXPECT_TRUE(LoadMuscleTemplate(test::SourceDir() + "/assets/head/default.template.json", &tmpl, &diag));
    EXPECT_TRUE(LoadLandmarks(test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json",
                              &landmarks, &diag));
    RigSpec spec;
    auto* r = new Rig;
    EXPECT_TRUE(FitTemplate(tmpl, mesh, landmarks, "cm", &spec, &diag)) << diag.Format();
    EXPECT_TRUE(BuildRig(spec, mesh, {}, r, &diag)) << diag.Format();
    return r;
  }();
  return rig;
}

TEST(FoldOver, DefaultRigMuscleSumsNeverFlipATriangle) {
  CheckMuscleSums(DefaultRig(), "sample head rig", 0.0);
}

TEST(FoldOver, IctFittedRigMuscleSumsNeverFlipATriangle) {
  const Rig* rig = IctRig();
  if (!rig) GTEST_SKIP() << "../shared/data/ict-facekit is absent: the ICT-fitted rig is not checked";
  CheckMuscleSums(*rig, "ICT-fitted rig", 0.0);
}

TEST(FoldOver, DefaultRigSkinLayersNeverFlipATriangle) {
  CheckSkinLayers(DefaultRig(), "sample head rig");
}

// The limiter's passes read only the previous pass's values, so how parallel_for splits the
// points does not change a bit: a pose where it reduces points, serial against two threads.
void TwoThreads(void*, uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
  const uint32_t mid = count / 3;
  std::thread t([&] { task(data, 0, mid); });
  task(data, mid, count);
  t.join();
}

TEST(FoldOver, LimiterGivesTheSameBitsHoweverTheWorkIsSplit) {
  const Rig& rig = DefaultRig();
  const std::vector<float> act(rig.muscle_count(), 1.f);
  std::vector<float> pos[2], nrm[2];
  uint32_t limited[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    EvaluateContext ctx(rig);
    pos[k].resize(3 * size_t(rig.vertex_count()));
    nrm[k].resize(3 * size_t(rig.vertex_count()));
    EvaluateJob job;
    job.rig = &rig;
    job.context = &ctx;
    job.activations = act;
    job.out_positions = pos[k];
    job.out_normals = nrm[k];
    if (k == 1) job.parallel_for = TwoThreads;
    if (k == 1) job.parallel_min_count = 1;  // split every loop, however short
    ASSERT_TRUE(job.Run());
    limited[k] = ctx.limited_point_count();
  }
  EXPECT_GT(limited[0], 0u) << "the pose no longer engages the limiter";
  EXPECT_EQ(limited[0], limited[1]);
  EXPECT_EQ(std::memcmp(pos[0].data(), pos[1].data(), pos[0].size() * 4), 0);
  EXPECT_EQ(std::memcmp(nrm[0].data(), nrm[1].data(), nrm[0].size() * 4), 0);
}

// The limiter's worklist (docs/model.md §16: after the first pass only the triangles touching
// a moved point and the points around them) against the full scan it replaces
// (EvaluateJob::limit_folds_full_scan recomputes every active triangle and tests every active
// point in every pass, and tests the curvature bound of every offset against every neighbour's
// normal instead of taking the shortest-edge shortcut of LimitedOffsets): the same positions, normals, limited points and passes, to the bit, on
// hard poses (every expression of assets/expressions/default.library.json, every 20th sampled
// pose, every muscle at 1), serially (allocating nothing) and split over two threads. The
// expected bits are the full scan's.
void CheckWorklistAgainstFullScan(const Rig& rig, const char* label) {
  ASSERT_TRUE(rig.tables().point_triangles_exact) << label << ": the worklist would not run";
  std::vector<std::pair<std::string, std::vector<float>>> poses;
  std::vector<Expression> library;
  Diagnostics diag;
  ASSERT_TRUE(LoadExpressionLibrary(test::SourceDir() + "/assets/expressions/default.library.json",
                                    &library, &diag))
      << diag.Format();
  std::map<std::string, float> jaw_of;  // AU26, AU27: the jaw input, not a muscle
  for (const Expression& e : library) {
    std::vector<float> a(rig.muscle_count(), 0.f);
    for (const auto& [name, value] : e.activations) {
      if (name == kJawInputName && rig.FindMuscle(name) < 0) {
        jaw_of[e.name] = value;
        continue;
      }
      const int m = rig.FindMuscle(name);
      ASSERT_GE(m, 0) << label << ": no muscle " << name << " (" << e.name << ")";
      a[size_t(m)] = value;
    }
    poses.emplace_back(e.name, a);
  }
  const auto sampled = Poses(rig);
  for (size_t i = 0; i < sampled.size(); ++i)
    if (i % 20 == 0 || i + 1 == sampled.size()) poses.push_back(sampled[i]);
  const size_t n3 = 3 * size_t(rig.vertex_count());
  EvaluateContext ctx(rig);
  size_t busy = 0;  // poses where the limiter ran more than one pass (the worklist's part)
  uint32_t most_passes = 0;
  for (const auto& [pose, a] : poses) {
    std::vector<float> pos[3], nrm[3];
    uint32_t limited[3], passes[3];
    for (int k = 0; k < 3; ++k) {  // full scan, worklist, worklist over two threads
      pos[k].assign(n3, -1.f);
      nrm[k].assign(n3, -1.f);
      EvaluateJob job;
      job.rig = &rig;
      job.context = &ctx;
      job.activations = a;
      job.jaw = jaw_of.count(pose) ? jaw_of.at(pose) : 0.f;
      job.out_positions = pos[k];
      job.out_normals = nrm[k];
      job.limit_folds_full_scan = k == 0;
      if (k == 2) job.parallel_for = TwoThreads;
      if (k == 2) job.parallel_min_count = 1;  // split every loop, however short
      const long allocations = g_allocations.load();
      ASSERT_TRUE(job.Run());
      if (k == 1) {
        EXPECT_EQ(g_allocations.load() - allocations, 0) << label << ", " << pose;
      }
      limited[k] = ctx.limited_point_count();
      passes[k] = ctx.limiter_passes();
    }
    for (int k = 1; k < 3; ++k) {
      EXPECT_EQ(limited[k], limited[0]) << label << ", " << pose << ", run " << k;
      EXPECT_EQ(passes[k], passes[0]) << label << ", " << pose << ", run " << k;
      EXPECT_EQ(std::memcmp(pos[k].data(), pos[0].data(), n3 * 4), 0)
          << label << ", " << pose << ", run " << k << ": positions differ";
      EXPECT_EQ(std::memcmp(nrm[k].data(), nrm[0].data(), n3 * 4), 0)
          << label << ", " << pose << ", run " << k << ": normals differ";
    }
    busy += passes[0] > 1;
    most_passes = std::max(most_passes, passes[0]);
  }
  std::printf("%s: %zu poses, the limiter ran more than one pass in %zu (at most %u)\n", label,
              poses.size(), busy, most_passes);
  EXPECT_GT(busy, 0u) << label << ": no pose exercises the worklist";
}

TEST(FoldOver, LimiterWorklistGivesTheFullScansBits) {
  CheckWorklistAgainstFullScan(DefaultRig(), "sample head rig");
}

TEST(FoldOver, IctFittedRigLimiterWorklistGivesTheFullScansBits) {
  const Rig* rig = IctRig();
  if (!rig) GTEST_SKIP() << "../shared/data/ict-facekit is absent: the ICT-fitted rig is not checked";
  CheckWorklistAgainstFullScan(*rig, "ICT-fitted rig");
}

TEST(FoldOver, IctFittedRigSkinLayersNeverFlipATriangle) {
  const Rig* rig = IctRig();
  if (!rig) GTEST_SKIP() << "../shared/data/ict-facekit is absent: the ICT-fitted rig is not checked";
  CheckSkinLayers(*rig, "ICT-fitted rig");
}

}  // namespace
}  // namespace mimetic
