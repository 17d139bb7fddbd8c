// tests/tools/mesh_expect.h: comparing the meshes two commands wrote (tests/tools only: it reads
// them with the io module, which the lower test directories do not link).
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace mimetic::test {

// The whole file as text ("" when it cannot be read).
inline std::string ReadText(const std::string& path) { return ReadFileBytes(path); }

// Both files read as meshes with the same vertices, normals and triangles, and the same bytes.
inline void ExpectSameMesh(const std::string& a, const std::string& b) {
  MeshData ma, mb;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(a, "", &ma, &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(b, "", &mb, &diag)) << diag.Format();
  ASSERT_EQ(ma.vertex_count(), mb.vertex_count());
  EXPECT_EQ(ma.positions, mb.positions);
  EXPECT_EQ(ma.normals, mb.normals);
  EXPECT_EQ(ma.indices, mb.indices);
  EXPECT_EQ(ReadText(a), ReadText(b));
}

}  // namespace mimetic::test
