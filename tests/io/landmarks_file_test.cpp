// tests/io/landmarks_file_test.cpp: landmark files (fitting/landmarks.h,
// docs/landmarks-format.md).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/file_util.h"
#include "fitting/landmarks.h"
#include "io/landmarks_file.h"
#include "test_support.h"

namespace mimetic {
namespace {

std::string PointsJson(int count, const std::string& override_first = "") {
  std::string s = "[";
  for (int i = 0; i < count; ++i) {
    if (i) s += ",";
    s += (i == 0 && !override_first.empty()) ? override_first
                                             : "[" + std::to_string(i) + ", 1.5, -2]";
  }
  return s + "]";
}

std::string File(const std::string& body) {
  return "{\"format\": \"mimetic-landmarks\", \"version\": 1, " + body + "}";
}

TEST(Landmarks, SaveLoadRoundTripIsExact) {
  Landmarks lm;
  for (int i = 0; i < 68; ++i) lm.points.push_back({0.1f * i, -1.f / (i + 3), 1e-3f * i * i});
  for (int i = 0; i < 68; ++i) lm.vertex_indices.push_back(i == 5 ? -1 : 1000 + i);
  const std::string path = test::TempDir() + "/lm.json";
  Diagnostics diag;
  ASSERT_TRUE(SaveLandmarks(path, lm, &diag)) << diag.Format();
  Landmarks back;
  ASSERT_TRUE(LoadLandmarks(path, &back, &diag)) << diag.Format();
  EXPECT_EQ(back.scheme, "ibug68");
  ASSERT_EQ(back.points.size(), 68u);
  for (int i = 0; i < 68; ++i) EXPECT_EQ(back.points[i], lm.points[i]) << i;  // %.9g is exact
  EXPECT_EQ(back.vertex_indices, lm.vertex_indices);
  // The text names the format and units.
  std::string text;
  ASSERT_TRUE(ReadFile(path, &text, &diag));
  EXPECT_NE(text.find("\"format\": \"mimetic-landmarks\""), std::string::npos);
  EXPECT_NE(text.find("\"units\": \"mm\""), std::string::npos);
}

TEST(Landmarks, VerticesOnlyAreResolvedOnAMesh) {
  std::string verts = "[";
  for (int i = 0; i < 68; ++i) verts += (i ? "," : "") + std::to_string(67 - i);
  verts += "]";
  Landmarks lm;
  Diagnostics diag;
  ASSERT_TRUE(ParseLandmarks(File("\"vertices\": " + verts), "f.json", &lm, &diag))
      << diag.Format();
  EXPECT_TRUE(lm.points.empty());
  MeshData mesh;
  for (int i = 0; i < 68; ++i) mesh.positions.push_back({float(i), float(2 * i), 0.f});
  ASSERT_TRUE(ResolveLandmarkPoints(mesh, &lm, &diag)) << diag.Format();
  ASSERT_EQ(lm.points.size(), 68u);
  EXPECT_EQ(lm.points[0], (float3{67.f, 134.f, 0.f}));
  EXPECT_EQ(lm.points[67], (float3{0.f, 0.f, 0.f}));
  // An index past the mesh is reported with its path.
  mesh.positions.resize(10);
  Landmarks lm2;
  ASSERT_TRUE(ParseLandmarks(File("\"vertices\": " + verts), "f.json", &lm2, &diag));
  Diagnostics d2;
  EXPECT_FALSE(ResolveLandmarkPoints(mesh, &lm2, &d2));
  EXPECT_TRUE(d2.Contains("vertices[0]")) << d2.Format();
  EXPECT_TRUE(d2.Contains("below the mesh's 10 vertices")) << d2.Format();
}

TEST(Landmarks, BadInputIsReportedWithPathAndExpectation) {
  const std::string ok_points = "\"points\": " + PointsJson(68);
  struct Case {
    const char* name;
    std::string text;
    std::vector<std::string> expect;  // substrings of the formatted diagnostics
  };
  const std::vector<Case> cases = {
      {"not json", "{\"format\": ", {"not valid JSON"}},
      {"top level array", "[1, 2]", {"top level is array", "expected an object"}},
      {"missing format", "{\"version\": 1, " + ok_points + "}", {"format", "missing"}},
      {"wrong format", "{\"format\": \"obj\", \"version\": 1, " + ok_points + "}",
       {"format", "expected \"mimetic-landmarks\""}},
      {"future version", File(ok_points).replace(File(ok_points).find("\"version\": 1"), 12,
                                                  "\"version\": 2"),
       {"version", "supports version 1 only"}},
      {"version as string",
       "{\"format\": \"mimetic-landmarks\", \"version\": \"1\", " + ok_points + "}",
       {"version", "expected the integer 1"}},
      {"bad scheme", File("\"scheme\": \"dlib5\", " + ok_points), {"scheme", "expected \"ibug68\""}},
      {"unknown key", File("\"colour\": 3, " + ok_points), {"colour", "unknown key"}},
      {"wrong count", File("\"points\": " + PointsJson(67)),
       {"points", "has 67 entries; expected 68"}},
      {"point of two numbers", File("\"points\": " + PointsJson(68, "[1, 2]")),
       {"points[0]", "expected an array of 3 numbers"}},
      {"string coordinate", File("\"points\": " + PointsJson(68, "[1, \"a\", 2]")),
       {"points[0][1]", "is string", "expected a number"}},
      {"outside float range", File("\"points\": " + PointsJson(68, "[1, 2, 1e39]")),
       {"points[0][2]", "expected a finite number"}},
      {"points not an array", File("\"points\": {\"a\": 1}"), {"points", "is object"}},
      {"negative vertex", File("\"vertices\": [-2" + std::string(67 * 3, ' ') + "]"),
       {"vertices[0]", "is -2", "expected a vertex index >= 0"}},
      {"fractional vertex", File(ok_points + ", \"vertices\": [3.5]"),
       {"vertices[0]", "expected an integer vertex index", "has 1 entries; expected 68"}},
      {"nothing given", File("\"units\": \"mm\""),
       {"neither \"points\" nor \"vertices\""}},
      {"bad units", File("\"units\": \"cm\", " + ok_points), {"units", "expected \"mm\""}},
  };
  ASSERT_GE(cases.size(), 10u);
  for (const Case& c : cases) {
    Landmarks lm;
    Diagnostics diag;
    EXPECT_FALSE(ParseLandmarks(c.text, "lm.json", &lm, &diag)) << c.name;
    const std::string msg = diag.Format();
    for (const std::string& e : c.expect)
      EXPECT_NE(msg.find(e), std::string::npos) << c.name << ": no '" << e << "' in\n" << msg;
    EXPECT_NE(msg.find("lm.json"), std::string::npos) << c.name << ": file name in\n" << msg;
  }
}

TEST(Landmarks, EveryProblemIsReportedNotOnlyTheFirst) {
  Landmarks lm;
  Diagnostics diag;
  const std::string text =
      "{\"format\": \"x\", \"version\": 7, \"extra\": 1, \"points\": " +
      PointsJson(68, "[1, null, 2]") + "}";
  EXPECT_FALSE(ParseLandmarks(text, "lm.json", &lm, &diag));
  EXPECT_EQ(diag.ErrorCount(), 4u) << diag.Format();  // format, version, extra, points[0][1]
}

TEST(Landmarks, DeepNestingAndOverflowingNumbersAreCleanErrors) {
  // 100,000 nested brackets used to overflow the stack; they are refused before parsing.
  Landmarks lm;
  Diagnostics diag;
  EXPECT_FALSE(ParseLandmarks(std::string(100000, '[') + std::string(100000, ']'), "lm.json", &lm,
                              &diag));
  EXPECT_NE(diag.Format().find("error: lm.json: nested deeper than 64 levels at line 1, column 65"),
            std::string::npos)
      << diag.Format();
  EXPECT_TRUE(diag.Contains("top level is array")) << diag.Format();
  // 1e400 overflows a double (nlohmann's parser used to throw out_of_range, uncaught): now a
  // message with its path.
  Diagnostics d2;
  EXPECT_FALSE(ParseLandmarks(File("\"points\": " + PointsJson(68, "[1, 1e400, 2]")), "lm.json",
                              &lm, &d2));
  EXPECT_EQ(d2.ErrorCount(), 1u) << d2.Format();
  EXPECT_NE(d2.Format().find("error: lm.json: points[0][1]: is a number that overflows to "
                             "infinity; expected a finite number (float range)"),
            std::string::npos)
      << d2.Format();
}

TEST(Landmarks, IntegralNumbersAreVertexIndices) {
  std::string verts = "[";
  for (int i = 0; i < 68; ++i) verts += (i ? "," : "") + std::to_string(i) + ".0";
  Landmarks lm;
  Diagnostics diag;
  ASSERT_TRUE(ParseLandmarks(File("\"vertices\": " + verts + "]"), "f.json", &lm, &diag))
      << diag.Format();
  ASSERT_EQ(lm.vertex_indices.size(), 68u);
  EXPECT_EQ(lm.vertex_indices[67], 67);
}

TEST(Landmarks, LoadReportsMissingFile) {
  Landmarks lm;
  Diagnostics diag;
  EXPECT_FALSE(LoadLandmarks("/nonexistent-dir/lm.json", &lm, &diag));
  EXPECT_TRUE(diag.Contains("/nonexistent-dir/lm.json"));
}

TEST(Landmarks, SaveRefusesWhatWouldNotLoad) {
  Landmarks lm;
  lm.points.resize(10);
  Diagnostics diag;
  const std::string path = test::TempDir() + "/lm.json";
  EXPECT_FALSE(SaveLandmarks(path, lm, &diag));
  EXPECT_TRUE(diag.Contains("10 points; expected 68"));
  lm.points.assign(68, float3{0, 0, 0});
  lm.points[3].y = NAN;
  Diagnostics d2;
  EXPECT_FALSE(SaveLandmarks(path, lm, &d2));
  EXPECT_TRUE(d2.Contains("points[3]"));
}

TEST(Landmarks, IbugNames) {
  EXPECT_STREQ(Ibug68Name(8), "jaw 8 (chin, menton)");
  EXPECT_STREQ(Ibug68Name(30), "nose tip (pronasale)");
  EXPECT_STREQ(Ibug68Name(36), "right eye outer corner");
  EXPECT_STREQ(Ibug68Name(45), "left eye outer corner");
  EXPECT_STREQ(Ibug68Name(67), "lower lip inner 67");
  EXPECT_STREQ(Ibug68Name(68), "");
  EXPECT_STREQ(Ibug68Name(-1), "");
}

}  // namespace
}  // namespace mimetic
