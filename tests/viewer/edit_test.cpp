// The viewer's edits (viewer/core/edit.h through Session): after any seeded random sequence of
// commands, undo gives back the clip spec, the library, the compiled clip and the pose bit for
// bit (each step against the state recorded before it); keys land where asked and play as their
// interpolation says (values computed here by hand); the expression commands; a saved clip and
// library reload equal; a save killed between the temporary file and the rename leaves the old
// file's bytes; a failed save keeps the edits and the dirty flag; an autosave recovers the
// edits in a new session.
#include "viewer/core/edit.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "core/file_util_hook.h"
#include "io/clip_file.h"
#include "io/expression_library.h"
#include "test_support.h"
#include "viewer/core/session.h"

namespace mimetic::viewer {
namespace {

std::string Surface() { return test::SourceDir() + "/assets/surface/surface.rig.json"; }

// A rig (surface: zygomatic, frontalis), a library {A, B} and a clip of two channels, in a
// folder of its own.
struct Fixture {
  std::string dir, lib, clip;
  explicit Fixture(const std::string& name) {
    dir = test::TempDir() + "/edit_" + name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    lib = dir + "/two.library.json";
    clip = dir + "/two.clip.json";
    std::ofstream(lib) << R"({"format": "mimetic-expression-library", "version": 1, "expressions": [
      {"name": "A", "activations": {"zygomatic": 0.8, "frontalis": 0.4}},
      {"name": "B", "activations": {"frontalis": 0.9}}]})";
    std::ofstream(clip) << R"({"format": "mimetic-clip", "version": 1, "name": "two", "channels": [
      {"expression": "A", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 1}]},
      {"muscle": "zygomatic", "keys": [{"t": 0, "v": 0}, {"t": 1, "v": 1, "interp": "cubic"}, {"t": 2, "v": 0.5}]}]})";
  }
  void Load(Session* s) const {
    ASSERT_TRUE(s->LoadRigFile(Surface()));
    ASSERT_TRUE(s->LoadLibraryFile(lib));
    ASSERT_TRUE(s->LoadClipFile(clip));
  }
};

// Everything an edit may change, as bytes.
struct State {
  std::string clip_json, library_json;
  std::vector<float> compiled, activations;
  float jaw = 0.f;
  bool operator==(const State& o) const {
    return clip_json == o.clip_json && library_json == o.library_json &&
           compiled.size() == o.compiled.size() &&
           std::memcmp(compiled.data(), o.compiled.data(), compiled.size() * sizeof(float)) == 0 &&
           activations.size() == o.activations.size() &&
           std::memcmp(activations.data(), o.activations.data(), activations.size() * sizeof(float)) == 0 &&
           std::memcmp(&jaw, &o.jaw, sizeof jaw) == 0;
  }
};

State Capture(const Session& s) {
  State st;
  st.clip_json = s.has_clip_spec() ? ClipToJson(s.clip_spec()) : "";
  st.library_json = ExpressionLibraryToJson(s.library());
  if (s.has_clip()) {
    const CompiledClip& c = s.clip();
    for (auto part : {c.key_times(), c.key_values(), c.key_tangents(), c.expression_activations()})
      st.compiled.insert(st.compiled.end(), part.begin(), part.end());
    st.compiled.push_back(c.duration());
    for (uint32_t t : c.targets()) st.compiled.push_back(float(t));
    for (KeyInterp i : c.key_interps()) st.compiled.push_back(float(i));
  }
  st.activations = s.activations;
  st.jaw = s.jaw;
  return st;
}

TEST(ViewerEdit, UndoOfARandomSequenceRestoresEverythingBitForBit) {
  Fixture f("random");
  Session s(1);
  f.Load(&s);
  const State initial = Capture(s);
  std::mt19937 rng(17);
  auto uniform = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
  auto pick = [&](size_t n) { return size_t(std::uniform_int_distribution<size_t>(0, n - 1)(rng)); };
  const std::vector<ChannelId> channels = {{ClipChannelKind::kMuscle, "zygomatic"},
                                           {ClipChannelKind::kMuscle, "frontalis"},
                                           {ClipChannelKind::kExpression, "A"},
                                           {ClipChannelKind::kExpression, "B"}};
  const std::vector<std::string> names = {"A", "B", "C", "D"};
  auto random_key = [&]() -> std::vector<KeyRef> {
    const ClipSpec& c = s.clip_spec();
    if (c.channels.empty()) return {};
    const size_t ch = pick(c.channels.size());
    std::vector<KeyRef> out{{uint32_t(ch), uint32_t(pick(c.channels[ch].keys.size()))}};
    if (pick(2) && c.channels[ch].keys.size() > 1)  // a second key: a multi-selection
      out.push_back({uint32_t(ch), uint32_t(pick(c.channels[ch].keys.size()))});
    return out;
  };
  std::vector<State> undo_states, redo_states;
  int applied = 0, refused = 0, undone = 0, redone = 0;
  for (int step = 0; step < 400; ++step) {
    const State before = Capture(s);
    const size_t op = pick(14);
    auto redo_once = [&] {
      const State now = Capture(s);
      if (!s.Redo()) return;
      ++redone;
      ASSERT_FALSE(redo_states.empty());
      EXPECT_TRUE(Capture(s) == redo_states.back()) << "redo at step " << step;
      redo_states.pop_back();
      undo_states.push_back(now);
    };
    if (op == 12) {  // undo one to three times, then now and then redo some of it
      const size_t n = 1 + pick(3);
      for (size_t i = 0; i < n; ++i) {
        const State now = Capture(s);
        if (s.Undo()) {
          ++undone;
          ASSERT_FALSE(undo_states.empty());
          EXPECT_TRUE(Capture(s) == undo_states.back()) << "undo at step " << step;
          undo_states.pop_back();
          redo_states.push_back(now);
        } else {
          EXPECT_TRUE(undo_states.empty());
        }
      }
      if (pick(2))
        for (size_t i = pick(n + 1); i > 0; --i) redo_once();
      continue;
    }
    if (op == 13) {  // redo
      redo_once();
      continue;
    }
    CommandPtr c;
    const float t = std::round(uniform(0.f, 3.f) * 20.f) / 20.f;
    switch (op) {
      case 0: c = MakeSetMuscles({uint32_t(pick(2))}, uniform(0.f, 1.f)); break;
      case 1: c = MakeAddKey(channels[pick(channels.size())], t, uniform(0.f, 1.f),
                             KeyInterp(pick(3))); break;
      case 2: c = MakeDeleteKeys(random_key()); break;
      case 3: c = MakeMoveKeys(random_key(), uniform(-0.5f, 0.5f), uniform(-0.3f, 0.3f)); break;
      case 4: if (auto k = random_key(); !k.empty()) c = MakeSetKey(k[0], t, uniform(0.f, 1.f)); break;
      case 5: c = MakeSetInterp(random_key(), KeyInterp(pick(3))); break;
      case 6: c = MakePasteKeys(CopyKeys(s.clip_spec(), random_key()), t); break;
      case 7: c = MakeSaveExpression(names[pick(names.size())]); break;
      case 8: c = MakeOverwriteExpression(names[pick(names.size())]); break;
      case 9: c = MakeRenameExpression(names[pick(names.size())], names[pick(names.size())]); break;
      case 10: c = MakeDeleteExpression(names[pick(names.size())]); break;
      case 11: c = MakeSetPose({uniform(0.f, 1.f), uniform(0.f, 1.f)}, 0.f); break;
    }
    if (!c) continue;
    if (s.Edit(std::move(c))) {
      ++applied;
      undo_states.push_back(before);
      redo_states.clear();
    } else {
      ++refused;
      EXPECT_TRUE(Capture(s) == before) << "a refused command changed something at step " << step;
    }
  }
  EXPECT_GT(applied, 100);
  EXPECT_GT(refused, 10);
  EXPECT_GT(undone, 10);
  EXPECT_GT(redone, 5);
  EXPECT_TRUE(s.clip_dirty() || s.library_dirty());
  while (s.Undo()) {
    EXPECT_TRUE(Capture(s) == undo_states.back());
    undo_states.pop_back();
  }
  EXPECT_TRUE(Capture(s) == initial);
  EXPECT_FALSE(s.clip_dirty());
  EXPECT_FALSE(s.library_dirty());
}

// The zygomatic activation of the clip at time t.
float Zygomatic(Session* s, float t) {
  EXPECT_TRUE(s->SampleClip(t));
  return s->activations[size_t(s->rig().FindMuscle("zygomatic"))];
}

TEST(ViewerEdit, KeysLandWhereAskedAndPlayAsTheirInterpolation) {
  Session s(1);
  ASSERT_TRUE(s.LoadRigFile(Surface()));
  ASSERT_TRUE(s.NewClip(test::TempDir() + "/edit_new.clip.json"));
  EXPECT_EQ(s.clip_spec().name, "edit_new");
  EXPECT_TRUE(s.clip_dirty());
  const ChannelId zyg{ClipChannelKind::kMuscle, "zygomatic"};
  ASSERT_TRUE(s.Edit(MakeAddKey(zyg, 0.f, 0.f)));
  ASSERT_TRUE(s.Edit(MakeAddKey(zyg, 2.f, 1.f)));
  // Linear from (0, 0) to (2, 1): 0.25 at 0.5.
  EXPECT_FLOAT_EQ(Zygomatic(&s, 0.5f), 0.25f);
  // A key in between at (1, 0.8): 0.4 at 0.5, 0.9 at 1.5.
  ASSERT_TRUE(s.Edit(MakeAddKey(zyg, 1.f, 0.8f)));
  ASSERT_EQ(s.clip_spec().channels[0].keys.size(), 3u);
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[1].t, 1.f);
  EXPECT_FLOAT_EQ(Zygomatic(&s, 0.5f), 0.4f);
  EXPECT_FLOAT_EQ(Zygomatic(&s, 1.5f), 0.9f);
  // Step on the first key: it holds 0 until t = 1.
  ASSERT_TRUE(s.Edit(MakeSetInterp({{0, 0}}, KeyInterp::kStep)));
  EXPECT_FLOAT_EQ(Zygomatic(&s, 0.9f), 0.f);
  EXPECT_FLOAT_EQ(Zygomatic(&s, 1.f), 0.8f);
  // The middle key to (1.5, 0.2): linear 0.2 -> 1 over [1.5, 2], 0.6 at 1.75.
  ASSERT_TRUE(s.Edit(MakeSetKey({0, 1}, 1.5f, 0.2f)));
  EXPECT_FLOAT_EQ(Zygomatic(&s, 1.75f), 0.6f);
  // It cannot pass the last key: refused with a message, nothing changed.
  std::string error;
  EXPECT_FALSE(s.Edit(MakeMoveKeys({{0, 1}}, 0.6f, 0.f), &error));
  EXPECT_NE(error.find("time order"), std::string::npos) << error;
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[1].t, 1.5f);
  // Both ends moved together by +1 s (values clamped to [0, 1]): keys at 1, 2.5, 3.
  ASSERT_TRUE(s.Edit(MakeMoveKeys({{0, 0}, {0, 1}, {0, 2}}, 1.f, 0.5f)));
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[0].t, 1.f);
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[0].v, 0.5f);
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[2].v, 1.f);
  EXPECT_FLOAT_EQ(s.clip().duration(), 3.f);
  // Copy the first two keys, paste at 4: keys at 4 and 5.5 with their values.
  ASSERT_TRUE(s.Edit(MakePasteKeys(CopyKeys(s.clip_spec(), {{0, 0}, {0, 1}}), 4.f)));
  ASSERT_EQ(s.clip_spec().channels[0].keys.size(), 5u);
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[3].t, 4.f);
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[4].t, 5.5f);
  EXPECT_FLOAT_EQ(s.clip_spec().channels[0].keys[4].v, 0.7f);
  // An expression-weight channel beside the muscle channel (needs the library's name).
  EXPECT_FALSE(s.Edit(MakeAddKey({ClipChannelKind::kExpression, "Nope"}, 0.f, 1.f), &error));
  EXPECT_NE(error.find("Nope"), std::string::npos) << error;
  // Cubic with auto tangents between two keys is the straight line (both tangents the secant).
  ASSERT_TRUE(s.Edit(MakeDeleteKeys({{0, 2}, {0, 3}, {0, 4}})));
  ASSERT_TRUE(s.Edit(MakeSetInterp({{0, 0}}, KeyInterp::kCubic)));
  EXPECT_NEAR(Zygomatic(&s, 1.75f), 0.5f + 0.5f * (0.7f - 0.5f), 1e-6f);  // keys (1, 0.5), (2.5, 0.7)
  // Deleting every key removes the channel.
  ASSERT_TRUE(s.Edit(MakeDeleteKeys({{0, 0}, {0, 1}})));
  EXPECT_TRUE(s.clip_spec().channels.empty());
  EXPECT_FALSE(s.has_clip());
}

TEST(ViewerEdit, ExpressionsSaveRenameOverwriteAndDelete) {
  Fixture f("expr");
  Session s(1);
  f.Load(&s);
  const size_t zyg = size_t(s.rig().FindMuscle("zygomatic"));
  ASSERT_TRUE(s.SetByName("zygomatic", 0.6f));
  ASSERT_TRUE(s.Edit(MakeSaveExpression("Grin")));
  ASSERT_EQ(s.library().size(), 3u);
  EXPECT_EQ(s.library()[2].name, "Grin");
  ASSERT_EQ(s.library()[2].activations.size(), 1u);  // only the non-zero muscle
  EXPECT_EQ(s.library()[2].activations[0].first, "zygomatic");
  EXPECT_FLOAT_EQ(s.library()[2].activations[0].second, 0.6f);
  EXPECT_EQ(s.expression_weights.size(), 3u);
  std::string error;
  EXPECT_FALSE(s.Edit(MakeSaveExpression("A"), &error));
  EXPECT_NE(error.find("already has"), std::string::npos) << error;
  // Rename A (a clip channel animates it): the channel follows; the clip still plays
  // 0.5 A at t = 1 (zygomatic's own channel overrides it, frontalis 0.5 * 0.4).
  ASSERT_TRUE(s.Edit(MakeRenameExpression("A", "Alpha")));
  EXPECT_EQ(s.library()[0].name, "Alpha");
  EXPECT_EQ(s.clip_spec().channels[0].target, "Alpha");
  ASSERT_TRUE(s.SampleClip(1.f));
  EXPECT_NEAR(s.activations[size_t(s.rig().FindMuscle("frontalis"))], 0.2f, 1e-6f);
  EXPECT_FALSE(s.Edit(MakeDeleteExpression("Alpha"), &error));
  EXPECT_NE(error.find("channels[0]"), std::string::npos) << error;
  // Overwrite B with the pose zygomatic 0.3; delete it; undo twice gives B's frontalis 0.9.
  s.activations.assign(s.activations.size(), 0.f);
  s.activations[zyg] = 0.3f;
  ASSERT_TRUE(s.Edit(MakeOverwriteExpression("B")));
  ASSERT_EQ(s.library()[1].activations.size(), 1u);
  EXPECT_FLOAT_EQ(s.library()[1].activations[0].second, 0.3f);
  ASSERT_TRUE(s.Edit(MakeDeleteExpression("B")));
  EXPECT_EQ(s.library().size(), 2u);
  ASSERT_TRUE(s.Undo());
  ASSERT_TRUE(s.Undo());
  EXPECT_EQ(s.library()[1].name, "B");
  EXPECT_EQ(s.library()[1].activations[0].first, "frontalis");
  EXPECT_FLOAT_EQ(s.library()[1].activations[0].second, 0.9f);
}

TEST(ViewerEdit, ASavedClipAndLibraryReloadEqual) {
  Fixture f("save");
  Session s(1);
  f.Load(&s);
  ASSERT_TRUE(s.Edit(MakeAddKey({ClipChannelKind::kExpression, "B"}, 0.35f, 0.123456f, KeyInterp::kCubic)));
  ASSERT_TRUE(s.Edit(MakeSetKey({1, 1}, 1.1f, 0.3f)));
  ASSERT_TRUE(s.SetByName("frontalis", 0.45f));
  ASSERT_TRUE(s.SetByName("zygomatic", 0.123457f));
  ASSERT_TRUE(s.Edit(MakeSaveExpression("Brow")));
  EXPECT_TRUE(s.clip_dirty());
  EXPECT_TRUE(s.library_dirty());
  const std::string clip = f.dir + "/saved.clip.json", lib = f.dir + "/saved.library.json";
  ASSERT_TRUE(s.SaveClipFile(clip));
  ASSERT_TRUE(s.SaveLibraryFile(lib));
  EXPECT_FALSE(s.clip_dirty());
  EXPECT_FALSE(s.library_dirty());
  EXPECT_EQ(s.clip_path(), clip);
  Session t(1);
  ASSERT_TRUE(t.LoadRigFile(Surface()));
  ASSERT_TRUE(t.LoadLibraryFile(lib));
  ASSERT_TRUE(t.LoadClipFile(clip));
  EXPECT_EQ(Capture(t).clip_json, Capture(s).clip_json);
  EXPECT_EQ(Capture(t).library_json, Capture(s).library_json);
  EXPECT_EQ(Capture(t).compiled, Capture(s).compiled);
  ClipSpec reread;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(clip, &reread, &diag)) << diag.Format();
  EXPECT_FLOAT_EQ(reread.channels[2].keys[0].t, 0.35f);
  EXPECT_EQ(reread.channels[2].keys[0].v, 0.123456f);
  EXPECT_EQ(reread.channels[2].keys[0].interp, KeyInterp::kCubic);
  // The library's values are written with six decimals (io/expression_library.cpp).
  ASSERT_EQ(t.library().size(), 3u);
  ASSERT_EQ(t.library()[2].activations.size(), 2u);
  EXPECT_EQ(t.library()[2].activations[1].first, "zygomatic");
  EXPECT_EQ(t.library()[2].activations[1].second, 0.123457f);
  // Undo after the save makes it dirty again; redo back to the saved version, clean.
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(s.library_dirty());
  ASSERT_TRUE(s.Redo());
  EXPECT_FALSE(s.library_dirty());
}

TEST(ViewerEdit, ASaveKilledBeforeTheRenameLeavesTheOldFile) {
  Fixture f("killed");
  const std::string old_bytes = test::ReadFileBytes(f.clip), old_lib = test::ReadFileBytes(f.lib);
  for (int which = 0; which < 2; ++which) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      // The child makes its own session (no threads were forked), edits, and saves over the
      // old files with a hook that ends it between the temporary file and the rename.
      Session s(1);
      if (!s.LoadRigFile(Surface()) || !s.LoadLibraryFile(f.lib) || !s.LoadClipFile(f.clip)) _exit(2);
      if (!s.Edit(MakeAddKey({ClipChannelKind::kMuscle, "frontalis"}, 0.5f, 0.5f))) _exit(3);
      if (!s.SetByName("frontalis", 0.5f) || !s.Edit(MakeSaveExpression("X"))) _exit(4);
      SetWriteFileAtomicHook([](const std::string&, const std::string&) { _exit(86); });
      if (which == 0) s.SaveClipFile();
      else s.SaveLibraryFile();
      _exit(5);  // not reached: the hook ends the save
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 86);
    EXPECT_EQ(test::ReadFileBytes(f.clip), old_bytes);
    EXPECT_EQ(test::ReadFileBytes(f.lib), old_lib);
    // The child's complete temporary file is there, holding the new text.
    const std::string tmp = (which == 0 ? f.clip : f.lib) + ".tmp" + std::to_string(child);
    ASSERT_TRUE(std::filesystem::exists(tmp));
    EXPECT_NE(test::ReadFileBytes(tmp).find(which == 0 ? "frontalis" : "\"X\""), std::string::npos);
  }
  // The next save of the same file removes the dead process's temporary file.
  Session s(1);
  f.Load(&s);
  ASSERT_TRUE(s.Edit(MakeAddKey({ClipChannelKind::kMuscle, "frontalis"}, 0.5f, 0.5f)));
  ASSERT_TRUE(s.SaveClipFile());
  for (const auto& e : std::filesystem::directory_iterator(f.dir))
    EXPECT_EQ(e.path().string().find("two.clip.json.tmp"), std::string::npos) << e.path();
  EXPECT_NE(test::ReadFileBytes(f.clip), old_bytes);
}

TEST(ViewerEdit, AFailedSaveSaysWhyAndKeepsTheEdits) {
  Fixture f("failed");
  Session s(1);
  f.Load(&s);
  ASSERT_TRUE(s.Edit(MakeAddKey({ClipChannelKind::kMuscle, "frontalis"}, 0.5f, 0.5f)));
  const std::string edited = ClipToJson(s.clip_spec());
  const std::string bad = f.dir + "/no_such_folder/x.clip.json";
  std::string error;
  EXPECT_FALSE(s.SaveClipFile(bad, &error));
  EXPECT_NE(error.find(bad), std::string::npos) << error;
  EXPECT_NE(error.find("No such file"), std::string::npos) << error;
  EXPECT_NE(error.find("kept"), std::string::npos) << error;
  EXPECT_TRUE(s.clip_dirty());
  EXPECT_EQ(ClipToJson(s.clip_spec()), edited);
  EXPECT_EQ(s.clip_path(), f.clip);
  EXPECT_FALSE(s.SaveLibraryFile(f.dir + "/no_such_folder/x.library.json", &error));
  EXPECT_TRUE(s.Undo());  // the edit is still undoable
  EXPECT_FALSE(s.clip_dirty());
}

TEST(ViewerEdit, AnAutosaveRecoversTheEditsInANewSession) {
  Fixture f("autosave");
  const std::string old_clip = test::ReadFileBytes(f.clip), old_lib = test::ReadFileBytes(f.lib);
  State edited;
  {
    Session s(1);
    f.Load(&s);
    EXPECT_TRUE(s.Autosave());  // nothing changed: nothing written
    EXPECT_TRUE(s.PendingAutosaves().empty());
    ASSERT_TRUE(s.Edit(MakeAddKey({ClipChannelKind::kMuscle, "frontalis"}, 0.25f, 0.75f)));
    ASSERT_TRUE(s.Edit(MakeRenameExpression("B", "Beta")));
    ASSERT_TRUE(s.Autosave());
    EXPECT_EQ(s.PendingAutosaves().size(), 2u);
    edited = Capture(s);
  }  // the session ends without saving (a crash)
  EXPECT_EQ(test::ReadFileBytes(f.clip), old_clip);
  EXPECT_EQ(test::ReadFileBytes(f.lib), old_lib);
  Session t(1);
  f.Load(&t);
  ASSERT_EQ(t.PendingAutosaves().size(), 2u);
  EXPECT_EQ(t.RecoverAutosaves(), 2);
  const State got = Capture(t);
  EXPECT_EQ(got.clip_json, edited.clip_json);
  EXPECT_EQ(got.library_json, edited.library_json);
  EXPECT_EQ(got.compiled, edited.compiled);
  EXPECT_TRUE(t.clip_dirty());
  EXPECT_TRUE(t.library_dirty());
  // Saving removes the autosaves.
  ASSERT_TRUE(t.SaveClipFile());
  ASSERT_TRUE(t.SaveLibraryFile());
  EXPECT_TRUE(t.PendingAutosaves().empty());
  EXPECT_EQ(test::ReadFileBytes(f.clip), edited.clip_json);
}

}  // namespace
}  // namespace mimetic::viewer
