// tests/io/expression_library_test.cpp: expression libraries (io/expression_library.h): a
// hand-written library, its round trip, the bad-input table, the check against a rig's
// muscles, and the shipped default library against the sample head rig and its sources.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "expressions/runtime/clip.h"
#include "io/expression_library.h"
#include "io/rig_loader.h"
#include "test_support.h"

namespace mimetic {
namespace {

const char* kGood = R"({"format": "mimetic-expression-library", "version": 1, "expressions": [
  {"name": "rest", "activations": {}},
  {"name": "Fear", "description": "inner brows up and in", "sources": "Zhang 2005 §3",
   "activations": {"frontalis_inner_L": 0.8, "corrugator_supercilii_L": 0.6}}]})";

TEST(ExpressionLibrary, ReadsAHandWrittenLibraryAndRoundTrips) {
  std::vector<Expression> lib;
  Diagnostics diag;
  ASSERT_TRUE(ParseExpressionLibrary(kGood, "lib.json", &lib, &diag)) << diag.Format();
  ASSERT_EQ(lib.size(), 2u);
  EXPECT_EQ(lib[0].name, "rest");
  EXPECT_TRUE(lib[0].activations.empty());
  EXPECT_TRUE(lib[0].description.empty());
  EXPECT_EQ(lib[1].name, "Fear");
  EXPECT_EQ(lib[1].description, "inner brows up and in");
  EXPECT_EQ(lib[1].sources, "Zhang 2005 §3");
  // Members come back sorted by name (the parser's objects are ordered maps).
  ASSERT_EQ(lib[1].activations.size(), 2u);
  EXPECT_EQ(lib[1].activations[0], (std::pair<std::string, float>{"corrugator_supercilii_L", 0.6f}));
  EXPECT_EQ(lib[1].activations[1], (std::pair<std::string, float>{"frontalis_inner_L", 0.8f}));

  const std::string path = test::TempDir() + "/x.library.json";
  ASSERT_TRUE(SaveExpressionLibrary(path, lib, &diag)) << diag.Format();
  std::vector<Expression> back;
  ASSERT_TRUE(LoadExpressionLibrary(path, &back, &diag)) << diag.Format();
  ASSERT_EQ(back.size(), lib.size());
  for (size_t i = 0; i < lib.size(); ++i) {
    EXPECT_EQ(back[i].name, lib[i].name);
    EXPECT_EQ(back[i].description, lib[i].description);
    EXPECT_EQ(back[i].sources, lib[i].sources);
    EXPECT_EQ(back[i].activations, lib[i].activations);  // six decimals hold these exactly
  }
}

TEST(ExpressionLibrary, BadInputsSayWhatAndWhere) {
  const std::string good = kGood;
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  struct Case {
    std::string text;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"", "not valid JSON"},
      {"{}", "format"},
      {with("\"mimetic-expression-library\"", "\"mimetic-expression\""), "format"},
      {with("\"version\": 1", "\"version\": 2"), "version"},
      {with("\"expressions\": [", "\"expressions\": {\"a\": ["), "not valid JSON"},
      {R"({"format": "mimetic-expression-library", "version": 1, "expressions": {}})",
       "expressions: expected an array of expressions"},
      {with("\"name\": \"rest\", ", ""), "expressions[0].name: missing required key"},
      {with("\"name\": \"rest\"", "\"name\": \"\""), "expressions[0].name"},
      {with("\"name\": \"rest\"", "\"name\": \"Fear\""),
       "expressions[1].name: \"Fear\" is also the name of expressions[0]"},
      {with("\"activations\": {}", "\"activations\": [0.5]"), "expressions[0].activations"},
      {with("0.8,", "1.5,"),
       "expressions[1].activations.frontalis_inner_L: is 1.5; expected an activation in [0, 1]"},
      {with("0.6}", "-0.1}"), "expressions[1].activations.corrugator_supercilii_L: is -0.1"},
      {with("0.6}", "\"lots\"}"), "expressions[1].activations.corrugator_supercilii_L: is \"lots\""},
      {with("{\"name\": \"rest\", \"activations\": {}}",
            "{\"name\": \"rest\", \"activations\": {\"\": 0.1}}"),
       "expressions[0].activations: has an empty muscle name"},
      {with("\"sources\"", "\"source\""), "expressions[1].source: unknown key"},
      {with("\"description\": \"inner brows up and in\"", "\"description\": 3"),
       "expressions[1].description"},
      {std::string(100, '[') + std::string(100, ']'), "nest"},
  };
  for (const Case& c : cases) {
    std::vector<Expression> lib;
    Diagnostics diag;
    EXPECT_FALSE(ParseExpressionLibrary(c.text, "lib.json", &lib, &diag)) << c.text;
    EXPECT_NE(diag.Format().find(c.message), std::string::npos)
        << c.text << "\n" << diag.Format();
    EXPECT_NE(diag.Format().find("lib.json"), std::string::npos) << diag.Format();
  }
}

TEST(ExpressionLibrary, TheWriterRefusesWhatTheReaderWouldRefuse) {
  const std::string dir = test::TempDir();
  struct Case {
    std::vector<Expression> lib;
    const char* message;
  };
  Expression a, b;
  a.name = "A";
  a.activations = {{"m", 0.5f}};
  b = a;
  Expression bad_value = a, empty = a, twice = a;
  bad_value.activations = {{"m", 1.5f}};
  empty.name = "";
  twice.activations = {{"m", 0.1f}, {"m", 0.2f}};
  const std::vector<Case> cases = {{{a, b}, "expressions[1]: name 'A' appears twice"},
                                   {{bad_value}, "expressions[0].activations[0]"},
                                   {{empty}, "expressions[0]: name is empty"},
                                   {{twice}, "'m' appears twice"}};
  for (const Case& c : cases) {
    const std::string path = dir + "/bad.library.json";
    Diagnostics diag;
    EXPECT_FALSE(SaveExpressionLibrary(path, c.lib, &diag));
    EXPECT_NE(diag.Format().find(c.message), std::string::npos) << diag.Format();
    EXPECT_FALSE(std::filesystem::exists(path));
  }
}

TEST(ExpressionLibrary, UnknownMusclesAreNamedWithTheClosestOnes) {
  std::vector<Expression> lib(2);
  lib[0].name = "ok";
  lib[0].activations = {{"frontalis_inner_L", 0.5f}};
  lib[1].name = "typo";
  lib[1].activations = {{"zygomaticus_majr_L", 0.5f}};
  const std::vector<std::string> rig = {"frontalis_inner_L", "zygomaticus_major_L",
                                        "zygomaticus_minor_L"};
  Diagnostics diag;
  EXPECT_FALSE(CheckLibraryMuscles(lib, rig, "lib.json", &diag));
  EXPECT_EQ(diag.ErrorCount(), 1u);
  const std::string text = diag.Format();
  EXPECT_NE(text.find("lib.json: expressions[1].activations.zygomaticus_majr_L"), std::string::npos)
      << text;
  EXPECT_NE(text.find("'typo'"), std::string::npos) << text;
  EXPECT_NE(text.find("zygomaticus_major_L"), std::string::npos) << text;
  diag.Clear();
  EXPECT_TRUE(CheckLibraryMuscles({lib[0]}, rig, "lib.json", &diag)) << diag.Format();
}

// The shipped library: it loads, every muscle exists in the sample head rig, it has the
// papers' expressions and the action units docs/facs.md lists, and the hand-set expressions
// use the muscles their sources name (Zhang 2005 §3).
TEST(ExpressionLibrary, TheDefaultLibraryFitsTheSampleHead) {
  std::vector<Expression> lib;
  Diagnostics diag;
  ASSERT_TRUE(LoadExpressionLibrary(
      test::SourceDir() + "/assets/expressions/default.library.json", &lib, &diag))
      << diag.Format();
  LoadedRig loaded;
  ASSERT_TRUE(LoadRig(test::SourceDir() + "/assets/head/sample_head.rig.json", &loaded, &diag))
      << diag.Format();
  EXPECT_TRUE(CheckLibraryMuscles(lib, loaded.rig.muscle_names(), "default.library.json", &diag))
      << diag.Format();
  std::set<std::string> names;
  for (const Expression& e : lib) names.insert(e.name);
  for (const char* n : {"neutral", "Surprise", "Frowning", "Fear", "Thinking", "Puzzled",
                        "Disgust", "Smile", "AU1", "AU2", "AU4", "AU9", "AU10", "AU12", "AU14",
                        "AU15", "AU17", "AU20"})
    EXPECT_TRUE(names.count(n)) << n;
  auto muscles_of = [&](const std::string& name) {
    std::set<std::string> out;
    for (const Expression& e : lib)
      if (e.name == name)
        for (const auto& [m, v] : e.activations)
          if (v > 0.f) out.insert(m);
    return out;
  };
  EXPECT_TRUE(muscles_of("neutral").empty());
  // Zhang et al. 2005 §3: surprise = the frontalis major, inner and outer pairs; frowning =
  // the corrugator pair; fear = frontalis inner and corrugator.
  EXPECT_EQ(muscles_of("Surprise"),
            (std::set<std::string>{"frontalis_inner_L", "frontalis_inner_R", "frontalis_major_L",
                                   "frontalis_major_R", "frontalis_outer_L", "frontalis_outer_R"}));
  EXPECT_EQ(muscles_of("Frowning"),
            (std::set<std::string>{"corrugator_supercilii_L", "corrugator_supercilii_R"}));
  EXPECT_EQ(muscles_of("Fear"),
            (std::set<std::string>{"frontalis_inner_L", "frontalis_inner_R",
                                   "corrugator_supercilii_L", "corrugator_supercilii_R"}));
  // Every bilateral entry is symmetric: NAME_L and NAME_R at the same value.
  for (const Expression& e : lib) {
    std::map<std::string, float> a(e.activations.begin(), e.activations.end());
    for (const auto& [m, v] : a) {
      if (m == kJawInputName) continue;  // the jaw input has no sides
      const std::string side = m.substr(m.size() - 2), base = m.substr(0, m.size() - 2);
      const std::string other = base + (side == "_L" ? "_R" : "_L");
      ASSERT_TRUE(a.count(other)) << e.name << ": " << m << " without " << other;
      EXPECT_EQ(a[other], v) << e.name << ": " << m;
    }
    EXPECT_FALSE(e.description.empty() && e.name != "neutral") << e.name;
  }
}

// docs/facs.md: AU26 (jaw drop) is the jaw input at half its opening and AU27 (mouth stretch) at
// its full opening, the muscles at rest; on the sample head's rig (which has a jaw) the name
// resolves to the jaw, not to a muscle.
TEST(ExpressionLibrary, TheJawPresetsSetTheJawAsDocumented) {
  std::vector<Expression> lib;
  Diagnostics diag;
  ASSERT_TRUE(LoadExpressionLibrary(
      test::SourceDir() + "/assets/expressions/default.library.json", &lib, &diag))
      << diag.Format();
  auto find = [&](const std::string& name) -> const Expression* {
    for (const Expression& e : lib)
      if (e.name == name) return &e;
    return nullptr;
  };
  const Expression* au26 = find("AU26");
  const Expression* au27 = find("AU27");
  ASSERT_NE(au26, nullptr);
  ASSERT_NE(au27, nullptr);
  using A = std::vector<std::pair<std::string, float>>;
  EXPECT_EQ(au26->activations, (A{{"jaw", 0.5f}}));
  EXPECT_EQ(au27->activations, (A{{"jaw", 1.f}}));
  LoadedRig loaded;
  ASSERT_TRUE(LoadRig(test::SourceDir() + "/assets/head/sample_head.rig.json", &loaded, &diag))
      << diag.Format();
  EXPECT_FALSE(loaded.rig.jaw().empty());
  for (const std::string& m : loaded.rig.muscle_names()) EXPECT_NE(m, "jaw");
  // No other preset touches the jaw (the Surprise + AU26 render adds it on purpose).
  for (const Expression& e : lib) {
    if (e.name == "AU26" || e.name == "AU27") continue;
    for (const auto& [m, v] : e.activations) EXPECT_NE(m, "jaw") << e.name;
  }
}

}  // namespace
}  // namespace mimetic
