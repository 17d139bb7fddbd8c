// Tests for ImportMesh / ExportMesh (geometry/mesh.h), and the bad-input table that runs
// import + weld on broken files and checks each message names the broken element.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/weld.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace mimetic {
namespace {

// A 3x3 grid of points (x = col, y = row) made of 2x2 quads, with a UV seam down the middle
// column: the right-hand quads use duplicates of the middle column's vertices (9, 10, 11), so
// the file has 9 + 3 = 12 vertices, 8 triangles and, welded, 9 points.
//   vertex j*3+i = point (i, j); vertex 9+j = duplicate of vertex j*3+1.
const std::vector<uint32_t> kGridIndices = {0, 1, 4, 0, 4, 3,  9,  2, 5, 9,  5, 10,
                                            3, 4, 7, 3, 7, 6, 10,  5, 8, 10, 8, 11};

float GridCoord(int i) { return 0.1f * static_cast<float>(i) + 1.f / 3.f; }  // not round

MeshData SeamGrid() {
  MeshData m;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      m.positions.push_back({GridCoord(i), GridCoord(j), 0.25f});
      m.uvs.push_back({0.5f * static_cast<float>(i), 0.5f * static_cast<float>(j)});
    }
  }
  for (int j = 0; j < 3; ++j) {
    m.positions.push_back({GridCoord(1), GridCoord(j), 0.25f});
    m.uvs.push_back({0.75f, 0.5f * static_cast<float>(j)});
  }
  m.normals.assign(m.positions.size(), float3{0.f, 0.f, 1.f});
  m.indices = kGridIndices;
  return m;
}

// Builds a one-buffer glTF model from a mesh: POSITION, NORMAL, TEXCOORD_0 (when present)
// and indices of the given component type (or none).
struct GltfOptions {
  bool indexed = true;
  int index_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  int mode = TINYGLTF_MODE_TRIANGLES;
  std::string mesh_name = "grid";
};

tinygltf::Model BuildModel(const MeshData& m, const GltfOptions& o = {}) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  tinygltf::Buffer buffer;
  auto view = [&](const void* data, size_t bytes) {
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = buffer.data.size();
    bv.byteLength = bytes;
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.data.insert(buffer.data.end(), p, p + bytes);
    while (buffer.data.size() % 4) buffer.data.push_back(0);
    model.bufferViews.push_back(bv);
    return static_cast<int>(model.bufferViews.size()) - 1;
  };
  auto accessor = [&](int bv, int component, size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = bv;
    a.byteOffset = 0;
    a.componentType = component;
    a.count = count;
    a.type = type;
    a.normalized = false;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size()) - 1;
  };
  tinygltf::Primitive prim;
  prim.mode = o.mode;
  const size_t nv = m.positions.size();
  prim.attributes["POSITION"] = accessor(view(m.positions.data(), nv * 12),
                                         TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
  if (!m.normals.empty()) {
    prim.attributes["NORMAL"] = accessor(view(m.normals.data(), m.normals.size() * 12),
                                         TINYGLTF_COMPONENT_TYPE_FLOAT, m.normals.size(),
                                         TINYGLTF_TYPE_VEC3);
  }
  if (!m.uvs.empty()) {
    prim.attributes["TEXCOORD_0"] = accessor(view(m.uvs.data(), m.uvs.size() * 8),
                                             TINYGLTF_COMPONENT_TYPE_FLOAT, m.uvs.size(),
                                             TINYGLTF_TYPE_VEC2);
  }
  if (o.indexed) {
    std::vector<unsigned char> bytes;
    for (uint32_t i : m.indices) {
      if (o.index_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        bytes.push_back(static_cast<unsigned char>(i));
      } else if (o.index_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        const uint16_t s = static_cast<uint16_t>(i);
        bytes.insert(bytes.end(), reinterpret_cast<const unsigned char*>(&s),
                     reinterpret_cast<const unsigned char*>(&s) + 2);
      } else {
        bytes.insert(bytes.end(), reinterpret_cast<const unsigned char*>(&i),
                     reinterpret_cast<const unsigned char*>(&i) + 4);
      }
    }
    prim.indices = accessor(view(bytes.data(), bytes.size()), o.index_type, m.indices.size(),
                            TINYGLTF_TYPE_SCALAR);
  }
  model.buffers.push_back(buffer);
  tinygltf::Mesh mesh;
  mesh.name = o.mesh_name;
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  return model;
}

// Non-indexed version of a mesh: each triangle corner becomes its own vertex.
MeshData Unindex(const MeshData& m) {
  MeshData out;
  for (uint32_t i : m.indices) {
    out.positions.push_back(m.positions[i]);
    if (!m.uvs.empty()) out.uvs.push_back(m.uvs[i]);
    if (!m.normals.empty()) out.normals.push_back(m.normals[i]);
  }
  return out;
}

std::string WriteModel(const tinygltf::Model& model, const std::string& path) {
  tinygltf::TinyGLTF writer;
  const bool binary = path.size() > 4 && path.substr(path.size() - 4) == ".glb";
  EXPECT_TRUE(writer.WriteGltfSceneToFile(&model, path, true, true, true, binary)) << path;
  return path;
}

std::string WriteText(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  return path;
}

void ExpectSame(const MeshData& expected, const MeshData& got, bool normals = true) {
  ASSERT_EQ(got.positions.size(), expected.positions.size());
  for (size_t i = 0; i < expected.positions.size(); ++i) {
    EXPECT_EQ(got.positions[i].x, expected.positions[i].x) << "vertex " << i;
    EXPECT_EQ(got.positions[i].y, expected.positions[i].y) << "vertex " << i;
    EXPECT_EQ(got.positions[i].z, expected.positions[i].z) << "vertex " << i;
  }
  ASSERT_EQ(got.uvs.size(), expected.uvs.size());
  for (size_t i = 0; i < expected.uvs.size(); ++i) {
    EXPECT_EQ(got.uvs[i].x, expected.uvs[i].x) << "vertex " << i;
    EXPECT_EQ(got.uvs[i].y, expected.uvs[i].y) << "vertex " << i;
  }
  if (normals) {
    ASSERT_EQ(got.normals.size(), expected.normals.size());
    for (size_t i = 0; i < expected.normals.size(); ++i) {
      EXPECT_EQ(got.normals[i], expected.normals[i]) << "vertex " << i;
    }
  }
  EXPECT_EQ(got.indices, expected.indices);
}

// ---------------------------------------------------------------------------------------
// glTF import

TEST(MeshImportGltf, SeamGridGltfAndGlbAllIndexTypes) {
  const std::string dir = test::TempDir();
  const MeshData grid = SeamGrid();
  const int types[] = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};
  for (const char* ext : {".gltf", ".glb"}) {
    for (int type : types) {
      SCOPED_TRACE(std::string(ext) + " index type " + std::to_string(type));
      GltfOptions o;
      o.index_type = type;
      const std::string path =
          WriteModel(BuildModel(grid, o), dir + "/grid" + std::to_string(type) + ext);
      MeshData mesh;
      Diagnostics diag;
      ASSERT_TRUE(ImportMesh(path, "", &mesh, &diag)) << diag.Format();
      EXPECT_EQ(mesh.vertex_count(), 12u);
      EXPECT_EQ(mesh.triangle_count(), 8u);
      EXPECT_EQ(mesh.source, path);
      // Written values, independent of SeamGrid(): vertex 10 duplicates vertex 4 = (1, 1).
      EXPECT_EQ(mesh.positions[10].x, 0.1f + 1.f / 3.f);
      EXPECT_EQ(mesh.positions[10].y, 0.1f + 1.f / 3.f);
      EXPECT_EQ(mesh.uvs[10].x, 0.75f);
      EXPECT_EQ(mesh.uvs[4].x, 0.5f);
      ExpectSame(grid, mesh);
    }
  }
}

TEST(MeshImportGltf, NonIndexedPrimitive) {
  const std::string dir = test::TempDir();
  const MeshData flat = Unindex(SeamGrid());
  GltfOptions o;
  o.indexed = false;
  const std::string path = WriteModel(BuildModel(flat, o), dir + "/flat.glb");
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(path, "", &mesh, &diag)) << diag.Format();
  EXPECT_EQ(mesh.vertex_count(), 24u);  // 8 triangles x 3 corners
  ASSERT_EQ(mesh.triangle_count(), 8u);
  for (uint32_t i = 0; i < 24; ++i) EXPECT_EQ(mesh.indices[i], i);
  // Triangle 2 of the grid is (9, 2, 5): its first corner is the seam duplicate of (1, 0).
  EXPECT_EQ(mesh.positions[6].x, 0.1f + 1.f / 3.f);
  EXPECT_EQ(mesh.uvs[6].x, 0.75f);
}

// Interleaved POSITION + TEXCOORD_0 (stride 20) behind a non-zero bufferView and accessor
// byteOffset, u16 indices; and a second primitive that is concatenated.
TEST(MeshImportGltf, HonoursStrideOffsetsAndConcatenatesPrimitives) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  tinygltf::Buffer buffer;
  buffer.data.assign(16, 0xEE);  // junk before the bufferView
  const float verts[4][5] = {{0, 0, 0, 0.f, 0.f}, {1, 0, 0, 1.f, 0.f},
                             {1, 1, 0, 1.f, 1.f}, {0, 1, 0, 0.f, 1.f}};
  const size_t view_start = buffer.data.size();
  buffer.data.resize(view_start + 8, 0xAA);  // junk before the accessor (accessor byteOffset 8)
  for (const auto& v : verts) {
    const auto* p = reinterpret_cast<const unsigned char*>(v);
    buffer.data.insert(buffer.data.end(), p, p + 20);
  }
  const size_t index_start = buffer.data.size();
  const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  buffer.data.insert(buffer.data.end(), reinterpret_cast<const unsigned char*>(idx),
                     reinterpret_cast<const unsigned char*>(idx) + 12);
  model.buffers.push_back(buffer);
  tinygltf::BufferView interleaved;
  interleaved.buffer = 0;
  interleaved.byteOffset = view_start;
  interleaved.byteLength = 8 + 4 * 20;
  interleaved.byteStride = 20;
  tinygltf::BufferView indices;
  indices.buffer = 0;
  indices.byteOffset = index_start;
  indices.byteLength = 12;
  model.bufferViews = {interleaved, indices};
  tinygltf::Accessor pos, uv, ind;
  pos.bufferView = 0;
  pos.byteOffset = 8;
  pos.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  pos.count = 4;
  pos.type = TINYGLTF_TYPE_VEC3;
  uv = pos;
  uv.byteOffset = 8 + 12;
  uv.type = TINYGLTF_TYPE_VEC2;
  ind.bufferView = 1;
  ind.byteOffset = 0;
  ind.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  ind.count = 6;
  ind.type = TINYGLTF_TYPE_SCALAR;
  model.accessors = {pos, uv, ind};
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes = {{"POSITION", 0}, {"TEXCOORD_0", 1}};
  prim.indices = 2;
  tinygltf::Mesh other, quad;
  other.name = "other";
  other.primitives = {prim};
  quad.name = "quad";
  quad.primitives = {prim, prim};  // the same data twice: 8 vertices, 4 triangles
  model.meshes = {other, quad};
  const std::string path = WriteModel(model, test::TempDir() + "/interleaved.gltf");

  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(path, "quad", &mesh, &diag)) << diag.Format();
  ASSERT_EQ(mesh.vertex_count(), 8u);
  ASSERT_EQ(mesh.triangle_count(), 4u);
  EXPECT_TRUE(mesh.normals.empty());
  for (int v = 0; v < 8; ++v) {
    EXPECT_EQ(mesh.positions[v].x, verts[v % 4][0]) << v;
    EXPECT_EQ(mesh.positions[v].y, verts[v % 4][1]) << v;
    EXPECT_EQ(mesh.positions[v].z, 0.f) << v;
    EXPECT_EQ(mesh.uvs[v].x, verts[v % 4][3]) << v;
    EXPECT_EQ(mesh.uvs[v].y, verts[v % 4][4]) << v;
  }
  const std::vector<uint32_t> expected = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  EXPECT_EQ(mesh.indices, expected);

  // Empty name picks the first mesh ("other", one primitive).
  ASSERT_TRUE(ImportMesh(path, "", &mesh, &diag)) << diag.Format();
  EXPECT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(mesh.triangle_count(), 2u);
}

TEST(MeshImportGltf, WeldsSeamGridToNinePoints) {
  const std::string path = WriteModel(BuildModel(SeamGrid()), test::TempDir() + "/grid.glb");
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(path, "grid", &mesh, &diag)) << diag.Format();
  WeldedMesh welded;
  ASSERT_TRUE(WeldMesh(mesh, 0.f, &welded, &diag)) << diag.Format();
  EXPECT_EQ(welded.points.size(), 9u);
  // Seam duplicates 9, 10, 11 map to the middle column's points 1, 4, 7.
  const std::vector<uint32_t> pov = {0, 1, 2, 3, 4, 5, 6, 7, 8, 1, 4, 7};
  EXPECT_EQ(welded.point_of_vertex, pov);
  // Same triangles, written with the grid's point numbers j*3+i.
  const std::vector<uint32_t> tris = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4,
                                      3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7};
  EXPECT_EQ(welded.triangles, tris);
  EXPECT_TRUE(diag.empty()) << diag.Format();
}

// ---------------------------------------------------------------------------------------
// OBJ import

TEST(MeshImportObj, SeamQuadAndTriangle) {
  // A unit quad 1-2-3-4 and a triangle 2-5-3 that uses another texcoord (vt 5) at vertex 2.
  const std::string path = WriteText(test::TempDir() + "/seam.obj",
                                     "# seam test\n"
                                     "o seam\n"
                                     "v 0 0 0\n"
                                     "v 1 0 0\n"
                                     "v 1 1 0\n"
                                     "v 0 1 0\n"
                                     "  v 2 0.5 0\n"  // leading blanks are fine
                                     "vt 0 0\n"
                                     "vt 1 0\n"
                                     "vt 1 1\n"
                                     "vt 0 1\n"
                                     "vt 0.5 0.25\n"
                                     "vn 0 0 1\n"
                                     "f 1/1/1 2/2/1 3/3/1 4/4/1\r\n"
                                     "f 2/5/1 5/2/1 -3/-3/-1\n");
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(path, "", &mesh, &diag)) << diag.Format();
  // 5 file vertices + 1 split (vertex 2 with vt 5) = 6; quad -> 2 triangles, plus 1.
  ASSERT_EQ(mesh.vertex_count(), 6u);
  ASSERT_EQ(mesh.triangle_count(), 3u);
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3, 5, 4, 2};
  EXPECT_EQ(mesh.indices, indices);
  EXPECT_TRUE(mesh.normals.empty());  // OBJ normals are not imported
  ASSERT_EQ(mesh.uvs.size(), 6u);
  // The file's vt, v flipped (OBJ's v runs up, MeshData's down: docs/errors.md).
  const float expected_uv[6][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}, {1, 1}, {0.5f, 0.75f}};
  const float expected_pos[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                    {0, 1, 0}, {2, 0.5f, 0}, {1, 0, 0}};
  for (int v = 0; v < 6; ++v) {
    EXPECT_EQ(mesh.uvs[v].x, expected_uv[v][0]) << v;
    EXPECT_EQ(mesh.uvs[v].y, expected_uv[v][1]) << v;
    EXPECT_EQ(mesh.positions[v].x, expected_pos[v][0]) << v;
    EXPECT_EQ(mesh.positions[v].y, expected_pos[v][1]) << v;
    EXPECT_EQ(mesh.positions[v].z, expected_pos[v][2]) << v;
  }
  WeldedMesh welded;
  ASSERT_TRUE(WeldMesh(mesh, 0.f, &welded, &diag)) << diag.Format();
  EXPECT_EQ(welded.points.size(), 5u);
  EXPECT_EQ(welded.point_of_vertex[5], 1u);
}

TEST(MeshImportObj, PolygonFanWithoutTexcoords) {
  // A convex pentagon: fan-triangulated from its first corner into 3 triangles.
  const std::string path = WriteText(test::TempDir() + "/pentagon.obj",
                                     "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\n"
                                     "f 1 2 3 4 5\n");
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(path, "", &mesh, &diag)) << diag.Format();
  EXPECT_EQ(mesh.vertex_count(), 5u);
  EXPECT_TRUE(mesh.uvs.empty());
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3, 0, 3, 4};
  EXPECT_EQ(mesh.indices, indices);
}

TEST(MeshImportObj, FacesMayComeBeforeTheirVertices) {
  const std::string path = WriteText(test::TempDir() + "/forward.obj",
                                     "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -1 -2\n");
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(path, "", &mesh, &diag)) << diag.Format();
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 1};
  EXPECT_EQ(mesh.indices, indices);
}

// OpenMesh's own mesh would refuse the third face on edge 1-2 ("complex edge"); the raw
// importer keeps it and WeldMesh reports it.
TEST(MeshImportObj, KeepsNonManifoldFacesForTheWeldCheck) {
  const std::string path = WriteText(test::TempDir() + "/fin.obj",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                     "f 1 2 3\nf 2 1 4\nf 1 2 5\n");
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(path, "", &mesh, &diag)) << diag.Format();
  EXPECT_EQ(mesh.triangle_count(), 3u);
}

// ---------------------------------------------------------------------------------------
// Export round trips

TEST(MeshExport, RoundTripObjAndGlb) {
  const std::string dir = test::TempDir();
  MeshData grid = SeamGrid();
  // Values that need all 9 significant digits to survive text.
  grid.positions[5] = {1.f / 7.f, -123456.789f, 3.0e-7f};
  grid.uvs[5] = {2.f / 3.f, 1e-9f};
  for (const char* ext : {".glb", ".obj"}) {
    SCOPED_TRACE(ext);
    const std::string path = dir + "/out" + ext;
    Diagnostics diag;
    ASSERT_TRUE(ExportMesh(path, grid, &diag)) << diag.Format();
    MeshData back;
    ASSERT_TRUE(ImportMesh(path, "", &back, &diag)) << diag.Format();
    ExpectSame(grid, back, /*normals=*/std::string(ext) == ".glb");
  }
  // The .glb has the structure the validator needs: POSITION min/max, u32 indices, one
  // node, one scene.
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, dir + "/out.glb")) << err;
  ASSERT_EQ(model.meshes.size(), 1u);
  EXPECT_EQ(model.nodes.size(), 1u);
  EXPECT_EQ(model.scenes.size(), 1u);
  const auto& prim = model.meshes[0].primitives.at(0);
  const auto& pos = model.accessors.at(prim.attributes.at("POSITION"));
  ASSERT_EQ(pos.minValues.size(), 3u);
  ASSERT_EQ(pos.maxValues.size(), 3u);
  EXPECT_EQ(pos.minValues[1], -123456.789f);  // the moved vertex 5
  EXPECT_EQ(pos.maxValues[0], GridCoord(2));
  EXPECT_EQ(pos.maxValues[2], 0.25f);
  EXPECT_EQ(model.accessors.at(prim.indices).componentType,
            TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  EXPECT_TRUE(prim.attributes.count("NORMAL"));
  EXPECT_TRUE(prim.attributes.count("TEXCOORD_0"));
  // The .obj text has 1-based faces: triangle 0 = (0, 1, 4) -> "f 1/1/1 2/2/2 5/5/5".
  std::ifstream obj(dir + "/out.obj");
  const std::string text((std::istreambuf_iterator<char>(obj)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\nf 1/1/1 2/2/2 5/5/5\n"), std::string::npos);
}

TEST(MeshExport, RefusesBadMeshAndUnknownExtension) {
  const std::string dir = test::TempDir();
  MeshData grid = SeamGrid();
  Diagnostics diag;
  EXPECT_FALSE(ExportMesh(dir + "/x.ply", grid, &diag));
  EXPECT_TRUE(diag.Contains("unknown export extension '.ply'")) << diag.Format();
  grid.indices[3] = 40;
  diag.Clear();
  EXPECT_FALSE(ExportMesh(dir + "/x.obj", grid, &diag));
  EXPECT_TRUE(diag.Contains("index 40 out of range (mesh has 12 vertices)")) << diag.Format();
  std::ifstream f(dir + "/x.obj");
  EXPECT_FALSE(f.good());  // nothing written
}

// ---------------------------------------------------------------------------------------
// Bad input: every case must fail and name what is wrong.

struct BadCase {
  std::string description;
  // Writes the file into `dir` and returns its path (may be a missing path).
  std::function<std::string(const std::string& dir)> make;
  std::string expected;        // substring of Diagnostics::Format()
  std::string mesh_name = "";  // for ImportMesh
  bool weld_stage = false;     // the import succeeds; WeldMesh must report it
};

std::string GridWith(const std::string& path, const std::function<void(MeshData*)>& edit,
                     const std::function<void(tinygltf::Model*)>& edit_model = nullptr) {
  MeshData m = SeamGrid();
  if (edit) edit(&m);
  tinygltf::Model model = BuildModel(m);
  if (edit_model) edit_model(&model);
  return WriteModel(model, path);
}

TEST(MeshBadInput, EveryCaseFailsWithAMessageNamingTheElement) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<BadCase> cases = {
      {"missing file", [](const std::string& d) { return d + "/nope.obj"; }, "cannot open"},
      {"empty file", [](const std::string& d) { return WriteText(d + "/empty.glb", ""); },
       "file is empty"},
      {"garbage bytes as .glb",
       [](const std::string& d) {
         return WriteText(d + "/garbage.glb", std::string("\x01\x02garbage bytes, not a glb file") +
                                                  std::string(64, '\xff'));
       },
       "not a GLB file: the first 4 bytes are not 'glTF'"},
      {"invalid JSON .gltf",
       [](const std::string& d) { return WriteText(d + "/bad.gltf", "{ \"asset\": [1, 2"); },
       "invalid glTF"},
      {"unknown extension", [](const std::string& d) { return WriteText(d + "/m.ply", "ply"); },
       "unknown mesh file extension '.ply' (expected .gltf, .glb or .obj)"},
      {"glTF without meshes",
       [](const std::string& d) {
         return WriteText(d + "/nomesh.gltf", R"({"asset": {"version": "2.0"}})");
       },
       "the file has no meshes"},
      {"named mesh not found",
       [](const std::string& d) { return GridWith(d + "/named.glb", nullptr); },
       "no mesh named 'face' (available: 'grid')", "face"},
      {"non-triangle mode",
       [](const std::string& d) {
         return GridWith(d + "/lines.glb", nullptr, [](tinygltf::Model* m) {
           m->meshes[0].primitives[0].mode = TINYGLTF_MODE_LINE;
         });
       },
       "mesh 'grid' primitive 0: mode 1 (LINES) is not supported"},
      {"glTF index out of range",
       [](const std::string& d) {
         return GridWith(d + "/range.gltf", [](MeshData* m) { m->indices[12] = 99; });
       },
       "triangle 4: index 99 out of range (mesh has 12 vertices)"},
      {"glTF index count not a multiple of 3",
       [](const std::string& d) {
         return GridWith(d + "/count.glb", [](MeshData* m) { m->indices.pop_back(); });
       },
       "index count 23 is not a multiple of 3"},
      {"NaN position",
       [nan](const std::string& d) {
         return GridWith(d + "/nan.glb", [nan](MeshData* m) { m->positions[7].y = nan; });
       },
       "vertex 7: position is not finite"},
      {"infinite normal",
       [](const std::string& d) {
         return GridWith(d + "/inf.glb", [](MeshData* m) {
           m->normals[3].z = std::numeric_limits<float>::infinity();
         });
       },
       "vertex 3: normal is not finite"},
      {"accessor past the end of its bufferView",
       [](const std::string& d) {
         return GridWith(d + "/acc.glb", nullptr, [](tinygltf::Model* m) {
           m->accessors[0].count = 13;  // POSITION: 13 x 12 bytes > 144
         });
       },
       "POSITION (accessor 0) (count 13, byteOffset 0, stride 12) reads past the end of "
       "bufferView 0, which has 144 bytes"},
      {"bufferView past the end of its buffer",
       [](const std::string& d) {
         return GridWith(d + "/view.glb", nullptr, [](tinygltf::Model* m) {
           m->bufferViews[3].byteLength = 4096;  // the index view
         });
       },
       "bufferView 3 (used by indices (accessor 3)) spans bytes"},
      {"accessor count mismatch",
       [](const std::string& d) {
         return GridWith(d + "/mismatch.glb", nullptr, [](tinygltf::Model* m) {
           m->accessors[2].count = 11;  // TEXCOORD_0
         });
       },
       "accessor count mismatch: TEXCOORD_0 has 11 elements, POSITION has 12"},
      {"zero-area triangle",
       [](const std::string& d) {
         // Triangle 8 joins three collinear points of the bottom row.
         return GridWith(d + "/flat.glb", [](MeshData* m) {
           m->indices.insert(m->indices.end(), {0, 1, 2});
         });
       },
       "triangle 8 (vertices 0, 1, 2): has near-zero area", "", true},
      {"repeated index triangle",
       [](const std::string& d) {
         return GridWith(d + "/repeat.glb", [](MeshData* m) {
           m->indices.insert(m->indices.end(), {0, 0, 4});
         });
       },
       "triangle 8 (vertices 0, 0, 4): is degenerate: it uses a point twice (points 0, 0, 4)",
       "", true},
      {"seam duplicates that weld into one triangle",
       [](const std::string& d) {
         return GridWith(d + "/seamrepeat.glb", [](MeshData* m) {
           m->indices.insert(m->indices.end(), {1, 9, 4});  // 9 is a copy of 1
         });
       },
       "triangle 8 (vertices 1, 9, 4): is degenerate: it uses a point twice (points 1, 1, 4)",
       "", true},
      {"non-manifold edge (3 triangles on one edge)",
       [](const std::string& d) {
         return GridWith(d + "/fin.glb", [](MeshData* m) {
           m->positions.push_back({0.5f, -1.f, 0.f});   // vertex 12
           m->positions.push_back({0.5f, 0.f, 1.f});    // vertex 13
           m->normals.resize(14, float3{0, 0, 1});
           m->uvs.resize(14);
           m->indices.insert(m->indices.end(), {1, 0, 12, 0, 1, 13});  // triangles 8, 9
         });
       },
       "edge (points 0, 1): is non-manifold: shared by 3 triangles (0, 8, 9)", "", true},
      {"OBJ face beyond the last vertex",
       [](const std::string& d) {
         return WriteText(d + "/range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                            "f 1 2 3\nf 2 4 9\n");
       },
       "line 6: face 1: references vertex 9, but the file has 4 vertices (OBJ "
       "indices run from 1 to 4)"},
      {"OBJ face referencing vertex 0",
       [](const std::string& d) {
         return WriteText(d + "/zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
       },
       "line 4: face 0: references vertex 0, but OBJ indices start at 1"},
      {"OBJ texcoord out of range",
       [](const std::string& d) {
         return WriteText(d + "/vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                                         "f 1/1 2/2 3/3\n");
       },
       "line 6: face 0: references texcoord 3, but the file has 2 texcoords"},
      {"OBJ relative index before the first vertex",
       [](const std::string& d) {
         return WriteText(d + "/rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
       },
       "line 4: face 0: references vertex -4, which is before the first vertex"},
      {"OBJ face mixing corners with and without texcoords",
       [](const std::string& d) {
         return WriteText(d + "/mix.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n"
                                          "f 1/1 2/1 3\n");
       },
       "line 5: face 0: corner 2 has no texcoord"},
      {"OBJ unreadable face corner",
       [](const std::string& d) {
         return WriteText(d + "/word.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n");
       },
       "line 4: face 0: cannot read corner 'two'"},
      {"OBJ with no faces",
       [](const std::string& d) { return WriteText(d + "/nofaces.obj", "v 0 0 0\nv 1 0 0\n"); },
       "no faces (expected at least one 'f' line"},
      {"OBJ NaN position",
       [](const std::string& d) {
         return WriteText(d + "/nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
       },
       "line 2: vertex 1: position is not finite"},
      {"OBJ unreadable vertex",
       [](const std::string& d) {
         return WriteText(d + "/short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
       },
       "line 2: vertex 1: cannot read the position"},
      {"OBJ face repeating a vertex",
       [](const std::string& d) {
         return WriteText(d + "/rep.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 1 3\n");
       },
       "line 5: face 1: uses vertex 1 twice"},
      {"OBJ face with two corners",
       [](const std::string& d) {
         return WriteText(d + "/two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n");
       },
       "line 4: face 0: has 2 corners (expected at least 3)"},
      {"OBJ non-manifold edge",
       [](const std::string& d) {
         return WriteText(d + "/fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                          "f 1 2 3\nf 2 1 4\nf 1 2 5\n");
       },
       "edge (points 0, 1): is non-manifold: shared by 3 triangles (0, 1, 2)", "", true},
  };
  ASSERT_GE(cases.size(), 15u);
  const std::string dir = test::TempDir();
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.description);
    const std::string path = c.make(dir);
    MeshData mesh;
    Diagnostics diag;
    const bool imported = ImportMesh(path, c.mesh_name, &mesh, &diag);
    if (c.weld_stage) {
      ASSERT_TRUE(imported) << diag.Format();
      WeldedMesh welded;
      EXPECT_FALSE(WeldMesh(mesh, 0.f, &welded, &diag));
    } else {
      EXPECT_FALSE(imported);
      EXPECT_EQ(mesh.vertex_count(), 0u);  // nothing half-read is handed back
    }
    EXPECT_TRUE(diag.HasErrors());
    EXPECT_NE(diag.Format().find(c.expected), std::string::npos)
        << "expected: " << c.expected << "\ngot:\n" << diag.Format();
    if (std::getenv("MIMETIC_PRINT_DIAGNOSTICS")) std::printf("%s", diag.Format().c_str());
  }
}

// Randomly corrupted copies of a valid .glb, .gltf and .obj: whatever the bytes, ImportMesh
// returns; on failure it says why, on success the mesh obeys MeshData's invariants.
TEST(MeshBadInput, CorruptedFilesNeverCrash) {
  const std::string dir = test::TempDir();
  const MeshData grid = SeamGrid();
  Diagnostics diag;
  ASSERT_TRUE(ExportMesh(dir + "/ok.glb", grid, &diag)) << diag.Format();
  ASSERT_TRUE(ExportMesh(dir + "/ok.obj", grid, &diag)) << diag.Format();
  WriteModel(BuildModel(grid), dir + "/ok.gltf");
  std::mt19937 rng(7);
  for (const char* ext : {".glb", ".gltf", ".obj"}) {
    std::ifstream in(dir + "/ok" + ext, std::ios::binary);
    const std::string original((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    ASSERT_FALSE(original.empty());
    for (int trial = 0; trial < 120; ++trial) {
      std::string bytes = original;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits; ++e) {
        const size_t at = rng() % bytes.size();
        switch (rng() % 3) {
          case 0: bytes[at] = static_cast<char>(rng() & 0xff); break;
          case 1: bytes[at] = "0123456789-.e/ \n"[rng() % 16]; break;
          default: bytes.resize(at + 1); break;  // truncate
        }
      }
      const std::string path = WriteText(dir + "/fuzz" + ext, bytes);
      MeshData mesh;
      Diagnostics d;
      if (ImportMesh(path, "", &mesh, &d)) {
        ASSERT_GT(mesh.triangle_count(), 0u);
        ASSERT_EQ(mesh.indices.size() % 3, 0u);
        for (uint32_t i : mesh.indices) ASSERT_LT(i, mesh.vertex_count());
        for (const float3& p : mesh.positions) ASSERT_TRUE(IsFinite(p));
        ASSERT_TRUE(mesh.normals.empty() || mesh.normals.size() == mesh.vertex_count());
        ASSERT_TRUE(mesh.uvs.empty() || mesh.uvs.size() == mesh.vertex_count());
        WeldedMesh welded;
        WeldMesh(mesh, 0.f, &welded, &d);
        ASSERT_EQ(welded.point_of_vertex.size(), mesh.vertex_count());
      } else {
        ASSERT_TRUE(d.HasErrors()) << ext << " trial " << trial;
      }
    }
  }
}

TEST(MeshBadInput, ManyBadVerticesAreCapped) {
  MeshData m = SeamGrid();
  // 30 NaN vertices -> 20 messages and one "... and 10 more" line.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 30; ++i) {
    m.positions.push_back({nan, 0, 0});
    m.normals.push_back({0, 0, 1});
    m.uvs.push_back({0, 0});
  }
  const std::string path = WriteModel(BuildModel(m), test::TempDir() + "/nans.glb");
  MeshData mesh;
  Diagnostics diag;
  EXPECT_FALSE(ImportMesh(path, "", &mesh, &diag));
  EXPECT_EQ(diag.ErrorCount(), 21u) << diag.Format();
  const std::string text = diag.Format();
  EXPECT_NE(text.find("vertex 12: position is not finite"), std::string::npos) << text;
  EXPECT_NE(text.find("vertex 31: position is not finite"), std::string::npos) << text;
  EXPECT_EQ(text.find("vertex 32: position"), std::string::npos) << text;
  EXPECT_TRUE(diag.Contains("... and 10 more vertices with non-finite positions"));
}

// ---------------------------------------------------------------------------------------
// Shared datasets (never copied into the repository): imported, then welded (geometry/weld.h).

TEST(WeldShared, IctFaceKitNeutral) {
  const std::string shared = test::SharedDir();
  if (shared.empty()) GTEST_SKIP() << "../shared not present";
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(shared + "/data/ict-facekit/ict_skin_neutral.obj", "", &mesh, &diag))
      << diag.Format();
  WeldedMesh w;
  ASSERT_TRUE(WeldMesh(mesh, 0.f, &w, &diag)) << diag.Format();
  EXPECT_FALSE(diag.HasErrors()) << diag.Format();
  EXPECT_EQ(w.points.size(), 11248u);  // the dataset's documented vertex count
  // OBJ vertex k (1-based) is point k-1.
  for (uint32_t v = 0; v < 11248; ++v) ASSERT_EQ(w.point_of_vertex[v], v);
}

TEST(WeldShared, MediapipeCanonicalFace) {
  const std::string shared = test::SharedDir();
  if (shared.empty()) GTEST_SKIP() << "../shared not present";
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(
      ImportMesh(shared + "/data/mediapipe/canonical_face_model.obj", "", &mesh, &diag))
      << diag.Format();
  WeldedMesh w;
  ASSERT_TRUE(WeldMesh(mesh, 0.f, &w, &diag)) << diag.Format();
  EXPECT_FALSE(diag.HasErrors()) << diag.Format();
  EXPECT_EQ(w.points.size(), 468u);  // MediaPipe's 468 face landmarks
}

}  // namespace
}  // namespace mimetic
