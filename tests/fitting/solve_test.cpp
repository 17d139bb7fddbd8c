// tests/fitting/solve_test.cpp: SolveActivations (fitting/solve.h) and `mimetic solve`:
// targets made by evaluating the rig at known activations must come back to 1e-3 (the
// issue's bar), with and without the skin layers; bad inputs are refused with a reason.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "content/procedural.h"
#include "fitting/solve.h"
#include "geometry/normals.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"

namespace mimetic {
namespace {

// The rig's output at `activations`, as a mesh of the input's topology (the first #V output
// vertices are the input's vertices).
MeshData Posed(const Rig& rig, const MeshData& input, const std::vector<float>& activations) {
  EvaluateContext context(rig);
  std::vector<float> out(3 * size_t(rig.vertex_count()));
  EvaluateJob job;
  job.rig = &rig;
  job.context = &context;
  job.activations = activations;
  job.out_positions = out;
  EXPECT_TRUE(job.Run());
  MeshData m = input;
  for (size_t v = 0; v < m.vertex_count(); ++v) m.positions[v] = {out[3 * v], out[3 * v + 1], out[3 * v + 2]};
  return m;
}

// The test surface with `muscles` muscles and no skin layer: its output is exactly linear in
// the activations.
Rig LinearSurfaceRig(size_t muscles, const MeshData& mesh) {
  RigSpec spec = MakeSurfaceRigSpec(muscles, 100.f, 100.f, 8.f, 0.3f, 6.f);
  spec.layers = {.thickness = false, .muscle_wrinkles = false, .curve_wrinkles = false};
  Rig rig;
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  return rig;
}

const LoadedRig& SampleHeadRig() {
  static const LoadedRig* rig = [] {
    auto* r = new LoadedRig;
    Diagnostics diag;
    EXPECT_TRUE(LoadRig(test::SourceDir() + "/assets/head/sample_head.rig.json", r, &diag))
        << diag.Format();
    return r;
  }();
  return *rig;
}

TEST(RigLayout, OutputStartsWithTheFileVerticesInOrder) {
  // The documented output order (docs/rig-format.md): the file's vertices first, then the
  // ones refinement adds. The default head rig refines, so there are more of the latter.
  const LoadedRig& loaded = SampleHeadRig();
  const MeshData rest = RestMesh(loaded.rig);
  ASSERT_GT(rest.vertex_count(), loaded.mesh.vertex_count());
  for (size_t v = 0; v < loaded.mesh.vertex_count(); ++v) {
    ASSERT_EQ(rest.positions[v].x, loaded.mesh.positions[v].x) << v;
    ASSERT_EQ(rest.positions[v].y, loaded.mesh.positions[v].y) << v;
    ASSERT_EQ(rest.positions[v].z, loaded.mesh.positions[v].z) << v;
    ASSERT_EQ(rest.uvs[v].x, loaded.mesh.uvs[v].x) << v;
  }
}

TEST(Solve, RecoversSurfaceActivationsExactlyWhenLinear) {
  // Six muscles on the test surface, no skin layer: the target is in the muscle basis's span.
  const MeshData mesh = MakeSurfaceMesh(41, 41, 100.f, 100.f, 8.f);
  const Rig rig = LinearSurfaceRig(6, mesh);
  ASSERT_GT(rig.muscle_count(), 0u);
  Diagnostics diag;
  const std::vector<float> truth = {0.7f, 0.f, 0.35f, 1.f, 0.15f, 0.55f};
  const MeshData target = Posed(rig, mesh, truth);
  SolveResult r;
  ASSERT_TRUE(SolveActivations(rig, mesh, target, {}, &r, &diag)) << diag.Format();
  ASSERT_EQ(r.activations.size(), truth.size());
  for (size_t m = 0; m < truth.size(); ++m) EXPECT_NEAR(r.activations[m], truth[m], 1e-4) << m;
  EXPECT_LT(r.residual, 1e-6 * r.neutral_residual);
}

TEST(Solve, ReachSeparatesWhatTheMusclesCannotMakeFromWhatTheBoundsCost) {
  // A target built from the muscle basis with activations outside [0, 1] (1.6 and -0.4), plus
  // a bump where no muscle reaches: the unbounded solve (SolveOptions::reach) must find the
  // activations to 1e-3 and leave exactly the bump, the bounded one must pay for the bounds.
  const MeshData mesh = MakeSurfaceMesh(41, 41, 100.f, 100.f, 8.f);
  const Rig rig = LinearSurfaceRig(6, mesh);
  ASSERT_GT(rig.muscle_count(), 0u);
  Diagnostics diag;
  const size_t nv = mesh.vertex_count();
  std::vector<std::vector<float3>> basis(6);
  for (size_t m = 0; m < 6; ++m) {
    std::vector<float> e(6, 0.f);
    e[m] = 1.f;
    const MeshData p = Posed(rig, mesh, e);
    basis[m].resize(nv);
    for (size_t v = 0; v < nv; ++v) basis[m][v] = p.positions[v] - mesh.positions[v];
  }
  // The bump: vertices no muscle moves, lifted by 0.5 along z.
  std::vector<uint8_t> still(nv, 1);
  for (size_t m = 0; m < 6; ++m)
    for (size_t v = 0; v < nv; ++v)
      if (Length(basis[m][v]) > 0.f) still[v] = 0;
  const std::vector<float> truth = {1.6f, 0.f, -0.4f, 0.5f, 0.f, 0.f};
  MeshData target = mesh;
  size_t bumped = 0;
  for (size_t v = 0; v < nv; ++v) {
    for (size_t m = 0; m < 6; ++m) target.positions[v] = target.positions[v] + basis[m][v] * truth[m];
    if (still[v] && bumped < 40) target.positions[v].z += 0.5f, ++bumped;
  }
  ASSERT_EQ(bumped, 40u) << "the surface rig leaves too few vertices still";
  SolveOptions options;
  options.reach = true;
  SolveResult r;
  ASSERT_TRUE(SolveActivations(rig, mesh, target, options, &r, &diag)) << diag.Format();
  ASSERT_TRUE(r.has_reach);
  for (size_t m = 0; m < 6; ++m) EXPECT_NEAR(r.reach.activations[m], truth[m], 1e-3) << m;
  // The weights: 1 where the target moves more than 2% of its largest motion, else 0.25.
  double largest = 0.0;
  for (size_t v = 0; v < nv; ++v)
    largest = std::max(largest, double(Length(target.positions[v] - mesh.positions[v])));
  double motion = 0.0, bump = 0.0;
  for (size_t v = 0; v < nv; ++v) {
    const float3 d = target.positions[v] - mesh.positions[v];
    const double w = Length(d) > 0.02 * largest ? 1.0 : 0.25;
    motion += w * double(Dot(d, d));
    if (still[v] && Length(d) > 0.f) bump += w * 0.25;  // 0.5^2
  }
  EXPECT_NEAR(r.reach.motion, motion, 1e-6 * motion);
  EXPECT_NEAR(r.reach.residual, bump, 1e-4 * bump);  // the bump alone is left
  // Where no muscle reaches, the optimum stays at rest; elsewhere it is the target.
  for (size_t v = 0; v < nv; ++v) {
    const float3 want = still[v] ? mesh.positions[v] : target.positions[v];
    ASSERT_LT(Length(r.reach.posed[v] - want), 1e-3f) << v;
  }
  // The bounded solve cannot reach 1.6 or -0.4: it pays more, and stays in [0, 1].
  EXPECT_GT(r.reach.bounded_residual, r.reach.residual + 0.01 * motion);
  EXPECT_NEAR(r.reach.bounded_residual, r.linear_residual, 1e-6 * motion);  // layers are off
  for (float a : r.activations) EXPECT_TRUE(a >= 0.f && a <= 1.f) << a;
  // The height-first optimum: its motion and residual are the weighted squared components
  // along the neutral's vertex normals, its posed mesh is the basis at its activations, and
  // no activation (the whole-motion optimum's included) leaves less height error.
  const std::vector<float3> normals = ComputeVertexNormals(mesh);
  ASSERT_EQ(r.reach.height_activations.size(), 6u);
  double height_motion = 0.0, height_left = 0.0, height_left_whole = 0.0;
  for (size_t v = 0; v < nv; ++v) {
    const float3 d = target.positions[v] - mesh.positions[v];
    const double w = Length(d) > 0.02 * largest ? 1.0 : 0.25;
    float3 made = mesh.positions[v];
    for (size_t m = 0; m < 6; ++m) made = made + basis[m][v] * r.reach.height_activations[m];
    ASSERT_LT(Length(r.reach.height_posed[v] - made), 1e-3f) << v;
    const double t = Dot(normals[v], d), e = Dot(normals[v], made - target.positions[v]),
                 ew = Dot(normals[v], r.reach.posed[v] - target.positions[v]);
    height_motion += w * t * t;
    height_left += w * e * e;
    height_left_whole += w * ew * ew;
  }
  EXPECT_NEAR(r.reach.height_motion, height_motion, 1e-5 * height_motion);
  EXPECT_NEAR(r.reach.height_residual, height_left, 1e-5 * height_motion);
  EXPECT_LE(r.reach.height_residual, height_left_whole + 1e-6 * height_motion);
  EXPECT_LT(r.reach.height_residual, r.reach.height_motion);
  // Without the option, nothing is computed.
  SolveResult plain;
  ASSERT_TRUE(SolveActivations(rig, mesh, target, {}, &plain, &diag));
  EXPECT_FALSE(plain.has_reach);
  EXPECT_TRUE(plain.reach.activations.empty());
}

TEST(Solve, TheHeightWeightTradesSlidingForHeight) {
  // A target the muscles cannot make exactly (the basis at 0.6 and 0.3 plus a twist of every
  // moved point, part along the normal, part along the skin), solved twice with the layers
  // off (an exact bounded linear problem): each solution must be optimal for its own
  // objective against the other, computed here, and the height-weighted one must leave less
  // error along the normals.
  const MeshData mesh = MakeSurfaceMesh(41, 41, 100.f, 100.f, 8.f);
  const Rig rig = LinearSurfaceRig(4, mesh);
  ASSERT_GT(rig.muscle_count(), 0u);
  Diagnostics diag;
  const MeshData base = Posed(rig, mesh, {0.6f, 0.f, 0.3f, 0.f});
  const std::vector<float3> normals = ComputeVertexNormals(mesh);
  MeshData target = base;
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    const float3 d = base.positions[v] - mesh.positions[v];
    const float len = Length(d);
    if (len <= 0.f) continue;
    target.positions[v] = target.positions[v] + normals[v] * (0.4f * len * std::sin(0.3f * float(v))) +
                          float3{d.y, -d.x, 0.f} * 0.3f;
  }
  SolveOptions plain_options, height_options;
  height_options.height_weight = 16.0;
  SolveResult plain, height;
  ASSERT_TRUE(SolveActivations(rig, mesh, target, plain_options, &plain, &diag)) << diag.Format();
  ASSERT_TRUE(SolveActivations(rig, mesh, target, height_options, &height, &diag)) << diag.Format();
  double largest = 0.0;
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    largest = std::max(largest, double(Length(target.positions[v] - mesh.positions[v])));
  // objective(H) of a posed mesh: sum_v w_v (|e|^2 + (H - 1) (n . e)^2).
  auto objective = [&](const std::vector<float3>& posed, double h, double* along) {
    double sum = 0.0;
    *along = 0.0;
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      const double w = Length(target.positions[v] - mesh.positions[v]) > 0.02 * largest ? 1.0 : 0.25;
      const float3 e = posed[v] - target.positions[v];
      const double n = Dot(normals[v], e);
      sum += w * (double(Dot(e, e)) + (h - 1.0) * n * n);
      *along += w * n * n;
    }
    return sum;
  };
  double plain_along = 0, height_along = 0, unused = 0;
  const double plain_1 = objective(plain.posed, 1.0, &plain_along),
               height_1 = objective(height.posed, 1.0, &unused),
               plain_16 = objective(plain.posed, 16.0, &unused),
               height_16 = objective(height.posed, 16.0, &height_along);
  EXPECT_NEAR(height.residual, height_16, 1e-4 * height_16);  // the residual is its objective's
  EXPECT_NEAR(plain.residual, plain_1, 1e-4 * plain_1);
  EXPECT_LE(plain_1, height_1 * (1 + 1e-6));
  EXPECT_LE(height_16, plain_16 * (1 + 1e-6));
  EXPECT_LT(height_along, plain_along);  // strictly: the two solutions differ
  for (size_t m = 0; m < 4; ++m) EXPECT_TRUE(height.activations[m] >= 0.f && height.activations[m] <= 1.f);
  // A target the basis makes exactly comes back the same whatever the weight.
  SolveResult exact;
  ASSERT_TRUE(SolveActivations(rig, mesh, base, height_options, &exact, &diag));
  EXPECT_NEAR(exact.activations[0], 0.6f, 1e-4);
  EXPECT_NEAR(exact.activations[2], 0.3f, 1e-4);
  // Out of range: refused with the reason.
  for (double bad : {0.0, -1.0, 2e6, std::nan("")}) {
    SolveOptions o;
    o.height_weight = bad;
    Diagnostics d;
    EXPECT_FALSE(SolveActivations(rig, mesh, target, o, &plain, &d)) << bad;
    EXPECT_NE(d.Format().find("height weight: expected a number in [1e-6, 1e6]"), std::string::npos)
        << d.Format();
  }
}

TEST(Solve, RecoversSampleHeadActivationsWithEveryLayer) {
  // The default head rig with thickness, muscle wrinkles and curve wrinkles on: the linear
  // solve is off by what the layers add, the Gauss-Newton steps take it the rest of the way.
  const LoadedRig& loaded = SampleHeadRig();
  const Rig& rig = loaded.rig;
  std::vector<float> truth(rig.muscle_count(), 0.f);
  const std::pair<const char*, float> set[] = {{"zygomaticus_major_L", 0.6f},
                                              {"frontalis_major_R", 0.45f},
                                              {"corrugator_supercilii_L", 0.3f},
                                              {"depressor_anguli_oris_R", 0.8f}};
  for (const auto& [name, value] : set) {
    const int m = rig.FindMuscle(name);
    ASSERT_GE(m, 0) << name;
    truth[size_t(m)] = value;
  }
  const MeshData target = Posed(rig, loaded.mesh, truth);
  SolveOptions options;
  options.refine_steps = 5;
  SolveResult r;
  Diagnostics diag;
  ASSERT_TRUE(SolveActivations(rig, loaded.mesh, target, options, &r, &diag)) << diag.Format();
  for (uint32_t m = 0; m < rig.muscle_count(); ++m)
    EXPECT_NEAR(r.activations[m], truth[m], 1e-3) << rig.muscle_names()[m];
  EXPECT_LT(r.residual, r.linear_residual);  // the refinement steps helped
  EXPECT_GE(r.refine_steps_taken, 1);
}

TEST(Solve, MirrorTiesThePairsAndSubsetsKeepTheRestAtZero) {
  const LoadedRig& loaded = SampleHeadRig();
  const Rig& rig = loaded.rig;
  std::vector<float> truth(rig.muscle_count(), 0.f);
  truth[size_t(rig.FindMuscle("zygomaticus_major_L"))] = 0.5f;
  truth[size_t(rig.FindMuscle("zygomaticus_major_R"))] = 0.5f;
  const MeshData target = Posed(rig, loaded.mesh, truth);
  SolveOptions options;
  options.mirror = true;
  options.muscles = {uint32_t(rig.FindMuscle("zygomaticus_major_L")),
                     uint32_t(rig.FindMuscle("zygomaticus_major_R")),
                     uint32_t(rig.FindMuscle("risorius_L")), uint32_t(rig.FindMuscle("risorius_R"))};
  SolveResult r;
  Diagnostics diag;
  ASSERT_TRUE(SolveActivations(rig, loaded.mesh, target, options, &r, &diag)) << diag.Format();
  EXPECT_EQ(r.unknowns, 2u);  // two pairs
  for (uint32_t m = 0; m < rig.muscle_count(); ++m) EXPECT_NEAR(r.activations[m], truth[m], 1e-3);
  EXPECT_EQ(r.activations[size_t(rig.FindMuscle("zygomaticus_major_L"))],
            r.activations[size_t(rig.FindMuscle("zygomaticus_major_R"))]);
}

TEST(Solve, RefusesWhatItCannotSolve) {
  const MeshData mesh = MakeSurfaceMesh(11, 11, 100.f, 100.f, 8.f);
  const RigSpec spec = MakeSurfaceRigSpec(2, 100.f, 100.f, 8.f, 0.3f, 6.f);
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  const MeshData other = MakeSurfaceMesh(12, 11, 100.f, 100.f, 8.f);
  SolveResult r;
  auto fails_with = [&](const MeshData& target, const SolveOptions& o, const char* message) {
    Diagnostics d;
    EXPECT_FALSE(SolveActivations(rig, mesh, target, o, &r, &d)) << message;
    EXPECT_NE(d.Format().find(message), std::string::npos) << d.Format();
  };
  fails_with(other, {}, "target: has 132 vertices and 220 triangles; expected the rig mesh's "
                        "topology (121 vertices, 200 triangles");
  fails_with(mesh, {}, "target: does not move from the rig's rest shape");
  MeshData moved = mesh;
  moved.positions[60].z += 1.f;
  SolveOptions o;
  o.muscles = {7};
  fails_with(moved, o, "muscles: index 7 is out of range; the rig has 2 muscles");
  o = {};
  o.outside_weight = 2.f;
  fails_with(moved, o, "outside weight: expected a number in [0, 1]");
  o = {};
  o.region_threshold = 5.f;
  fails_with(moved, o, "region: no target vertex moves more than 5");
  // A rig built from another mesh of the same topology: its rest is not this neutral.
  MeshData shifted = mesh;
  for (float3& p : shifted.positions) p.x += 3.f;
  Diagnostics d;
  EXPECT_FALSE(SolveActivations(rig, shifted, shifted, {}, &r, &d));
  EXPECT_NE(d.Format().find("rest output does not start with its mesh's vertices"),
            std::string::npos) << d.Format();
}

TEST(SolveTool, WritesTheExpressionAndSaysHowClose) {
  const std::string dir = test::TempDir();
  const std::string rig = test::SourceDir() + "/assets/surface/surface.rig.json";
  test::ToolResult t = test::RunTool({"eval", rig, "--set", "zygomatic=0.6", "--set",
                                      "frontalis=0.3", "--out", dir + "/target.obj"});
  ASSERT_EQ(t.exit_code, 0) << t.output;
  t = test::RunTool({"solve", rig, "--target", dir + "/target.obj", "--out", dir + "/e.json",
                     "--posed", dir + "/posed.obj"});
  ASSERT_EQ(t.exit_code, 0) << t.output;
  EXPECT_NE(t.output.find("zygomatic                    0.6000"), std::string::npos) << t.output;
  EXPECT_NE(t.output.find("frontalis                    0.3000"), std::string::npos) << t.output;
  std::ifstream in(dir + "/e.json");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("\"format\": \"mimetic-expression\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"name\": \"target\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"zygomatic\": 0.6"), std::string::npos) << text;
  MeshData posed, target;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(dir + "/posed.obj", "", &posed, &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(dir + "/target.obj", "", &target, &diag));
  ASSERT_EQ(posed.vertex_count(), target.vertex_count());
  double far = 0;
  for (size_t v = 0; v < posed.vertex_count(); ++v)
    far = std::max(far, double(Length(posed.positions[v] - target.positions[v])));
  EXPECT_LT(far, 1e-3);

  // Mistakes: exit 1 with the reason, 2 for usage.
  t = test::RunTool({"solve", rig, "--target", dir + "/target.obj", "--out", dir + "/x.json",
                     "--muscles", "zygomatic,nope"});
  EXPECT_EQ(t.exit_code, 1);
  EXPECT_NE(t.output.find("unknown muscle 'nope'; the rig has: zygomatic, frontalis"),
            std::string::npos) << t.output;
  t = test::RunTool({"solve", rig, "--target", test::SourceDir() + "/assets/head/sample_head.glb",
                     "--out", dir + "/x.json"});
  EXPECT_EQ(t.exit_code, 1);
  EXPECT_NE(t.output.find("expected the rig mesh's topology"), std::string::npos) << t.output;
  t = test::RunTool({"solve", rig, "--out", dir + "/x.json"});
  EXPECT_EQ(t.exit_code, 2);
  t = test::RunTool({"solve", rig, "--target", dir + "/target.obj", "--out", dir + "/x.json",
                     "--steps", "2.5"});
  EXPECT_EQ(t.exit_code, 2);
  t = test::RunTool({"solve", rig, "--target", dir + "/target.obj", "--out", dir + "/x.json",
                     "--height-weight", "0"});
  EXPECT_EQ(t.exit_code, 2);
  EXPECT_NE(t.output.find("--height-weight '0': expected a number in [1e-6, 1e6]"),
            std::string::npos) << t.output;
  // A target the rig makes comes back whatever the weight.
  t = test::RunTool({"solve", rig, "--target", dir + "/target.obj", "--out", dir + "/h.json",
                     "--height-weight", "16"});
  ASSERT_EQ(t.exit_code, 0) << t.output;
  EXPECT_NE(t.output.find("zygomatic                    0.6000"), std::string::npos) << t.output;
}

}  // namespace
}  // namespace mimetic
