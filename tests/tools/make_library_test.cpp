// tests/tools/make_library_test.cpp: `mimetic make-library`: its usage errors, and (with
// ../shared present) that a rerun writes exactly the committed library and ARKit map, so the
// files in assets/ are what the command makes from the template and ICT-FaceKit.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "test_support.h"

namespace mimetic {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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

TEST(MakeLibrary, ARerunWritesTheCommittedFiles) {
  const std::string shared = test::SharedDir();
  if (shared.empty() || !std::ifstream(shared + "/data/ict-facekit/ict_skin_neutral.obj"))
    GTEST_SKIP() << "../shared/data/ict-facekit is absent: the library is not regenerated";
  if (test::Sanitized())  // ~10x slower there; the plain build's run checks the same bytes
    GTEST_SKIP() << "sanitizer build: the library rerun (20 solves) runs in the plain build";
  const std::string dir = test::TempDir();
  const test::ToolResult r = test::RunTool(
      {"make-library", "--data", shared + "/data", "--template",
       test::SourceDir() + "/assets/head/default.template.json", "--landmarks",
       test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json", "--library",
       dir + "/default.library.json", "--arkit", dir + "/default.arkit.json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadText(dir + "/default.library.json"),
            ReadText(test::SourceDir() + "/assets/expressions/default.library.json"))
      << "assets/expressions/default.library.json is not what mimetic make-library writes; "
         "rerun bash tools/make-library.sh";
  EXPECT_EQ(ReadText(dir + "/default.arkit.json"),
            ReadText(test::SourceDir() + "/assets/arkit/default.arkit.json"))
      << "assets/arkit/default.arkit.json is not what mimetic make-library writes; rerun "
         "bash tools/make-library.sh";
}

}  // namespace
}  // namespace mimetic
