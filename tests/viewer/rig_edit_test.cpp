// Editing the rig in the viewer (viewer/core/rig_edit.h, Session's rig edits, RigRebuilder):
// a muscle's strength doubled doubles its muscle-only displacement (docs/model.md §2: the
// displacement is exactly linear in k = a * strength); after an edit and its rebuild the
// session evaluates exactly what a rig built directly from the saved rig file gives; undo
// (one edit, or all of a seeded random sequence of edits made without waiting) gives back the
// spec's text and the evaluated output bit for bit; the rebuild runs on another thread (the
// edit returns while a hook holds the build) and a newer edit supersedes a waiting one; a
// build that fails keeps the last good rig; bad values are refused naming the field; a drag
// merges into one undo step; the script lines; Regenerate maps (MapJob, off the UI thread)
// writes the bytes `mimetic texture` writes for the edited rig.
#include "viewer/core/rig_edit.h"

#include <atomic>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "io/rig_file.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "test_support.h"
#include "viewer/core/map_job.h"
#include "viewer/core/script.h"
#include "viewer/core/session.h"

namespace mimetic::viewer {
namespace {

// The surface rig (a 41 x 41 grid, 100 mm, uvs [0, 1]^2) with a wrinkle block on the linear
// muscle, one curve wrinkle across the middle and a fine_scale block, in a folder of its own.
struct Fixture {
  std::string dir, rig;
  explicit Fixture(const std::string& name) {
    dir = test::TempDir() + "/rig_edit_" + name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    rig = dir + "/edit.rig.json";
    std::ofstream(rig) << R"({"format": "mimetic-rig", "version": 1,
      "mesh": {"path": ")" << test::SourceDir() << R"(/assets/surface/surface.obj"},
      "units": "mm", "thickness": {"type": "constant", "value": 3.0},
      "muscles": [
        {"name": "zygomatic", "type": "linear", "strength": 8.0, "attachment": [35.0, 35.0, -2.0],
         "insertion": [-10.0, -10.0, 9.0], "zone_angle_deg": 35.0, "falloff_start": 30.0,
         "falloff_end": 60.0, "wrinkles": {"lambda_w": 0.5, "count": 3, "depth": 0.4, "shape": 0.5,
         "phi_c_deg": 10}},
        {"name": "frontalis", "type": "sheet", "strength": 6.0,
         "attachment": [[-30.0, 45.0, 0.0], [30.0, 45.0, 0.0]],
         "insertion": [[-30.0, 0.0, 10.0], [30.0, 0.0, 10.0]], "length": 45.0, "width": 60.0,
         "falloff_start": 15.0}],
      "curve_wrinkles": [{"name": "furrow", "control": [[0.3, 0.5], [0.4, 0.52], [0.6, 0.52], [0.7, 0.5]],
         "depth": 1.0, "width": 4.0, "profile": "bando", "modulation": "area", "rest_amplitude": 0.0}],
      "fine_scale": {"fields": [
         {"name": "lines", "vectors": [{"vertex": 820, "vector": [0.5, 0, 0]}, {"vertex": 700, "vector": [0.4, 0.1, 0]}]},
         {"name": "cross", "vectors": [{"vertex": 820, "vector": [0, 0.3, 0]}]}]}
    })";
  }
};

std::string SpecText(const Session& s) { return RigSpecText(*s.rig_spec(), "/"); }

// The positions and normals the session evaluates for its pose, as bytes.
std::string Output(Session* s) {
  EXPECT_TRUE(s->Evaluate(Overlay::kNone));
  std::string bytes(reinterpret_cast<const char*>(s->positions().data()),
                    s->positions().size() * sizeof(float3));
  bytes.append(reinterpret_cast<const char*>(s->normals().data()),
               s->normals().size() * sizeof(float3));
  return bytes;
}

void Load(Session* s, const Fixture& f) {
  ASSERT_TRUE(s->LoadRigFile(f.rig)) << (s->messages().empty() ? "" : s->messages().back().text);
  ASSERT_NE(s->rig_spec(), nullptr);
  s->activations = {0.6f, 0.4f};
}

bool Script(Session* s, const std::string& text, std::string* error) {
  return RunScript(text, "test", s, ScriptHooks{}, error);
}

TEST(ViewerRigEdit, DoublingStrengthDoublesTheMuscleOnlyDisplacement) {
  Fixture f("double");
  Session s(1);
  Load(&s, f);
  s.layers = SkinLayers{false, false, false};  // the muscles alone (docs/model.md §1 steps 1-2)
  s.activations = {0.5f, 0.f};
  ASSERT_TRUE(s.Evaluate(Overlay::kNone));
  const std::vector<float3> rest = s.rest_positions(), once = s.positions();
  std::string error;
  ASSERT_TRUE(Script(&s, "muscle zygomatic strength 16", &error)) << error;
  EXPECT_FALSE(s.rig_stale());
  EXPECT_EQ(s.loaded().spec.muscles[0].strength, 16.f);  // the shown rig is the rebuilt one
  ASSERT_TRUE(s.Evaluate(Overlay::kNone));
  ASSERT_EQ(s.positions().size(), once.size());
  double largest = 0.0;
  for (size_t v = 0; v < once.size(); ++v) {
    const float3 d1 = once[v] - rest[v], d2 = s.positions()[v] - rest[v];
    largest = std::max(largest, double(Length(d1)));
    EXPECT_NEAR(d2.x, 2.f * d1.x, 1e-4f) << v;
    EXPECT_NEAR(d2.y, 2.f * d1.y, 1e-4f) << v;
    EXPECT_NEAR(d2.z, 2.f * d1.z, 1e-4f) << v;
  }
  EXPECT_GT(largest, 0.5);  // the muscle moves the skin by more than half a millimetre
}

TEST(ViewerRigEdit, RebuiltRigEvaluatesAsTheRigBuiltFromItsSavedFile) {
  Fixture f("saved");
  Session s(1);
  Load(&s, f);
  std::string error;
  ASSERT_TRUE(Script(&s, R"(muscle zygomatic insertion -12 -8 9.5
muscle zygomatic zone_angle 40
muscle frontalis width 55
muscle zygomatic wrinkles.depth 0.6
curve furrow point 1 0.42 0.55
curve furrow depth 1.5
direction lines 700 0 1 0 0.8
save-rig )" + f.dir + "/edited.rig.json",
                     &error))
      << error;
  const std::string shown = Output(&s);
  LoadedRig direct;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(f.dir + "/edited.rig.json", &direct, &diag)) << diag.Format();
  EXPECT_EQ(direct.spec.curve_wrinkles[0].spec.control[1].x, 0.42f);
  EXPECT_EQ(direct.spec.muscles[0].linear.insertion.y, -8.f);
  MeshData posed;
  ASSERT_TRUE(PosedMesh(direct.rig, s.activations, s.layers, &posed));
  ASSERT_EQ(posed.positions.size(), s.positions().size());
  std::string bytes(reinterpret_cast<const char*>(posed.positions.data()),
                    posed.positions.size() * sizeof(float3));
  bytes.append(reinterpret_cast<const char*>(posed.normals.data()),
               posed.normals.size() * sizeof(float3));
  EXPECT_TRUE(bytes == shown);
  EXPECT_FALSE(s.rig_dirty());  // saved
}

TEST(ViewerRigEdit, UndoGivesBackTheSpecAndTheOutputBitForBit) {
  Fixture f("undo");
  Session s(1);
  Load(&s, f);
  const std::string text0 = SpecText(s), out0 = Output(&s);
  std::string error;
  ASSERT_TRUE(Script(&s, "muscle zygomatic strength 9.5\ncurve furrow width 5", &error)) << error;
  EXPECT_NE(SpecText(s), text0);
  EXPECT_NE(Output(&s), out0);
  EXPECT_TRUE(s.rig_dirty());
  ASSERT_TRUE(Script(&s, "undo\nundo", &error)) << error;
  EXPECT_EQ(SpecText(s), text0);
  EXPECT_TRUE(Output(&s) == out0);
  EXPECT_FALSE(s.rig_dirty());
  ASSERT_TRUE(Script(&s, "redo", &error)) << error;
  EXPECT_EQ(s.rig_spec()->muscles[0].strength, 9.5f);
}

// Seeded random edits of every kind, made without waiting for their rebuilds (they coalesce),
// then undo them all: the spec's text and the output are the original's.
TEST(ViewerRigEdit, UndoOfARandomSequenceRestoresTheRigBitForBit) {
  Fixture f("random");
  Session s(1);
  Load(&s, f);
  const std::string text0 = SpecText(s), out0 = Output(&s);
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  int done = 0;
  for (int i = 0; i < 40; ++i) {
    const RigSpec& spec = *s.rig_spec();
    const MuscleSpec& z = spec.muscles[0];
    const MuscleSpec& fr = spec.muscles[1];
    CommandPtr c;
    std::string error;
    switch (rng() % 9) {
      case 0: c = MakeMuscleValueEdit(spec, 0, "strength", {z.strength * (0.5f + u(rng))}, &error); break;
      case 1: c = MakeMuscleValueEdit(spec, 0, "insertion", {z.linear.insertion.x + u(rng), -10.f, 9.f}, &error); break;
      case 2: c = MakeMuscleValueEdit(spec, 0, "falloff_end", {z.linear.falloff_start + 5.f + 40.f * u(rng)}, &error); break;
      case 3: c = MakeMuscleValueEdit(spec, 1, "attachment", {1.f, 30.f, 45.f + u(rng), 0.f}, &error); break;
      case 4: c = MakeMuscleValueEdit(spec, 1, "falloff_start", {fr.sheet.falloff_start * (0.8f + 0.4f * u(rng))}, &error); break;
      case 5: c = MakeCurvePointEdit(spec, 0, int(rng() % 4), {0.3f + 0.4f * u(rng), 0.4f + 0.2f * u(rng)}, &error); break;
      case 6: c = MakeCurveEdit(spec, "furrow", "depth", {std::to_string(0.5f + u(rng))}, &error); break;
      case 7: c = MakeDirectionEdit(spec, s.mesh_vertex_count(), "cross", 600 + rng() % 400,
                                    {"1", std::to_string(u(rng)), "0", std::to_string(0.1f + 0.8f * u(rng))}, &error); break;
      default: c = MakeMuscleValueEdit(spec, 0, "wrinkles.count", {float(1 + rng() % 5)}, &error); break;
    }
    ASSERT_NE(c, nullptr) << error;
    if (s.Edit(std::move(c), &error)) ++done;
  }
  EXPECT_GT(done, 30);
  ASSERT_TRUE(s.WaitRigRebuild());
  EXPECT_NE(SpecText(s), text0);
  while (s.Undo()) {
  }
  ASSERT_TRUE(s.WaitRigRebuild());
  EXPECT_EQ(SpecText(s), text0);
  EXPECT_TRUE(Output(&s) == out0);
}

// A hook holds each build until the test releases it.
struct Gate {
  std::mutex m;
  std::condition_variable cv;
  bool open = false;
  int builds = 0;
  std::thread::id test_thread = std::this_thread::get_id(), build_thread;
  void Hook() {
    std::unique_lock<std::mutex> lock(m);
    ++builds;
    build_thread = std::this_thread::get_id();
    if (build_thread == test_thread) return;  // a build on the caller's thread: never block it
    cv.notify_all();
    cv.wait(lock, [this] { return open; });
  }
  void WaitForBuilds(int n) {
    std::unique_lock<std::mutex> lock(m);
    cv.wait(lock, [&] { return builds >= n; });
  }
  void Open() {
    std::lock_guard<std::mutex> lock(m);
    open = true;
    cv.notify_all();
  }
};

// A session with the fixture's rig loaded whose rebuilds wait at `gate` (declared first, so
// the session, and any build it still holds, goes before the gate does).
struct HeldSession {
  explicit HeldSession(const char* name) : f(name), s(1) {
    Load(&s, f);
    s.SetRebuildHook([this] { gate.Hook(); });
  }
  Gate gate;
  Fixture f;
  Session s;
};

TEST(ViewerRigEdit, TheEditReturnsWhileItsRebuildRunsOnAnotherThread) {
  HeldSession held("thread");
  Session& s = held.s;
  Gate& gate = held.gate;
  const std::string out0 = Output(&s);
  std::string error;
  ASSERT_TRUE(s.Edit(MakeMuscleEdit(*s.rig_spec(), "zygomatic", "strength", {"12"}, &error), &error))
      << error;
  // The build is held by the hook: the edit came back without it, the last good rig is shown.
  gate.WaitForBuilds(1);
  EXPECT_NE(gate.build_thread, gate.test_thread);
  EXPECT_TRUE(s.rig_rebuilding());
  EXPECT_TRUE(s.rig_stale());
  // Held before BuildRig starts: queued at 0 (BuildRig's own stages: rig_builder_test).
  EXPECT_EQ(s.rig_rebuild_progress(), 0.f);
  EXPECT_STREQ(s.rig_rebuild_stage(), "queued");
  EXPECT_FALSE(s.PollRigRebuild());
  EXPECT_TRUE(Output(&s) == out0);
  EXPECT_EQ(s.rig_spec()->muscles[0].strength, 12.f);  // the spec has the edit already
  EXPECT_EQ(s.loaded().spec.muscles[0].strength, 8.f);  // the shown rig does not
  // Two more edits while it is held: they coalesce into one build, the held one is dropped.
  ASSERT_TRUE(s.Edit(MakeMuscleEdit(*s.rig_spec(), "zygomatic", "strength", {"14"}, &error), &error));
  ASSERT_TRUE(s.Edit(MakeMuscleEdit(*s.rig_spec(), "zygomatic", "strength", {"16"}, &error), &error));
  gate.Open();
  ASSERT_TRUE(s.WaitRigRebuild());
  EXPECT_EQ(s.rig_rebuild_progress(), 1.f);
  EXPECT_STREQ(s.rig_rebuild_stage(), "done");
  EXPECT_EQ(gate.builds, 2);
  EXPECT_EQ(s.loaded().spec.muscles[0].strength, 16.f);
  EXPECT_FALSE(s.rig_stale());
}

TEST(ViewerRigEdit, LoadingARigDropsTheRebuildOfTheOldOne) {
  HeldSession held("reload");
  Session& s = held.s;
  Gate& gate = held.gate;
  const Fixture& f = held.f;
  std::string error;
  ASSERT_TRUE(s.Edit(MakeMuscleEdit(*s.rig_spec(), "zygomatic", "strength", {"12"}, &error), &error));
  gate.WaitForBuilds(1);
  ASSERT_TRUE(s.LoadRigFile(f.rig));  // while the edit's build is held
  EXPECT_FALSE(s.rig_stale());
  EXPECT_EQ(s.history().undo_size(), 0u);
  gate.Open();
  EXPECT_TRUE(s.WaitRigRebuild());
  EXPECT_EQ(s.loaded().spec.muscles[0].strength, 8.f);  // the held build was not swapped in
  EXPECT_EQ(s.rig_spec()->muscles[0].strength, 8.f);
  EXPECT_FALSE(s.rig_dirty());
}

TEST(ViewerRigEdit, AnAutosavedRigIsRecoveredInANewSession) {
  Fixture f("autosave");
  std::string text, out;
  {
    Session s(1);
    Load(&s, f);
    std::string error;
    ASSERT_TRUE(Script(&s, "muscle zygomatic strength 11\ncurve furrow depth 1.75\nautosave", &error)) << error;
    EXPECT_TRUE(s.rig_dirty());  // autosaved, not saved
    text = SpecText(s);
    out = Output(&s);
  }
  Session t(1);
  Load(&t, f);
  EXPECT_EQ(t.rig_spec()->muscles[0].strength, 8.f);  // the file itself is as it was
  ASSERT_EQ(t.PendingAutosaves(), std::vector<std::string>{AutosavePath(f.rig)});
  EXPECT_EQ(t.RecoverAutosaves(), 1);
  ASSERT_TRUE(t.WaitRigRebuild());
  EXPECT_TRUE(t.rig_dirty());
  EXPECT_EQ(SpecText(t), text);
  EXPECT_TRUE(Output(&t) == out);
  std::string error;
  ASSERT_TRUE(t.SaveRigFile("", &error)) << error;  // a save removes the autosave
  EXPECT_TRUE(t.PendingAutosaves().empty());
}

TEST(ViewerRigEdit, AFailedBuildKeepsTheLastGoodRig) {
  Fixture f("fail");
  Session s(1);
  Load(&s, f);
  const std::string out0 = Output(&s);
  std::string error;
  // The file's reader takes any strength >= 0; BuildRig refuses one past 10 bounding-box
  // diagonals (rig_builder.h kMaxLengthFactor), naming the key.
  EXPECT_FALSE(Script(&s, "muscle zygomatic strength 1e7", &error));
  EXPECT_NE(error.find("muscles[0].strength"), std::string::npos) << error;
  EXPECT_NE(error.find("last good rig"), std::string::npos) << error;
  EXPECT_TRUE(s.rig_stale());
  EXPECT_TRUE(Output(&s) == out0);
  ASSERT_TRUE(Script(&s, "undo", &error)) << error;  // its undo builds the old spec again
  EXPECT_FALSE(s.rig_stale());
}

// A build refused at once can be over before the script line returns; the line must fail
// all the same (it once passed now and then under a loaded ctest: the script asked whether a
// build was running, not whether its own request had been built). Repeated, so that the
// build's thread wins the race on some of the tries.
TEST(ViewerRigEdit, ARefusedBuildFailsItsLineHoweverFastItIsRefused) {
  Fixture f("fast_fail");
  Session s(1);
  Load(&s, f);
  for (int i = 0; i < 40; ++i) {
    std::string error;
    EXPECT_FALSE(Script(&s, "muscle zygomatic strength 1e7", &error)) << "try " << i;
    EXPECT_NE(error.find("muscles[0].strength"), std::string::npos) << "try " << i << ": " << error;
    EXPECT_TRUE(s.rig_stale()) << "try " << i;
    ASSERT_TRUE(Script(&s, "undo", &error)) << "try " << i << ": " << error;
    EXPECT_FALSE(s.rig_stale()) << "try " << i;
  }
}

TEST(ViewerRigEdit, BadValuesAreRefusedNamingTheFieldAndChangeNothing) {
  Fixture f("bad");
  Session s(1);
  Load(&s, f);
  const std::string text0 = SpecText(s);
  const size_t undo0 = s.history().undo_size();
  const struct {
    const char* line;
    const char* says;
  } cases[] = {
      {"muscle zygomatic strength nan", "strength: expected a finite number >= 0, got nan"},
      {"muscle zygomatic strength -1", "strength: expected a finite number >= 0, got -1"},
      {"muscle zygomatic falloff_start -3", "falloff_start: expected a finite number > 0"},
      {"muscle zygomatic falloff_end 20", "falloff_end: expected a number > falloff_start"},
      {"muscle zygomatic zone_angle 200", "zone_angle: expected an angle in (0, 180)"},
      {"muscle zygomatic length 3", "no parameter 'length' for a linear muscle"},
      {"muscle zygomatic tangent_radius -2", "tangent_radius: expected a finite number >= 0, got -2"},
      {"muscle frontalis insertion 3 0 0 0", "insertion is a line: expected I X Y Z"},
      {"muscle nobody strength 1", "the rig has no muscle 'nobody'"},
      {"muscle zygomatic falloff gentle", "falloff: expected waters or smooth"},
      {"muscle zygomatic wrinkles.count 2.5", "wrinkles.count: expected a whole number"},
      {"curve furrow width 0", "width: expected a finite number > 0, got 0"},
      {"curve furrow point 4 0.5 0.5", "point: expected a control point index 0 to 3"},
      {"curve furrow profile wavy", "profile: expected bando, yang_zhang or yang_zhang_exact"},
      {"curve nothing depth 1", "no curve wrinkle 'nothing'"},
      {"direction lines 99999 1 0 0 0.5", "99999 is not a vertex of the mesh (it has 1681)"},
      {"direction lines 10 1 0 0 1.5", "magnitude: expected a number in (0, 1]"},
      {"direction lines 10 0 0 0 0.5", "the direction must not be zero"},
      {"direction cross 820 delete", "the field's last direction vector cannot be deleted"},
      {"direction other 820 delete", "no direction field 'other'"},
  };
  for (const auto& c : cases) {
    std::string error;
    EXPECT_FALSE(Script(&s, c.line, &error)) << c.line;
    EXPECT_NE(error.find(c.says), std::string::npos) << c.line << " -> " << error;
    EXPECT_EQ(SpecText(s), text0) << c.line;
    EXPECT_EQ(s.history().undo_size(), undo0) << c.line;
    EXPECT_FALSE(s.rig_rebuilding()) << c.line;
  }
}

TEST(ViewerRigEdit, ADragIsOneUndoStep) {
  Fixture f("drag");
  Session s(1);
  Load(&s, f);
  const std::string text0 = SpecText(s);
  const size_t undo0 = s.history().undo_size();
  std::string error;
  for (float uv : {0.41f, 0.43f, 0.45f})
    ASSERT_TRUE(s.EditMerged(MakeCurvePointEdit(*s.rig_spec(), 0, 2, {0.6f, uv}, &error),
                             "curve-drag", &error))
        << error;
  s.EndMerge();
  EXPECT_EQ(s.history().undo_size(), undo0 + 1);
  EXPECT_EQ(s.rig_spec()->curve_wrinkles[0].spec.control[2].y, 0.45f);
  ASSERT_TRUE(s.Undo());
  EXPECT_EQ(SpecText(s), text0);
  // A step the file's rules refuse (Rf below Rs) keeps the drag where its last good step left
  // it, still one undo step.
  const auto step = [&](float rf) {
    std::string e;
    return s.EditMerged(MakeMuscleValueEdit(*s.rig_spec(), 0, "falloff_end", {rf}, &e), "rf", &e);
  };
  EXPECT_TRUE(step(50.f));
  EXPECT_FALSE(step(20.f));
  EXPECT_EQ(s.rig_spec()->muscles[0].linear.falloff_end, 50.f);
  EXPECT_EQ(s.history().undo_size(), undo0 + 1);
  EXPECT_TRUE(step(55.f));
  s.EndMerge();
  EXPECT_EQ(s.rig_spec()->muscles[0].linear.falloff_end, 55.f);
  EXPECT_EQ(s.history().undo_size(), undo0 + 1);
  ASSERT_TRUE(s.Undo());
  EXPECT_EQ(SpecText(s), text0);
  ASSERT_TRUE(s.WaitRigRebuild());
}

TEST(ViewerRigEdit, ScriptLinesEditTheSpecAsWritten) {
  Fixture f("script");
  Session s(1);
  Load(&s, f);
  std::string error;
  ASSERT_TRUE(Script(&s, R"(muscle frontalis insertion 1 25 0 11
muscle zygomatic falloff smooth
muscle zygomatic motion tangent
muscle zygomatic tangent_radius 7.5
muscle frontalis wrinkles on
muscle frontalis wrinkles.h_c 4
muscle frontalis wrinkles.gate 0.75
curve furrow profile yang_zhang
direction lines 820 0 2 0 0.25
direction lines 1000 1 1 0 0.5
direction lines 700 delete
wait
save-rig)",
                     &error))
      << error;
  RigSpec back;
  Diagnostics diag;
  ASSERT_TRUE(LoadRigSpec(f.rig, &back, &diag)) << diag.Format();
  EXPECT_EQ(back.muscles[1].sheet.insertion[1].x, 25.f);
  EXPECT_EQ(back.muscles[1].sheet.insertion[1].z, 11.f);
  EXPECT_EQ(back.muscles[0].falloff, MuscleFalloff::kSmooth);
  EXPECT_EQ(back.muscles[0].motion, MuscleMotion::kTangent);
  EXPECT_EQ(back.muscles[0].tangent_radius, 7.5f);
  ASSERT_TRUE(back.muscle_wrinkles.size() > 1 && back.muscle_wrinkles[1].has_value());
  EXPECT_EQ(back.muscle_wrinkles[1]->h_c, 4.f);
  EXPECT_EQ(back.muscle_wrinkles[1]->gate, 0.75f);
  EXPECT_EQ(back.curve_wrinkles[0].spec.profile, CurveWrinkleProfile::kYangZhang);
  const auto& anchors = back.fine_scale->fields[0].anchors;
  ASSERT_EQ(anchors.size(), 2u);  // 820 moved, 700 deleted, 1000 added
  EXPECT_EQ(anchors[0].vertex, 820u);
  EXPECT_EQ(anchors[0].vector.y, 0.25f);  // (0, 2, 0) scaled to length 0.25
  EXPECT_EQ(anchors[0].vector.x, 0.f);
  EXPECT_EQ(anchors[1].vertex, 1000u);
  EXPECT_FLOAT_EQ(anchors[1].vector.x, 0.5f / std::sqrt(2.f));
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(ViewerRigEdit, RegeneratedMapsAreTheBytesMimeticTextureWrites) {
  Fixture f("maps");
  Session s(1);
  Load(&s, f);
  std::string error;
  ASSERT_TRUE(Script(&s, "direction lines 900 0 1 0 0.9\nsave-rig", &error)) << error;
  MapJob job;
  ASSERT_TRUE(job.Start(*s.rig_spec(), s.rig(), s.mesh_vertex_count(), f.dir + "/viewer_maps", 64, 1,
                        &error))
      << error;
  job.Wait();
  bool ok = false;
  Diagnostics diag;
  std::vector<std::string> written;
  ASSERT_TRUE(job.Take(&ok, &diag, &written));
  ASSERT_TRUE(ok) << diag.Format();
  EXPECT_EQ(job.progress(), 1.f);
  ASSERT_EQ(written.size(), 4u);
  const test::ToolResult tool =
      test::RunTool({"texture", f.rig, "--size", "64", "--seed", "1", "--out", f.dir + "/tool_maps", "--quiet"});
  ASSERT_EQ(tool.exit_code, 0) << tool.output;
  for (const char* name : kFineMapNames) {
    const std::string mine = Slurp(f.dir + "/viewer_maps/" + name);
    EXPECT_FALSE(mine.empty()) << name;
    EXPECT_TRUE(mine == Slurp(f.dir + "/tool_maps/" + name)) << name;
  }
  EXPECT_FALSE(job.Take(&ok, &diag, &written));  // handed over once
}

}  // namespace
}  // namespace mimetic::viewer
