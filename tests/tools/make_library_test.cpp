// tests/tools/make_library_test.cpp: `mimetic make-library`: its usage errors, and (with
// ../shared present) that a rerun writes exactly the committed library and ARKit map, so the
// files in assets/ are what the command makes from the template and ICT-FaceKit.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.h"
#include "tools/mesh_expect.h"

namespace mimetic {
namespace {

using test::ReadText;

TEST(MakeLibrary, UsageAndBadInputs) {
  const test::ToolResult help = test::RunTool({"make-library", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("usage: mimetic make-library"), std::string::npos) << help.output;
  EXPECT_EQ(test::RunTool({"make-library", "extra"}).exit_code, 2);
  EXPECT_EQ(test::RunTool({"make-library", "--bogus"}).exit_code, 2);
  const std::string dir = test::TempDir();
  const test::ToolResult bad = test::RunTool(
      {"make-library", "--data", dir + "/nowhere", "--template",
       test::SourceDir() + "/assets/head/default.template.json", "--landmarks",
       test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json", "--library",
       dir + "/l.json", "--arkit", dir + "/a.json"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("ict_skin_neutral.obj"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("cannot read the inputs"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::ifstream(dir + "/l.json").good());
}

// A rerun of three entries (one library expression, two ARKit shapes: 3 of the 20 solves) over
// copies of the committed files writes the committed bytes: the solved entries are what the
// command computes, the kept ones round-trip. tools/make-library.sh reruns all of them.
TEST(MakeLibrary, ARerunWritesTheCommittedFiles) {
  const std::string shared = test::SharedDir();
  if (shared.empty() || !std::ifstream(shared + "/data/ict-facekit/ict_skin_neutral.obj"))
    GTEST_SKIP() << "../shared/data/ict-facekit is absent: the library is not regenerated";
  if (test::Sanitized())  // ~10x slower there; the plain build's run checks the same bytes
    GTEST_SKIP() << "sanitizer build: the library rerun runs in the plain build";
  const std::string dir = test::TempDir();
  const std::string library = test::SourceDir() + "/assets/expressions/default.library.json";
  const std::string arkit = test::SourceDir() + "/assets/arkit/default.arkit.json";
  std::filesystem::copy_file(library, dir + "/default.library.json");
  std::filesystem::copy_file(arkit, dir + "/default.arkit.json");
  // A wrong value in a solved entry of the copy must be replaced by the solve.
  std::string copy = ReadText(dir + "/default.arkit.json");
  const size_t at = copy.find("\"mouthSmileLeft\"");
  ASSERT_NE(at, std::string::npos);
  const size_t note = copy.find("\"note\": \"solved", at);
  ASSERT_NE(note, std::string::npos);
  copy.insert(note + 9, "not ");
  std::ofstream(dir + "/default.arkit.json", std::ios::binary) << copy;
  ASSERT_NE(ReadText(dir + "/default.arkit.json"), ReadText(arkit));
  const test::ToolResult r = test::RunTool(
      {"make-library", "--data", shared + "/data", "--template",
       test::SourceDir() + "/assets/head/default.template.json", "--landmarks",
       test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json", "--library",
       dir + "/default.library.json", "--arkit", dir + "/default.arkit.json", "--only",
       "AU12,mouthSmileLeft,browInnerUp"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.output.find("mouthSmile_L") != std::string::npos) << r.output;
  EXPECT_TRUE(r.output.find("browDown_L") == std::string::npos) << r.output;  // kept, not solved
  EXPECT_EQ(ReadText(dir + "/default.library.json"), ReadText(library))
      << "assets/expressions/default.library.json is not what mimetic make-library writes; "
         "rerun bash tools/make-library.sh";
  EXPECT_EQ(ReadText(dir + "/default.arkit.json"), ReadText(arkit))
      << "assets/arkit/default.arkit.json is not what mimetic make-library writes; rerun "
         "bash tools/make-library.sh";
}

TEST(MakeLibrary, OnlyRefusesUnknownNamesAndMissingFiles) {
  const test::ToolResult unknown = test::RunTool({"make-library", "--only", "AU12,smirk"});
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_TRUE(unknown.output.find("\"smirk\" is neither a library expression nor an ARKit") !=
              std::string::npos) << unknown.output;
  const std::string dir = test::TempDir();
  const test::ToolResult missing = test::RunTool(
      {"make-library", "--only", "AU12", "--library", dir + "/none.library.json", "--arkit",
       dir + "/none.arkit.json"});
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_TRUE(missing.output.find("none.library.json") != std::string::npos) << missing.output;
  EXPECT_TRUE(missing.output.find("must be readable") != std::string::npos) << missing.output;
}

}  // namespace
}  // namespace mimetic
