// The rig checks of issue 11 through the command line: each bad input gives exit 1 (or a
// warning and exit 0 where the rig is repaired) with a message that names the file and the key.
// Rigs are the sample head's (assets/head/sample_head.rig.json) with one value changed.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <utility>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "io/rig_file.h"
#include "sample_rig.h"
#include "test_support.h"

namespace mimetic {
namespace {

using json = nlohmann::json;

// An n x n grid of 10 mm squares in z = 0 with a bulge, triangles facing +z.
MeshData Grid(uint32_t n) {
  MeshData m;
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i)
      m.positions.push_back({10.f * float(i), 10.f * float(j), float(i * (n - i) + j * (n - j))});
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  return m;
}

// The sample head's rig with absolute paths, changed by `edit`, saved under the temp dir.
std::string SampleRig(const std::string& name, const std::function<void(json&)>& edit) {
  return test::EditedSampleRig(name, edit);
}

void ExpectRefused(const std::vector<std::string>& args, const std::string& message) {
  const test::ToolResult r = test::RunTool(args);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << "expected: " << message << "\n" << r.output;
}

TEST(RigChecksCli, AbsurdMagnitudesAreRefusedNamingTheKey) {
  // The sample head: about 155 x 230 x 220 mm; its bounding-box diagonal is 354 mm.
  const std::string thick = SampleRig("thick", [](json& j) {
    j["thickness"] = {{"type", "constant"}, {"value", 3e38}};
  });
  ExpectRefused({"validate", thick},
                thick + ": thickness.value: is 3e+38 mm, more than 10 times the mesh's size "
                        "(bounding-box diagonal ");
  ExpectRefused({"eval", thick, "--out", test::TempDir() + "/x.glb"}, thick + ": thickness.value");
  const std::string deep = SampleRig("deep", [](json& j) {
    for (json& m : j["muscles"])
      if (m.contains("wrinkles")) {
        m["wrinkles"]["depth"] = 3e38;
        break;
      }
  });
  ExpectRefused({"validate", deep}, deep + ": muscles[0].wrinkles.depth: is 3e+38 mm");
  size_t linear = 0;
  const std::string far = SampleRig("far", [&](json& j) {
    while (j["muscles"][linear]["type"] != "linear") ++linear;
    j["muscles"][linear]["attachment"] = {1e38, 0, 0};
  });
  ExpectRefused({"validate", far}, far + ": muscles[" + std::to_string(linear) +
                                         "].attachment: (1e+38, 0, 0) is 1e+38 mm from the "
                                         "mesh's centre");
}

TEST(RigChecksCli, MeshCoordinatesAt1e38AreRefused) {
  MeshData mesh = Grid(10);
  mesh.positions[3].y = 1e38f;
  const std::string dir = test::TempDir();
  Diagnostics diag;
  ASSERT_TRUE(ExportMesh(dir + "/far.obj", mesh, &diag)) << diag.Format();
  std::ofstream(dir + "/far.rig.json") << R"({"format": "mimetic-rig", "version": 1,
      "mesh": {"path": "far.obj"}, "units": "mm", "muscles": []})";
  ExpectRefused({"validate", dir + "/far.rig.json"},
                "1 vertices have a coordinate beyond 1e+06 mm (1 km; first: vertex 3 at (");
}

TEST(RigChecksCli, TinyWrinkleValuesAreRefusedBeforeRefining) {
  const std::string narrow = SampleRig("narrow", [](json& j) { j["curve_wrinkles"][0]["width"] = 0.01; });
  // "from N": the triangles of the sample head's mesh file.
  MeshData head;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(test::SourceDir() + "/assets/head/sample_head.glb", "", &head, &diag))
      << diag.Format();
  ExpectRefused({"validate", narrow},
                narrow + ": curve_wrinkles[0].width: refinement where wrinkles act and fall-offs "
                         "bend would grow the mesh from " + std::to_string(head.triangle_count()) +
                         " to about ");
  const std::string many = SampleRig("many", [](json& j) {
    j["muscles"][0]["wrinkles"]["count"] = 2147483647;
  });
  ExpectRefused({"validate", many}, many + ": muscles[0].wrinkles.count: refinement");
  const std::string fine = SampleRig("fine", [](json& j) {
    j["refinement"] = {{"enabled", true}, {"edge_fraction", 1e-30}};
  });
  ExpectRefused({"validate", fine}, fine + ": refinement.edge_fraction: refinement");
}

TEST(RigChecksCli, FlippedWindingIsRepairedWithAWarning) {
  MeshData mesh = Grid(10);  // 200 triangles
  for (size_t t = 1; t < mesh.triangle_count(); t += 2)
    std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
  const std::string dir = test::TempDir();
  Diagnostics diag;
  ASSERT_TRUE(ExportMesh(dir + "/flipped.obj", mesh, &diag)) << diag.Format();
  std::ofstream(dir + "/flipped.rig.json") << R"({"format": "mimetic-rig", "version": 1,
      "mesh": {"path": "flipped.obj"}, "units": "mm", "muscles": []})";
  const test::ToolResult r = test::RunTool({"validate", dir + "/flipped.rig.json"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("100 of 200 triangles (50.0%) were wound against their neighbours "
                          "(first: triangle 1)"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace mimetic
