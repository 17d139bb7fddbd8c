// tests/io/mesh_multi_test.cpp: several meshes in one file (io/mesh_io.h ExportMeshes,
// ImportOtherMeshes): the first is what ImportMesh reads without a name; the others come back
// bit for bit; bad input is refused with the mesh named.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/file_util.h"
#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace mimetic {
namespace {

MeshData Triangle(float x, bool extras) {
  MeshData m;
  m.positions = {{x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0}};
  m.indices = {0, 1, 2};
  if (extras) {
    m.normals.assign(3, float3{0, 0, 1});
    m.uvs = {{0, 0}, {1, 0}, {0, 1}};
  }
  return m;
}

TEST(MeshMulti, GlbKeepsTheFirstMeshFirstAndTheOthersByName) {
  const std::string dir = test::TempDir();
  const MeshData skin = Triangle(0, true), eyes = Triangle(5, false), more = Triangle(9, true);
  Diagnostics d;
  ASSERT_TRUE(ExportMeshes(dir + "/m.glb", {{"head", &skin}, {"eyes", &eyes}, {"more", &more}}, &d))
      << d.Format();
  MeshData first, second;
  ASSERT_TRUE(ImportMesh(dir + "/m.glb", "", &first, &d)) << d.Format();
  ASSERT_TRUE(ImportMesh(dir + "/m.glb", "eyes", &second, &d)) << d.Format();
  EXPECT_EQ(first.positions, skin.positions);
  EXPECT_EQ(first.normals, skin.normals);
  ASSERT_EQ(first.uvs.size(), skin.uvs.size());
  for (size_t i = 0; i < skin.uvs.size(); ++i) {
    EXPECT_EQ(first.uvs[i].x, skin.uvs[i].x);
    EXPECT_EQ(first.uvs[i].y, skin.uvs[i].y);
  }
  EXPECT_EQ(second.positions, eyes.positions);
  EXPECT_TRUE(second.normals.empty());
  std::vector<NamedMeshData> others;
  std::string chosen;
  ASSERT_TRUE(ImportOtherMeshes(dir + "/m.glb", "", &others, &d, &chosen)) << d.Format();
  EXPECT_EQ(chosen, "head");
  ASSERT_EQ(others.size(), 2u);
  EXPECT_EQ(others[0].name, "eyes");
  EXPECT_EQ(others[0].mesh.positions, eyes.positions);
  EXPECT_EQ(others[1].name, "more");
  EXPECT_EQ(others[1].mesh.indices, more.indices);
  // Leaving out a named one: the first comes back among the others.
  ASSERT_TRUE(ImportOtherMeshes(dir + "/m.glb", "eyes", &others, &d, &chosen)) << d.Format();
  EXPECT_EQ(chosen, "eyes");
  ASSERT_EQ(others.size(), 2u);
  EXPECT_EQ(others[0].name, "head");
  EXPECT_EQ(others[0].mesh.positions, skin.positions);
  // One mesh: ExportMesh's file has no others.
  ASSERT_TRUE(ExportMesh(dir + "/one.glb", skin, &d)) << d.Format();
  ASSERT_TRUE(ImportOtherMeshes(dir + "/one.glb", "", &others, &d, &chosen)) << d.Format();
  EXPECT_TRUE(others.empty());
  EXPECT_EQ(chosen, "mesh");
}

TEST(MeshMulti, ObjWritesOneObjectEachAndReadsBackTheFirst) {
  const std::string dir = test::TempDir();
  const MeshData a = Triangle(0, false), b = Triangle(5, false);
  Diagnostics d;
  ASSERT_TRUE(ExportMeshes(dir + "/m.obj", {{"head", &a}, {"eyes", &b}}, &d)) << d.Format();
  const std::string text = test::ReadFileBytes(dir + "/m.obj");
  EXPECT_NE(text.find("o head\n"), std::string::npos);
  EXPECT_NE(text.find("o eyes\n"), std::string::npos);
  EXPECT_NE(text.find("f 4 5 6\n"), std::string::npos) << text;  // the second's indices run on
  MeshData first;
  ASSERT_TRUE(ImportMesh(dir + "/m.obj", "", &first, &d)) << d.Format();
  EXPECT_EQ(first.positions, a.positions);
  EXPECT_EQ(first.indices, a.indices);
  // A first object whose faces reach past it is refused, naming the face.
  const std::string bad = "o a\nv 0 0 0\nv 1 0 0\nf 1 2 3\no b\nv 0 1 0\nf 3 2 1\n";
  MeshData none;
  Diagnostics bad_diag;
  EXPECT_FALSE(ImportMeshBytes(bad, ".obj", "", "", &none, &bad_diag));
  EXPECT_NE(bad_diag.Format().find("face"), std::string::npos) << bad_diag.Format();
  // The other objects come back with their own vertex numbers (the file's run on).
  std::vector<NamedMeshData> others;
  std::string chosen;
  ASSERT_TRUE(ImportOtherMeshes(dir + "/m.obj", "", &others, &d, &chosen)) << d.Format();
  EXPECT_EQ(chosen, "head");
  ASSERT_EQ(others.size(), 1u);
  EXPECT_EQ(others[0].name, "eyes");
  EXPECT_EQ(others[0].mesh.positions, b.positions);
  EXPECT_EQ(others[0].mesh.indices, b.indices);
  // With uvs and normals on every mesh (f a/b/c: all three numbers run on), three objects.
  const MeshData s = Triangle(0, true), e = Triangle(5, true), m = Triangle(9, true);
  ASSERT_TRUE(ExportMeshes(dir + "/u.obj", {{"head", &s}, {"eyes", &e}, {"more", &m}}, &d))
      << d.Format();
  ASSERT_TRUE(ImportOtherMeshes(dir + "/u.obj", "", &others, &d)) << d.Format();
  ASSERT_EQ(others.size(), 2u);
  EXPECT_EQ(others[1].name, "more");
  EXPECT_EQ(others[1].mesh.positions, m.positions);
  EXPECT_EQ(others[1].mesh.indices, m.indices);
  MeshData first_u;  // each object is read as ImportMesh reads the first (OBJ normals: not read)
  ASSERT_TRUE(ImportMesh(dir + "/u.obj", "", &first_u, &d)) << d.Format();
  EXPECT_EQ(others[1].mesh.normals.size(), first_u.normals.size());
  ASSERT_EQ(others[1].mesh.uvs.size(), 3u);
  EXPECT_EQ(others[1].mesh.uvs[1].x, 1.f);
  // One object: no others. A later object whose face reaches back into the first is refused,
  // naming the object and the line.
  ASSERT_TRUE(ExportMesh(dir + "/one.obj", a, &d)) << d.Format();
  ASSERT_TRUE(ImportOtherMeshes(dir + "/one.obj", "", &others, &d)) << d.Format();
  EXPECT_TRUE(others.empty());
  ASSERT_TRUE(WriteFileAtomic(dir + "/back.obj",
                              "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
                              "o b\nv 0 0 1\nv 1 0 1\nf 4 5 1\n",
                              &d))
      << d.Format();
  Diagnostics back;
  EXPECT_FALSE(ImportOtherMeshes(dir + "/back.obj", "", &others, &back));
  EXPECT_TRUE(others.empty());
  EXPECT_NE(back.Format().find("object b, line 4"), std::string::npos) << back.Format();
  EXPECT_NE(back.Format().find("before the object"), std::string::npos) << back.Format();
  Diagnostics junk;
  ASSERT_TRUE(WriteFileAtomic(dir + "/junk.obj", "o a\nv 0 0 0\no b\nv 1 0 0\nf 2 x 2\n", &d));
  EXPECT_FALSE(ImportOtherMeshes(dir + "/junk.obj", "", &others, &junk));
  EXPECT_NE(junk.Format().find("not a vertex number"), std::string::npos) << junk.Format();
}

TEST(MeshMulti, ObjBytesReaderGivesTheObjectsWithTheirOwnNumbers) {
  // Object b's faces use the file's vertices 4-7 (v) and 4-7 (vt): locally 1-4, so its mesh
  // holds four positions and two triangles (0 1 2) and (1 3 2), by hand.
  const std::string text =
      "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"
      "o b\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
      "f 4/4 5/5 6/6\nf 5/5 7/7 6/6\n";
  std::vector<NamedMeshData> others;
  Diagnostics d;
  std::string first;
  ASSERT_TRUE(ImportOtherObjBytes(text, "", &others, &d, &first)) << d.Format();
  EXPECT_EQ(first, "a");
  ASSERT_EQ(others.size(), 1u);
  EXPECT_EQ(others[0].name, "b");
  ASSERT_EQ(others[0].mesh.positions.size(), 4u);
  EXPECT_EQ(others[0].mesh.positions[3].x, 1.f);
  EXPECT_EQ(others[0].mesh.positions[3].z, 1.f);
  ASSERT_EQ(others[0].mesh.indices.size(), 6u);
  const uint32_t* t = others[0].mesh.indices.data();
  // Each corner's position is the one its face line names (welding may renumber corners).
  const float3 expect[6] = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(others[0].mesh.positions[t[k]].x, expect[k].x) << "corner " << k;
    EXPECT_EQ(others[0].mesh.positions[t[k]].y, expect[k].y) << "corner " << k;
    EXPECT_EQ(others[0].mesh.positions[t[k]].z, expect[k].z) << "corner " << k;
  }
  // The file reader gives the same meshes.
  const std::string dir = test::TempDir();
  ASSERT_TRUE(WriteFileAtomic(dir + "/two.obj", text, &d)) << d.Format();
  std::vector<NamedMeshData> from_file;
  ASSERT_TRUE(ImportOtherMeshes(dir + "/two.obj", "", &from_file, &d)) << d.Format();
  ASSERT_EQ(from_file.size(), 1u);
  EXPECT_EQ(from_file[0].mesh.indices, others[0].mesh.indices);
  EXPECT_EQ(from_file[0].mesh.positions.size(), others[0].mesh.positions.size());
  // No object line at all, or one: nothing else; the first mesh is called "mesh" without one.
  ASSERT_TRUE(ImportOtherObjBytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "", &others, &d, &first));
  EXPECT_TRUE(others.empty());
  EXPECT_EQ(first, "mesh");
  // Binary junk in a later object is refused naming it, and leaves nothing.
  Diagnostics bad;
  EXPECT_FALSE(ImportOtherObjBytes(text + std::string("o c\nv 0 0 0\0\n"), "", &others, &bad));
  EXPECT_TRUE(others.empty());
  EXPECT_NE(bad.Format().find("mesh c"), std::string::npos) << bad.Format();
}

TEST(MeshMulti, BadInputIsRefusedNamingTheMesh) {
  const std::string dir = test::TempDir();
  const MeshData good = Triangle(0, false);
  MeshData bad = Triangle(1, false);
  bad.indices = {0, 1, 7};
  Diagnostics d;
  EXPECT_FALSE(ExportMeshes(dir + "/x.glb", {}, &d));
  EXPECT_NE(d.Format().find("no meshes"), std::string::npos) << d.Format();
  d = {};
  EXPECT_FALSE(ExportMeshes(dir + "/x.glb", {{"a", &good}, {"a", &good}}, &d));
  EXPECT_NE(d.Format().find("mesh 1 'a'"), std::string::npos) << d.Format();
  d = {};
  EXPECT_FALSE(ExportMeshes(dir + "/x.glb", {{"a", &good}, {"", &good}}, &d));
  EXPECT_NE(d.Format().find("distinct and not empty"), std::string::npos) << d.Format();
  d = {};
  EXPECT_FALSE(ExportMeshes(dir + "/x.glb", {{"a", &good}, {"eyes", &bad}}, &d));
  EXPECT_NE(d.Format().find("mesh 1 'eyes'"), std::string::npos) << d.Format();
  EXPECT_NE(d.Format().find("out of range"), std::string::npos) << d.Format();
  EXPECT_TRUE(test::ReadFileBytes(dir + "/x.glb").empty()) << "nothing is written";
  d = {};
  EXPECT_FALSE(ExportMeshes(dir + "/x.glb", {{"a", nullptr}}, &d));
  EXPECT_NE(d.Format().find("no mesh data"), std::string::npos) << d.Format();
  // Reading: a missing file, an unknown extension.
  std::vector<NamedMeshData> others;
  d = {};
  EXPECT_FALSE(ImportOtherMeshes(dir + "/missing.glb", "", &others, &d));
  EXPECT_TRUE(d.HasErrors());
  d = {};
  EXPECT_FALSE(ImportOtherMeshes(dir + "/m.stl", "", &others, &d));
  EXPECT_NE(d.Format().find("unknown mesh file extension"), std::string::npos) << d.Format();
}

}  // namespace
}  // namespace mimetic
