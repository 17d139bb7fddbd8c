// mimetic-viewer --script (viewer/core/script.h) without GL: a script's edits land as the same
// commands would (the saved clip's keys and the library's values read back here), its undo and
// redo, and every bad line is named FILE:LINE with what was wrong.
#include "viewer/core/script.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "io/clip_file.h"
#include "io/expression_library.h"
#include "test_support.h"

namespace mimetic::viewer {
namespace {

std::string Surface() { return test::SourceDir() + "/assets/surface/surface.rig.json"; }

TEST(ViewerScript, SplitsWordsWithQuotesAndComments) {
  std::vector<std::string> w;
  std::string error;
  ASSERT_TRUE(SplitScriptLine("  expr rename \"a b\" c\\d  # a comment", &w, &error));
  EXPECT_EQ(w, (std::vector<std::string>{"expr", "rename", "a b", "c\\d"}));
  ASSERT_TRUE(SplitScriptLine("expr save \"say \\\"hi\\\"\"", &w, &error));
  EXPECT_EQ(w.back(), "say \"hi\"");
  ASSERT_TRUE(SplitScriptLine("   # only a comment", &w, &error));
  EXPECT_TRUE(w.empty());
  EXPECT_FALSE(SplitScriptLine("expr save \"open", &w, &error));
  EXPECT_NE(error.find("quote"), std::string::npos);
}

TEST(ViewerScript, AScriptAuthorsAClipAndAnExpression) {
  const std::string dir = test::TempDir() + "/script_authors";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string lib = dir + "/lib.library.json", clip = dir + "/new.clip.json";
  std::ofstream(lib) << R"({"format": "mimetic-expression-library", "version": 1, "expressions": [
    {"name": "A", "activations": {"zygomatic": 0.8}}]})";
  Session s(1);
  ASSERT_TRUE(s.LoadRigFile(Surface()));
  ASSERT_TRUE(s.LoadLibraryFile(lib));
  const std::string script =
      "# a new clip: zygomatic 0 -> 1 -> 0.5, the weight of A, one key undone and redone\n"
      "clip new " + clip + "\n"
      "key add muscle:zygomatic 0 0\n"
      "key add muscle:zygomatic 1 1 cubic\n"
      "key add muscle:zygomatic 2 0.5\n"
      "key add expression:A 0.5 0.25 step\n"
      "key add expression:A 1.5 1\n"
      "key move muscle:zygomatic 2 2.5 0.4\n"
      "interp muscle:zygomatic 0 step\n"
      "key delete expression:A 1.5\n"
      "undo\n"
      "undo\n"
      "redo\n"
      "select muscle:zygomatic 0\n"
      "select muscle:zygomatic 1\n"
      "copy\n"
      "paste 3\n"
      "set frontalis 0.35\n"
      "set zygomatic 0.5\n"
      "expr save \"Half smile\"\n"
      "expr rename A Alpha\n"
      "save-clip\n"
      "save-library " + dir + "/out.library.json\n";
  std::string error;
  ASSERT_TRUE(RunScript(script, "authors.txt", &s, {}, &error)) << error;
  EXPECT_FALSE(s.clip_dirty());
  ClipSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(clip, &spec, &diag)) << diag.Format();
  EXPECT_EQ(spec.name, "new");
  ASSERT_EQ(spec.channels.size(), 2u);
  const auto& z = spec.channels[0].keys;
  ASSERT_EQ(z.size(), 5u);  // 0, 1, 2.5 and the pasted 3, 4
  EXPECT_EQ(z[0].interp, KeyInterp::kStep);  // redone
  EXPECT_EQ(z[1].interp, KeyInterp::kCubic);
  EXPECT_FLOAT_EQ(z[2].t, 2.5f);
  EXPECT_FLOAT_EQ(z[2].v, 0.4f);
  EXPECT_FLOAT_EQ(z[3].t, 3.f);
  EXPECT_EQ(z[3].interp, KeyInterp::kStep);
  EXPECT_FLOAT_EQ(z[4].t, 4.f);
  EXPECT_FLOAT_EQ(z[4].v, 1.f);
  EXPECT_EQ(spec.channels[1].target, "Alpha");  // renamed with its expression
  ASSERT_EQ(spec.channels[1].keys.size(), 2u);  // the delete was undone
  EXPECT_FLOAT_EQ(spec.channels[1].keys[1].t, 1.5f);
  std::vector<Expression> library;
  ASSERT_TRUE(LoadExpressionLibrary(dir + "/out.library.json", &library, &diag)) << diag.Format();
  ASSERT_EQ(library.size(), 2u);
  EXPECT_EQ(library[0].name, "Alpha");
  EXPECT_EQ(library[1].name, "Half smile");
  ASSERT_EQ(library[1].activations.size(), 2u);  // the two non-zero muscles, by name
  EXPECT_EQ(library[1].activations[0].first, "frontalis");
  EXPECT_FLOAT_EQ(library[1].activations[0].second, 0.35f);
  EXPECT_EQ(library[1].activations[1].first, "zygomatic");
  EXPECT_FLOAT_EQ(library[1].activations[1].second, 0.5f);
}

TEST(ViewerScript, ABadLineIsNamedWithItsFileAndLine) {
  const struct {
    std::string text, needle;
  } cases[] = {
      {"clip new x.clip.json\nfrobnicate\n", "s.txt:2: unknown command 'frobnicate'"},
      {"clip new x.clip.json\n\n# c\nkey add muscle:zygomatic one 0\n", "s.txt:4: 'one' is not a number"},
      {"clip new x.clip.json\nkey add muscle:zygomatic 0 1.5\n", "s.txt:2: key add muscle:zygomatic 0 1.5: value 1.5"},
      {"clip new x.clip.json\nkey add muscle:zygomatc 0 1\n", "s.txt:2:"},
      {"clip new x.clip.json\nkey add muscle:zygomatic 0 1\nkey delete muscle:zygomatic 3\n",
       "s.txt:3: channel muscle:zygomatic has no key at 3 s"},
      {"key add muscle:zygomatic 0 1\n", "s.txt:1: no clip is open"},
      {"set zygomatic\n", "s.txt:1: expected: set NAME VALUE"},
      {"set cheek 0.5\n", "s.txt:1: set cheek: the rig has no muscle 'cheek'"},
      {"undo\n", "s.txt:1: nothing to undo"},
      {"interp jaw 0 smooth\n", "s.txt:1: "},
      {"expr delete Nobody\n", "s.txt:1: expr delete Nobody: the library has no expression 'Nobody'"},
      {"expr save \"unclosed\n", "s.txt:1: a quote is not closed"},
      {"screenshot a.png\n", "s.txt:1: screenshot: no renderer here"},
      {"save-clip /no/such/dir/a.clip.json\n", "s.txt:1: save clip: no clip is open"},
  };
  for (const auto& c : cases) {
    Session s(1);
    ASSERT_TRUE(s.LoadRigFile(Surface()));
    std::string error;
    EXPECT_FALSE(RunScript(c.text, "s.txt", &s, {}, &error)) << c.text;
    EXPECT_EQ(error.rfind(c.needle, 0), 0u) << "got '" << error << "', expected it to start with '"
                                            << c.needle << "'";
  }
  Session s(1);
  std::string error;
  EXPECT_FALSE(RunScriptFile(test::TempDir() + "/no_such_script.txt", &s, {}, &error));
  EXPECT_NE(error.find("no_such_script.txt"), std::string::npos) << error;
}

// `time T` tells the window's playhead (ScriptHooks::playhead) where the pose is, so a later
// screenshot's timeline shows T; `time none` lets go of the clip (-1).
TEST(ViewerScript, TimeLinesMoveThePlayhead) {
  Session s(1);
  ASSERT_TRUE(s.LoadRigFile(Surface()));
  std::vector<float> seen;
  ScriptHooks hooks;
  hooks.playhead = [&](float t) { seen.push_back(t); };
  std::string error;
  ASSERT_TRUE(RunScript("clip new " + test::TempDir() + "/p.clip.json\n"
                        "key add muscle:zygomatic 0 0\nkey add muscle:zygomatic 2 1\n"
                        "time 0.5\ntime 1.25\ntime none\n",
                        "p.txt", &s, hooks, &error))
      << error;
  EXPECT_EQ(seen, (std::vector<float>{0.5f, 1.25f, -1.f}));
}

}  // namespace
}  // namespace mimetic::viewer
