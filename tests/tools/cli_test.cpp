// Runs the built `mimetic` tool: help, info, validate, eval, and its errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "io/rig_file.h"
#include "muscles/offline/waters.h"
#include "rig/offline/rig_spec.h"
#include "test_support.h"

namespace mimetic {
namespace {

using test::RunTool;

std::string SurfaceRig() { return test::SourceDir() + "/assets/surface/surface.rig.json"; }

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

TEST(Cli, HelpListsEveryCommandAndEachCommandHasHelp) {
  const auto top = RunTool({"--help"});
  EXPECT_EQ(top.exit_code, 0);
  for (const char* cmd : {"info", "validate", "eval", "make-surface"}) {
    EXPECT_TRUE(Contains(top.output, cmd)) << cmd;
    const auto r = RunTool({cmd, "--help"});
    EXPECT_EQ(r.exit_code, 0) << cmd;
    EXPECT_TRUE(Contains(r.output, std::string("usage: mimetic ") + cmd)) << r.output;
  }
}

TEST(Cli, UnknownCommandAndMissingArgumentsAreUsageErrors) {
  EXPECT_EQ(RunTool({"frobnicate"}).exit_code, 2);
  EXPECT_EQ(RunTool({}).exit_code, 2);
  EXPECT_EQ(RunTool({"info"}).exit_code, 2);
  EXPECT_EQ(RunTool({"eval", SurfaceRig()}).exit_code, 2);                        // no --out
  EXPECT_EQ(RunTool({"eval", SurfaceRig(), "--out", "x.stl"}).exit_code, 2);      // bad format
  EXPECT_EQ(RunTool({"info", SurfaceRig(), "--bogus"}).exit_code, 2);
}

TEST(Cli, InfoReportsTheSurfaceRig) {
  const auto r = RunTool({"info", SurfaceRig()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // 41 x 41 grid: 1681 vertices, 40 * 40 * 2 = 3200 triangles; two muscles.
  EXPECT_TRUE(Contains(r.output, "vertices:   1681")) << r.output;
  EXPECT_TRUE(Contains(r.output, "triangles:  3200")) << r.output;
  EXPECT_TRUE(Contains(r.output, "muscles:    2")) << r.output;
  EXPECT_TRUE(Contains(r.output, "zygomatic")) << r.output;
  EXPECT_TRUE(Contains(r.output, "frontalis")) << r.output;

  // Points that can move in a frame: those a muscle reaches (direct formulas) and those
  // sharing a triangle with one (their area ratio, hence thickness displacement, changes).
  RigSpec spec;
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(LoadRigSpec(SurfaceRig(), &spec, &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(spec.mesh_path, "", &mesh, &diag)) << diag.Format();
  std::vector<bool> moved(mesh.vertex_count(), false), active(mesh.vertex_count(), false);
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    for (const MuscleSpec& m : spec.muscles)
      if (MuscleDisplacement(m, mesh.positions[v], m.strength) != float3{}) moved[v] = true;
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t* i = &mesh.indices[3 * t];
    if (moved[i[0]] || moved[i[1]] || moved[i[2]]) active[i[0]] = active[i[1]] = active[i[2]] = true;
  }
  const size_t count = std::count(active.begin(), active.end(), true);
  EXPECT_TRUE(Contains(r.output, "per frame:  " + std::to_string(count) + " of 1681 points can move"))
      << "expected " << count << "\n" << r.output;
}

TEST(Cli, InfoSaysWhereAMusclesWrinklesOpenFully) {  // docs/model.md §6, the gate
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadRigSpec(SurfaceRig(), &spec, &diag)) << diag.Format();
  spec.muscle_wrinkles.resize(spec.muscles.size());
  MuscleWrinkleSpec w;
  w.depth = 0.5f;
  w.lambda_w = 0.2f;
  spec.muscle_wrinkles[0] = w;  // no gate
  w.gate = 0.4f;
  spec.muscle_wrinkles[1] = w;
  const std::string dir = test::TempDir();
  spec.file = dir + "/gated.rig.json";
  ASSERT_TRUE(SaveRigSpec(spec.file, spec, &diag)) << diag.Format();
  const auto r = RunTool({"info", spec.file});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  size_t lines_with_wrinkles = 0, gated = 0;
  for (size_t at = 0; (at = r.output.find("wrinkles on ", at)) != std::string::npos; ++at) {
    ++lines_with_wrinkles;
    const size_t end = r.output.find('\n', at);
    gated += r.output.substr(at, end - at).find(", full from activation 0.4)") != std::string::npos;
  }
  EXPECT_EQ(lines_with_wrinkles, 2u) << r.output;
  EXPECT_EQ(gated, 1u) << r.output;
}

TEST(Cli, InfoWarnsAboutAMuscleThatMovesAlmostNothing) {
  // The surface rig plus a linear muscle with a 6 mm zone: it moves a handful of the grid's
  // vertices (counted here from Waters' formula directly), fewer than the 50 `info` asks for.
  RigSpec spec;
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(LoadRigSpec(SurfaceRig(), &spec, &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(spec.mesh_path, "", &mesh, &diag)) << diag.Format();
  MuscleSpec tiny = spec.muscles[0];
  ASSERT_EQ(tiny.type, MuscleType::kLinear);
  tiny.name = "tiny";
  float3 p0 = mesh.positions[0];  // the grid vertex nearest (10, 10): the zone's centre
  for (const float3& p : mesh.positions)
    if (std::hypot(p.x - 10.f, p.y - 10.f) < std::hypot(p0.x - 10.f, p0.y - 10.f)) p0 = p;
  tiny.linear.attachment = p0 + float3{3.f, 3.f, -1.f};
  tiny.linear.insertion = p0 + float3{-3.f, -3.f, 1.f};
  tiny.linear.falloff_start = 3.f;
  tiny.linear.falloff_end = 6.f;
  spec.muscles.push_back(tiny);
  spec.muscle_wrinkles.resize(spec.muscles.size());
  const std::string dir = test::TempDir();
  spec.file = dir + "/tiny.rig.json";
  ASSERT_TRUE(SaveRigSpec(spec.file, spec, &diag)) << diag.Format();
  size_t count = 0;
  for (const float3& p : mesh.positions) count += MuscleDisplacement(tiny, p, tiny.strength) != float3{};
  ASSERT_GT(count, 0u);
  ASSERT_LT(count, 50u);
  const auto r = RunTool({"info", spec.file});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "warning: muscle 'tiny' moves only " + std::to_string(count) +
                                     " of the mesh's 1681 vertices"))
      << "expected " << count << "\n" << r.output;
  EXPECT_FALSE(Contains(r.output, "muscle 'zygomatic' moves only")) << r.output;
  EXPECT_FALSE(Contains(r.output, "muscle 'frontalis' moves only")) << r.output;
}

TEST(Cli, EvalSetsBothSidesFromOneName) {
  // A rig with frontalis_L and frontalis_R: --set frontalis=0.5 equals setting both.
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadRigSpec(SurfaceRig(), &spec, &diag)) << diag.Format();
  spec.muscles[0].name = "pull_L";
  spec.muscles[1].name = "pull_R";
  const std::string dir = test::TempDir();
  spec.file = dir + "/pair.rig.json";
  ASSERT_TRUE(SaveRigSpec(spec.file, spec, &diag)) << diag.Format();
  auto r = RunTool({"eval", spec.file, "--set", "pull=0.5", "--out", dir + "/one.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunTool({"eval", spec.file, "--set", "pull_L=0.5", "--set", "pull_R=0.5", "--out",
               dir + "/two.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  MeshData one, two, rest;
  ASSERT_TRUE(ImportMesh(dir + "/one.obj", "", &one, &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(dir + "/two.obj", "", &two, &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(spec.mesh_path, "", &rest, &diag)) << diag.Format();
  EXPECT_EQ(one.positions, two.positions);
  EXPECT_NE(one.positions, rest.positions);
}

TEST(Cli, ValidateAcceptsGoodAndRejectsBadRigs) {
  const auto ok = RunTool({"validate", SurfaceRig()});
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(Contains(ok.output, "ok")) << ok.output;

  const std::string dir = test::TempDir();
  const std::string bad = dir + "/bad.rig.json";
  std::ofstream(bad) << R"({"format":"mimetic-rig","version":1,"mesh":{"path":"nowhere.obj"},
    "units":"mm","muscles":[{"name":"a","type":"sphincter","strength":1}]})";
  const auto r = RunTool({"validate", bad});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.output, "muscles[0].type")) << r.output;
  EXPECT_TRUE(Contains(r.output, "sphincter")) << r.output;

  const std::string missing_mesh = dir + "/missing.rig.json";
  std::ofstream(missing_mesh) << R"({"format":"mimetic-rig","version":1,
    "mesh":{"path":"nowhere.obj"},"units":"mm","muscles":[]})";
  const auto m = RunTool({"validate", missing_mesh});
  EXPECT_EQ(m.exit_code, 1);
  EXPECT_TRUE(Contains(m.output, "nowhere.obj")) << m.output;

  const auto none = RunTool({"validate", dir + "/does-not-exist.rig.json"});
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_TRUE(Contains(none.output, "does-not-exist.rig.json")) << none.output;
}

// The posed mesh equals rest + the direct Waters formulas (a second method).
TEST(Cli, EvalWritesThePosedMesh) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadRigSpec(SurfaceRig(), &spec, &diag)) << diag.Format();
  MeshData rest;
  ASSERT_TRUE(ImportMesh(spec.mesh_path, "", &rest, &diag)) << diag.Format();

  for (const char* ext : {".obj", ".glb"}) {
    const std::string out = test::TempDir() + "/sub/posed" + ext;
    // Muscles only: the thickness layer is checked below and in tests/wrinkles.
    const auto r = RunTool({"eval", SurfaceRig(), "--set", "zygomatic=0.8", "--set",
                            "frontalis=0.5", "--out", out, "--no-thickness"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(Contains(r.output, "wrote " + out)) << r.output;
    MeshData posed;
    ASSERT_TRUE(ImportMesh(out, "", &posed, &diag)) << diag.Format();
    ASSERT_EQ(posed.vertex_count(), rest.vertex_count());
    ASSERT_EQ(posed.indices, rest.indices);
    size_t moved = 0;
    for (size_t v = 0; v < rest.vertex_count(); ++v) {
      const float3 p = rest.positions[v];
      const float3 expect = p + MuscleDisplacement(spec.muscles[0], p, 0.8f * spec.muscles[0].strength) +
                            MuscleDisplacement(spec.muscles[1], p, 0.5f * spec.muscles[1].strength);
      ASSERT_NEAR(posed.positions[v].x, expect.x, 1e-4f) << ext << " vertex " << v;
      ASSERT_NEAR(posed.positions[v].y, expect.y, 1e-4f);
      ASSERT_NEAR(posed.positions[v].z, expect.z, 1e-4f);
      moved += Length(expect - p) > 0.01f;
    }
    EXPECT_GT(moved, 100u) << ext;
  }
}

// With the thickness layer (the surface rig has h = 3 mm): points no muscle reaches keep r = 1
// and do not move; points a muscle compresses move along the normal, outward (r < 1).
TEST(Cli, EvalAppliesTheThicknessLayer) {
  const std::string dir = test::TempDir();
  const auto with = RunTool({"eval", SurfaceRig(), "--set", "zygomatic=1", "--out", dir + "/a.glb"});
  const auto without = RunTool({"eval", SurfaceRig(), "--set", "zygomatic=1", "--out",
                                dir + "/b.glb", "--no-thickness"});
  ASSERT_EQ(with.exit_code, 0) << with.output;
  ASSERT_EQ(without.exit_code, 0) << without.output;
  EXPECT_TRUE(Contains(with.output, "layers: muscles, thickness")) << with.output;
  EXPECT_TRUE(Contains(without.output, "thickness switched off")) << without.output;
  MeshData a, b;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(dir + "/a.glb", "", &a, &diag));
  ASSERT_TRUE(ImportMesh(dir + "/b.glb", "", &b, &diag));
  ASSERT_EQ(b.normals.size(), b.vertex_count());
  size_t differ = 0;
  for (size_t v = 0; v < a.vertex_count(); ++v) {
    const float3 d = a.positions[v] - b.positions[v];
    // The thickness displacement is along the normal, at most 19 h = 57 mm (r_min = 0.05).
    EXPECT_LT(Length(d), 57.f);
    if (Length(d) > 1e-4f) {
      ++differ;
      EXPECT_GT(std::fabs(Dot(d, b.normals[v])), 0.9f * Length(d)) << v;
    }
  }
  EXPECT_GT(differ, 10u);
  EXPECT_LT(differ, a.vertex_count() / 2);
}

TEST(Cli, EvalRejectsUnknownMusclesAndBadValues) {
  const std::string out = test::TempDir() + "/x.obj";
  struct Case {
    std::string set, expect;
  } cases[] = {
      {"zygomatik=0.5", "unknown muscle 'zygomatik'; closest: zygomatic"},
      {"zygomatic=abc", "not a finite number"},
      {"zygomatic=nan", "not a finite number"},
      {"zygomatic=1.5", "outside [0, 1]"},
      {"zygomatic=-0.1", "outside [0, 1]"},
      {"zygomatic", "expected NAME=VALUE"},
      {"zygomatic=", "not a finite number"},
  };
  for (const Case& c : cases) {
    const auto r = RunTool({"eval", SurfaceRig(), "--set", c.set, "--out", out});
    EXPECT_EQ(r.exit_code, 1) << c.set;
    EXPECT_TRUE(Contains(r.output, c.expect)) << c.set << "\n" << r.output;
  }
  // A partial name suggests the names that contain it.
  const auto partial = RunTool({"eval", SurfaceRig(), "--set", "zygo=0.5", "--out", out});
  EXPECT_EQ(partial.exit_code, 1);
  EXPECT_TRUE(Contains(partial.output, "closest: zygomatic")) << partial.output;
  const auto twice = RunTool({"eval", SurfaceRig(), "--set", "frontalis=0.1", "--set",
                              "frontalis=0.2", "--out", out});
  EXPECT_EQ(twice.exit_code, 1);
  EXPECT_TRUE(Contains(twice.output, "more than once")) << twice.output;
  std::ifstream written(out);
  EXPECT_FALSE(written.good()) << "nothing is written on error";
}

TEST(Cli, MakeSurfaceWritesTheGridItSays) {
  const std::string out = test::TempDir() + "/s.obj";
  const auto r = RunTool({"make-surface", "--out", out, "--columns", "5", "--rows", "4"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(out, "", &mesh, &diag)) << diag.Format();
  EXPECT_EQ(mesh.vertex_count(), 20u);
  EXPECT_EQ(mesh.triangle_count(), 4u * 3u * 2u);
  EXPECT_EQ(RunTool({"make-surface", "--out", out, "--columns", "1"}).exit_code, 2);
  EXPECT_EQ(RunTool({"make-surface", "--out", out, "--width", "abc"}).exit_code, 2);
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

double CreaseNumber(const std::string& output) {
  const size_t at = output.find("crease number: ");
  return at == std::string::npos ? -1.0 : std::atof(output.c_str() + at + 15);
}

TEST(Cli, CreasesComparesTheFalloffsOnOneRig) {
  const auto waters = test::RunTool({"creases", SurfaceRig(), "--falloff", "waters"});
  ASSERT_EQ(waters.exit_code, 0) << waters.output;
  const auto smooth = test::RunTool({"creases", SurfaceRig(), "--falloff", "smooth"});
  ASSERT_EQ(smooth.exit_code, 0) << smooth.output;
  EXPECT_GT(CreaseNumber(waters.output), 0.0) << waters.output;
  EXPECT_LT(CreaseNumber(smooth.output), CreaseNumber(waters.output)) << smooth.output;
  EXPECT_NE(smooth.output.find("zygomatic                    smooth"), std::string::npos)
      << smooth.output;
  EXPECT_EQ(test::RunTool({"creases", SurfaceRig(), "--falloff", "cubic"}).exit_code, 2);
  EXPECT_EQ(test::RunTool({"creases", SurfaceRig(), "--rings", "1.5"}).exit_code, 2);
  const auto shape = test::RunTool({"creases", SurfaceRig(), "--min-shape", "0.9"});
  EXPECT_EQ(shape.exit_code, 2);
  EXPECT_NE(shape.output.find("--min-shape '0.9': expected a number in [0, 0.5]"),
            std::string::npos)
      << shape.output;
  // The surface's triangles are half squares (altitude / longest edge 0.5): none is a sliver,
  // so leaving slivers out or not gives the same number.
  const auto all = test::RunTool({"creases", SurfaceRig(), "--falloff", "waters", "--min-shape", "0"});
  ASSERT_EQ(all.exit_code, 0) << all.output;
  EXPECT_EQ(CreaseNumber(all.output), CreaseNumber(waters.output));
  EXPECT_NE(waters.output.find(" 0 sliver edges under 0.05 left out"), std::string::npos)
      << waters.output;
}

}  // namespace
}  // namespace mimetic
