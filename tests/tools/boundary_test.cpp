// The CLI at the file boundary (docs/errors.md): exit codes, output names, integer options,
// the printing cap, validate's second report, and outputs that would overwrite inputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace mimetic {
namespace {

using test::RunTool;

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

size_t Lines(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(CliBoundary, IntegerOptionsRefuseFractions) {
  const std::string dir = test::TempDir();
  for (const char* bad : {"2.9", "3e0", "0x10", " 3", "3 ", ""}) {
    const auto r = RunTool({"make-surface", "--out", dir + "/s.obj", "--columns", bad});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(Contains(r.output, std::string("--columns '") + bad +
                                       "': expected a whole number in [2, 4096]"))
        << r.output;
  }
  const auto ok = RunTool({"make-surface", "--out", dir + "/s.obj", "--columns", "3", "--rows", "2"});
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  std::ifstream in(dir + "/s.obj");
  size_t v = 0;
  for (std::string line; std::getline(in, line);) v += line.rfind("v ", 0) == 0;
  EXPECT_EQ(v, 6u);  // 3 x 2 vertices, not 2 x 2
}

TEST(CliBoundary, UnknownOutputExtensionExitsTwoInEveryCommand) {
  const std::string dir = test::TempDir();
  const std::string rig = test::SourceDir() + "/assets/surface/surface.rig.json";
  const std::string mesh = test::SourceDir() + "/assets/surface/surface.obj";
  struct Case {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"eval", rig, "--out", dir + "/x.stl"}, "--out " + dir + "/x.stl: expected a .obj or .glb file name"},
      {{"make-surface", "--out", dir + "/x.stl"}, "--out " + dir + "/x.stl: expected a .obj or .glb file name"},
      {{"make-head", "--out", dir + "/x.ply"}, "--out " + dir + "/x.ply: expected a .obj or .glb file name"},
      {{"render", mesh, "--out", dir + "/x.jpg"}, "--out " + dir + "/x.jpg: expected a .png file name"},
      {{"compare", mesh, mesh, "--heatmap", dir + "/h.bmp"}, "--heatmap " + dir + "/h.bmp: expected a .png file name"},
  };
  for (const Case& c : cases) {
    const auto r = RunTool(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args[0] << "\n" << r.output;
    EXPECT_TRUE(Contains(r.output, c.message)) << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.jpg"));  // PNG bytes under a .jpg name: never
}

TEST(CliBoundary, EvalRefusesToOverwriteTheRigOrItsMesh) {
  const std::string dir = test::TempDir();
  for (const char* f : {"surface.rig.json", "surface.obj"})
    std::filesystem::copy_file(test::SourceDir() + "/assets/surface/" + f, dir + "/" + f);
  const std::string before = [&] {
    std::ifstream in(dir + "/surface.obj");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  auto r = RunTool({"eval", dir + "/surface.rig.json", "--out", dir + "/surface.obj"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(Contains(r.output, "--out " + dir + "/surface.obj is " + dir +
                                     "/surface.obj, an input of the rig; expected another file name"))
      << r.output;
  // Another spelling of the same file.
  r = RunTool({"eval", dir + "/surface.rig.json", "--out", dir + "/./surface.obj"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  std::ifstream in(dir + "/surface.obj");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), before);
}

TEST(CliBoundary, ValidateReportsABadFieldAndTheMissingMeshTogether) {
  const std::string dir = test::TempDir();
  std::ifstream in(test::SourceDir() + "/assets/surface/surface.rig.json");
  nlohmann::json rig = nlohmann::json::parse(in);
  rig["units"] = "furlong";
  rig["mesh"]["path"] = "gone.obj";
  std::ofstream(dir + "/r.rig.json") << rig.dump();
  const auto r = RunTool({"validate", dir + "/r.rig.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.output, "error: " + dir + "/r.rig.json: units: expected one of"))
      << r.output;
  EXPECT_TRUE(Contains(r.output, "error: " + dir + "/r.rig.json: mesh.path: " + dir +
                                     "/gone.obj: cannot open: No such file or directory"))
      << r.output;
  // Each message names the rig file once.
  EXPECT_FALSE(Contains(r.output, "r.rig.json: " + dir + "/r.rig.json")) << r.output;
}

TEST(CliBoundary, ManyBadEntriesPrintAtMostFiftyLines) {
  const std::string dir = test::TempDir();
  std::ifstream in(test::SourceDir() + "/assets/surface/surface.rig.json");
  nlohmann::json rig = nlohmann::json::parse(in);
  for (int i = 0; i < 20000; ++i) rig["unknown_" + std::to_string(i)] = i;
  std::ofstream(dir + "/r.rig.json") << rig.dump();
  const auto r = RunTool({"validate", dir + "/r.rig.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_LE(Lines(r.output), 52u) << r.output.substr(0, 2000);
  EXPECT_TRUE(Contains(r.output, " more (")) << r.output.substr(0, 4000);
  EXPECT_TRUE(Contains(r.output, "not shown")) << r.output.substr(0, 4000);
}

TEST(CliBoundary, BadPngNamesTheFileAndTheReason) {
  const std::string dir = test::TempDir();
  std::filesystem::copy_file(test::SourceDir() + "/assets/surface/surface.obj", dir + "/surface.obj");
  std::ifstream in(test::SourceDir() + "/assets/surface/surface.rig.json");
  nlohmann::json rig = nlohmann::json::parse(in);
  rig["thickness"] = {{"type", "image"}, {"path", "t.png"}, {"min", 0}, {"max", 3}};
  std::ofstream(dir + "/r.rig.json") << rig.dump();
  std::ofstream(dir + "/t.png", std::ios::binary) << std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
  const auto r = RunTool({"validate", dir + "/r.rig.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.output, "r.rig.json: thickness.path: cannot read thickness image '" + dir +
                                     "/t.png': "))
      << r.output;
  EXPECT_FALSE(Contains(r.output, "unknown error")) << r.output;
}

}  // namespace
}  // namespace mimetic
