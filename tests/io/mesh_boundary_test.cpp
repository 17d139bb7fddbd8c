// The glTF / OBJ boundary of io/mesh_io (docs/errors.md): the JSON guard before tinygltf,
// required extensions, node transforms, skins and morph targets, the metre scale of glTF
// output and OBJ's v convention, with their round trips.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace mimetic {
namespace {

using nlohmann::json;

std::string Base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

// One triangle (0,0,0), (10,0,0), (0,10,0), indexed 0 1 2, embedded buffer; `node` places it.
json Triangle(const json& node = json{{"mesh", 0}}) {
  std::string blob(44, '\0');
  const float p[9] = {0, 0, 0, 10, 0, 0, 0, 10, 0};
  const uint16_t idx[3] = {0, 1, 2};
  std::memcpy(&blob[0], p, 36);
  std::memcpy(&blob[36], idx, 6);
  json g = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", 44},
                    {"uri", "data:application/octet-stream;base64," + Base64(blob)}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
                       {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                     {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
      {"meshes", {{{"name", "tri"}, {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"nodes", json::array({node})},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  return g;
}

bool Import(const json& g, MeshData* m, Diagnostics* d) {
  return ImportMeshBytes(g.dump(), ".gltf", "", "", m, d);
}

TEST(GltfBoundary, DeeplyNestedExtrasAreRefusedBeforeTinygltf) {
  // 300,000 levels overflowed tinygltf's recursive parser (a crash); now the JSON reader's
  // guard refuses them with the place where nesting passes 64 levels.
  std::string text = Triangle().dump();
  text.pop_back();
  const std::string head = ",\"extras\":";
  text += head + std::string(300000, '[') + std::string(300000, ']') + "}";
  MeshData m;
  Diagnostics d;
  EXPECT_FALSE(ImportMeshBytes(text, ".gltf", "", "", &m, &d));
  // The top-level object is level 1, so the 64th '[' is the 65th level.
  const size_t column = Triangle().dump().size() - 1 + head.size() + 64;
  EXPECT_EQ(d.Format(), "error: glTF JSON: nested deeper than 64 levels at line 1, column " +
                            std::to_string(column) +
                            "; expected at most 64 levels of arrays and objects\n");
}

TEST(GltfBoundary, GlbLengthFieldBelowItsHeaderIsRefused) {
  // Found by fuzz_mesh_glb: a length field of 11 made "length - 20" wrap around, and the JSON
  // chunk was read past the end of the file.
  const std::string json = Triangle().dump();
  std::string glb = "glTF";
  const uint32_t header[3] = {2, 11, static_cast<uint32_t>(json.size())};
  glb.append(reinterpret_cast<const char*>(header), 12);
  glb += "JSON" + json;
  MeshData m;
  Diagnostics d;
  EXPECT_FALSE(ImportMeshBytes(glb, ".glb", "", "", &m, &d));
  EXPECT_EQ(d.Format(), "error: GLB header says the file is 11 bytes (expected at least 20: the "
                        "header and a JSON chunk)\n");
}

TEST(GltfBoundary, CompressionAndUnknownRequiredExtensionsAreRefused) {
  for (const char* ext : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
    json g = Triangle();
    g["extensionsRequired"] = {ext};
    MeshData m;
    Diagnostics d;
    EXPECT_FALSE(Import(g, &m, &d));
    EXPECT_EQ(d.Format(), std::string("error: extensionsRequired[0]: compressed glTF (") + ext +
                              ") is not supported; decompress it first, e.g. with gltf-transform "
                              "(npm @gltf-transform/cli): gltf-transform copy in.glb out.glb\n");
  }
  json g = Triangle();
  g["extensionsRequired"] = {"KHR_materials_unlit", "KHR_mesh_quantization"};
  MeshData m;
  Diagnostics d;
  EXPECT_FALSE(Import(g, &m, &d));
  ASSERT_EQ(d.items().size(), 1u) << d.Format();  // the material extension is harmless
  EXPECT_EQ(d.items()[0].where, "extensionsRequired[1]");
  EXPECT_NE(d.items()[0].what.find("requires extension KHR_mesh_quantization, which mimetic "
                                   "does not support"),
            std::string::npos);
}

TEST(GltfBoundary, NegativeValuesAndMissingReferencesNameTheirJsonPath) {
  json g = Triangle();
  g["accessors"][0]["byteOffset"] = -4;
  g["bufferViews"][1]["byteStride"] = -2;
  g["accessors"][1]["bufferView"] = 9;
  g["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 5;
  g["nodes"][0]["mesh"] = 2;
  MeshData m;
  Diagnostics d;
  EXPECT_FALSE(Import(g, &m, &d));
  EXPECT_EQ(d.Format(),
            "error: accessors[0].byteOffset: -4 is negative (expected an integer >= 0)\n"
            "error: accessors[1].bufferView: bufferView 9 does not exist (the file has 2 bufferViews)\n"
            "error: bufferViews[1].byteStride: -2 is negative (expected an integer >= 0)\n"
            "error: meshes[0].primitives[0].attributes.NORMAL: accessor 5 does not exist (the file has 2 accessors)\n"
            "error: nodes[0].mesh: mesh 2 does not exist (the file has 1 meshes)\n");
}

TEST(GltfBoundary, NodeRotationAndTranslationAreApplied) {
  // 90 degrees about +Y: (x, y, z) -> (z, y, -x); then + (1, 2, 3).
  const float h = 0.70710678f;
  MeshData m;
  Diagnostics d;
  ASSERT_TRUE(Import(Triangle({{"mesh", 0}, {"rotation", {0, h, 0, h}}, {"translation", {1, 2, 3}}}),
                     &m, &d))
      << d.Format();
  ASSERT_EQ(m.positions.size(), 3u);
  const float3 want[3] = {{1, 2, 3}, {1, 2, -7}, {1, 12, 3}};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(m.positions[i].x, want[i].x, 1e-5) << i;
    EXPECT_NEAR(m.positions[i].y, want[i].y, 1e-5) << i;
    EXPECT_NEAR(m.positions[i].z, want[i].z, 1e-5) << i;
  }
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(GltfBoundary, UniformScaleStatesTheUnitAndIsNotApplied) {
  // A parent node in metres (scale 0.001) with a child translated by 0.01 m = 10 mesh units.
  json g = Triangle();
  g["nodes"] = {{{"scale", {0.001, 0.001, 0.001}}, {"children", {1}}},
                {{"mesh", 0}, {"translation", {10, 0, 0}}}};
  MeshData m;
  Diagnostics d;
  ASSERT_TRUE(Import(g, &m, &d)) << d.Format();
  EXPECT_NEAR(m.positions[0].x, 10.f, 1e-4);
  EXPECT_NEAR(m.positions[1].x, 20.f, 1e-4);
  EXPECT_NEAR(m.positions[2].y, 10.f, 1e-4);
}

TEST(GltfBoundary, MirrorFlipsWindingAndShearIsRefused) {
  MeshData m;
  Diagnostics d;
  ASSERT_TRUE(Import(Triangle({{"mesh", 0}, {"scale", {-1, 1, 1}}}), &m, &d)) << d.Format();
  EXPECT_EQ(m.positions[1].x, -10.f);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 2, 1}));

  d.Clear();
  EXPECT_FALSE(Import(Triangle({{"mesh", 0}, {"scale", {1, 2, 1}}}), &m, &d));
  EXPECT_EQ(d.Format(), "error: mesh 'tri': node 0 places the mesh with a non-uniform scale or "
                        "shear; mimetic applies rotation, translation and a uniform scale only "
                        "(apply the transform in the exporting tool, e.g. Blender's Apply > "
                        "Scale)\n");
}

TEST(GltfBoundary, SkinsAndMorphTargetsAreIgnoredWithAWarning) {
  json g = Triangle();
  g["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 0}}};
  g["skins"] = {{{"joints", {0}}}};
  MeshData m;
  Diagnostics d;
  ASSERT_TRUE(Import(g, &m, &d)) << d.Format();
  EXPECT_EQ(d.Format(),
            "warning: mesh 'tri': has 1 morph targets; ignored (the base shape is read, no "
            "weights applied)\n"
            "warning: the file has 1 skin(s); ignored (positions are the mesh's bind pose, no "
            "joints applied)\n");
  EXPECT_EQ(m.positions[1].x, 10.f);
}

TEST(GltfBoundary, BufferUriThatIsADirectoryOrMissingIsRefused) {
  const std::string dir = test::TempDir();
  json g = Triangle();
  g["buffers"][0]["uri"] = "sub";
  std::filesystem::create_directory(dir + "/sub");
  std::ofstream(dir + "/t.gltf") << g.dump();
  MeshData m;
  Diagnostics d;
  EXPECT_FALSE(ImportMesh(dir + "/t.gltf", "", &m, &d));
  EXPECT_EQ(d.Format(), "error: glTF buffer '" + dir +
                            "/sub' is not a regular file (it is a directory; expected a glTF "
                            "buffer or image)\n");
  g["buffers"][0]["uri"] = "none.bin";
  std::ofstream(dir + "/t.gltf") << g.dump();
  d.Clear();
  EXPECT_FALSE(ImportMesh(dir + "/t.gltf", "", &m, &d));
  EXPECT_EQ(d.Format(), "error: glTF buffer '" + dir +
                            "/none.bin' cannot open: No such file or directory\n");
}

TEST(MeshFiles, ADirectoryIsNotAnEmptyFile) {
  const std::string dir = test::TempDir() + "/head.glb";
  std::filesystem::create_directory(dir);
  MeshData m;
  Diagnostics d;
  EXPECT_FALSE(ImportMesh(dir, "", &m, &d));
  EXPECT_EQ(d.Format(), "error: is not a regular file (it is a directory; expected a glb mesh file)\n");
}

void ExpectSameUvs(const std::vector<float2>& a, const std::vector<float2>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x) << i;
    EXPECT_EQ(a[i].y, b[i].y) << i;
  }
}

MeshData UvTriangle() {
  MeshData m;
  m.positions = {{0.1f, 0, 0}, {10, 0.2f, 0}, {0, 10, 1.f / 3.f}};
  m.uvs = {{0.25f, 0.25f}, {1, 0}, {0, 0.875f}};
  m.indices = {0, 1, 2};
  return m;
}

TEST(MeshOutput, GlbIsInMetresAndReadsBackInMeshUnits) {
  const std::string path = test::TempDir() + "/t.glb";
  const MeshData m = UvTriangle();
  Diagnostics d;
  ASSERT_TRUE(ExportMesh(path, m, &d, MetresPerUnit("mm"))) << d.Format();
  std::string bytes;
  ASSERT_TRUE(ReadFile(path, &bytes, &d));
  uint32_t json_length;
  std::memcpy(&json_length, bytes.data() + 12, 4);
  const json g = json::parse(bytes.substr(20, json_length));
  ASSERT_EQ(g["nodes"].size(), 1u);
  EXPECT_EQ(g["nodes"][0]["name"], "mimetic_units");
  EXPECT_EQ(g["nodes"][0]["scale"], json({0.001, 0.001, 0.001}));
  MeshData back;
  ASSERT_TRUE(ImportMesh(path, "", &back, &d)) << d.Format();
  EXPECT_EQ(back.positions, m.positions);  // exactly: the unit scale is not applied
  ExpectSameUvs(back.uvs, m.uvs);
  EXPECT_EQ(MetresPerUnit("in"), 0.0254);
  EXPECT_EQ(MetresPerUnit("m"), 1.0);
  EXPECT_EQ(MetresPerUnit("furlong"), 0.0);
}

TEST(MeshOutput, ObjWritesVUpAndReadsItBack) {
  const std::string path = test::TempDir() + "/t.obj";
  const MeshData m = UvTriangle();
  Diagnostics d;
  ASSERT_TRUE(ExportMesh(path, m, &d)) << d.Format();
  std::string text;
  ASSERT_TRUE(ReadFile(path, &text, &d));
  EXPECT_NE(text.find("vt 0.25 0.75\nvt 1 1\nvt 0 0.125\n"), std::string::npos) << text;
  MeshData back;
  ASSERT_TRUE(ImportMesh(path, "", &back, &d)) << d.Format();
  EXPECT_EQ(back.positions, m.positions);
  ExpectSameUvs(back.uvs, m.uvs);
}

TEST(MeshFiles, ObjMtllibIsIgnoredWithAWarning) {
  const std::string dir = test::TempDir();
  ASSERT_EQ(::mkfifo((dir + "/m.mtl").c_str(), 0600), 0);  // OpenMesh would block on it
  std::ofstream(dir + "/t.obj") << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  MeshData m;
  Diagnostics d;
  ASSERT_TRUE(ImportMesh(dir + "/t.obj", "", &m, &d)) << d.Format();
  EXPECT_EQ(d.Format(), "warning: line 1: 'mtllib' ignored (materials are not read)\n");
  EXPECT_EQ(m.triangle_count(), 1u);
}

}  // namespace
}  // namespace mimetic
