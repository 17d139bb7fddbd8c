// tests/io/arkit_take_test.cpp: reading face-capture takes (io/arkit_take.h): CSV with a
// timecode and with seconds, Live Link Face's UpperCamel names, BlendShapeCount ignored, bad
// cells named by line, column and header; JSON frames and their errors with paths.
#include <gtest/gtest.h>

#include "io/arkit_take.h"
#include "test_support.h"

namespace mimetic {
namespace {

bool Contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(ArkitTake, CsvWithTimecodeAndUpperCamelNames) {
  // 30 fps: 01:00 -> 0 s, 01:15 -> 0.5 s, 02:00 -> 1 s; 02:03.5 = 2 + 3.5 / 30 s -> 1 + 3.5/30.
  const std::string csv =
      "Timecode,BlendShapeCount,EyeBlinkLeft,JawOpen,HeadYaw\r\n"
      "00:00:01:00.000,2,0.0,0.1,0.5\r\n"
      "00:00:01:15.000,2,0.5,0.2,-1.5\r\n"
      "\r\n"
      "00:00:02:03.500,2,1.0,0.3,0\r\n";
  ArkitTake take;
  Diagnostics diag;
  ASSERT_TRUE(ParseArkitCsv(csv, "t.csv", 30.0, &take, &diag)) << diag.Format();
  ASSERT_EQ(take.names, (std::vector<std::string>{"EyeBlinkLeft", "JawOpen", "HeadYaw"}));
  ASSERT_EQ(take.times.size(), 3u);
  EXPECT_FLOAT_EQ(take.times[0], 0.f);
  EXPECT_FLOAT_EQ(take.times[1], 0.5f);
  EXPECT_FLOAT_EQ(take.times[2], float(1.0 + 3.5 / 30.0));
  EXPECT_EQ(take.weights, (std::vector<float>{0.f, 0.1f, 0.5f, 0.5f, 0.2f, -1.5f, 1.f, 0.3f, 0.f}));
  EXPECT_TRUE(IsArkitName("EyeBlinkLeft"));
  EXPECT_TRUE(IsArkitName("eyeBlinkLeft"));
  EXPECT_FALSE(IsArkitName("HeadYaw"));
  EXPECT_FALSE(IsArkitName("EYEBLINKLEFT"));
}

TEST(ArkitTake, CsvWithSeconds) {
  ArkitTake take;
  Diagnostics diag;
  ASSERT_TRUE(ParseArkitCsv("time,jawOpen\n2.0,0.25\n2.5,1\n", "s.csv", 60.0, &take, &diag))
      << diag.Format();
  EXPECT_EQ(take.names, std::vector<std::string>{"jawOpen"});
  EXPECT_EQ(take.times, (std::vector<float>{0.f, 0.5f}));
  EXPECT_EQ(take.weights, (std::vector<float>{0.25f, 1.f}));
}

TEST(ArkitTake, CsvBadCellsNameLineColumnAndHeader) {
  struct Case {
    std::string csv;
    std::vector<std::string> messages;
  } cases[] = {
      {"Timecode,JawOpen,MouthClose\n00:00:00:00,0.1,0.2\n00:00:00:01,abc,1.5\n",
       {"b.csv:3:2 (JawOpen): \"abc\" is not a number; expected a blendshape weight in [0, 1]",
        "b.csv:3:3 (MouthClose): 1.5 is outside [0, 1]"}},
      {"Timecode,JawOpen\n00:00:00:00,0.1\n00:00:00:99,0.2\n",
       {"b.csv:3:1 (Timecode): \"00:00:00:99\" is not a timecode"}},
      {"Time,JawOpen\n0,0.1\n0,0.2\n", {"b.csv:3:1 (Time): time 0 is not after the previous"}},
      {"JawOpen,MouthClose\n0.1,0.2\n", {"b.csv:1: the header has no time column"}},
      {"Time,JawOpen\n0,0.1,7\n", {"b.csv:2: has 3 cells; expected 2"}},
      {"Time,HeadYaw\n0,nan\n", {"b.csv:2:2 (HeadYaw): \"nan\" is not a number; expected a finite"}},
      {"Time,JawOpen\n", {"b.csv: has a header but no frame rows"}},
      {"", {"b.csv: is empty"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.csv);
    ArkitTake take;
    Diagnostics diag;
    EXPECT_FALSE(ParseArkitCsv(c.csv, "b.csv", 60.0, &take, &diag));
    for (const std::string& m : c.messages) EXPECT_TRUE(Contains(diag.Format(), m)) << diag.Format();
  }
}

TEST(ArkitTake, JsonFrames) {
  ArkitTake take;
  Diagnostics diag;
  ASSERT_TRUE(ParseArkitTakeJson(R"([{"time": 1.0, "blendshapes": {"jawOpen": 0.5}},
      {"time": 1.25, "blendshapes": {"jawOpen": 0.75, "HeadYaw": -2}}])", "j.json", &take, &diag))
      << diag.Format();
  EXPECT_EQ(take.names, (std::vector<std::string>{"jawOpen", "HeadYaw"}));
  EXPECT_EQ(take.times, (std::vector<float>{0.f, 0.25f}));
  // A channel a frame omits is 0 there.
  EXPECT_EQ(take.weights, (std::vector<float>{0.5f, 0.f, 0.75f, -2.f}));
  diag.Clear();
  ASSERT_TRUE(LoadArkitTake(test::SourceDir() + "/tests/data/arkit/take.json", 60, &take, &diag))
      << diag.Format();
  EXPECT_EQ(take.times.size(), 3u);
}

TEST(ArkitTake, BadJsonNamesPaths) {
  struct Case {
    const char* json;
    const char* message;
  } cases[] = {
      {R"([{"time": 0, "blendshapes": {"jawOpen": 1.5}}])", "[0].blendshapes.jawOpen: expected a blendshape weight in [0, 1], got 1.5"},
      {R"([{"time": 0, "blendshapes": {"jawOpen": "x"}}])", "[0].blendshapes.jawOpen: expected a blendshape weight in [0, 1]"},
      {R"([{"time": 0, "blendshapes": {}}, {"time": 0, "blendshapes": {}}])", "[1].time: is 0; expected a time after"},
      {R"([{"time": -1, "blendshapes": {}}])", "[0].time"},
      {R"([{"blendshapes": {}}])", "[0].time: missing required key"},
      {R"([{"time": 0, "blendshapes": {}, "extra": 1}])", "[0]"},
      {R"({"time": 0})", "expected an array of frames"},
      {R"([])", "is an empty array"},
      {R"([{)", "j.json"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.json);
    ArkitTake take;
    Diagnostics diag;
    EXPECT_FALSE(ParseArkitTakeJson(c.json, "j.json", &take, &diag));
    EXPECT_TRUE(Contains(diag.Format(), c.message)) << diag.Format();
  }
}

}  // namespace
}  // namespace mimetic
