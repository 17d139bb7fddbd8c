// The compiled clip (.mclip, docs/mclip-format.md): a round trip samples bit-identically to
// the clip it was written from; the header fields and the checksum are what the format says
// (decoded here independently of the reader); a truncated, corrupted or hostile file is an
// error naming what is wrong, never a crash. (The library clips' round trip and `mimetic play`
// on a .mclip are in tests/tools/build_clip_test.cpp.)
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "expressions/offline/clip_builder.h"
#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"
#include "binary_file_checks.h"

namespace mimetic {
namespace {

const std::vector<std::string> kMuscles = {"a", "b", "c_L", "c_R", "d"};

// Every kind of channel and layer, every interpolation, a jaw channel and an expression that
// names the jaw.
CompiledClip RichClip(ClipEnd end = ClipEnd::kLoop) {
  ClipSpec spec;
  spec.name = "rich";
  spec.end = end;
  spec.duration = 2.5f;
  auto key = [](float t, float v, KeyInterp i) { return ClipKeySpec{t, v, i, KeyTangent::kAuto}; };
  spec.channels.push_back({ClipChannelKind::kMuscle, "a", ClipLayer::kAdd,
                           {key(0.f, 0.f, KeyInterp::kCubic), key(0.7f, 0.9f, KeyInterp::kCubic),
                            key(1.3f, 0.2f, KeyInterp::kLinear), key(2.f, 0.6f, KeyInterp::kStep)}});
  spec.channels.push_back({ClipChannelKind::kMuscle, "c", ClipLayer::kAdd,  // c_L and c_R
                           {key(0.2f, 0.4f, KeyInterp::kStep), key(1.f, 1.f, KeyInterp::kLinear)}});
  spec.channels.push_back({ClipChannelKind::kExpression, "open", ClipLayer::kAdd,
                           {key(0.f, 0.f, KeyInterp::kCubic), key(1.f, 1.f, KeyInterp::kCubic),
                            key(2.4f, 0.3f, KeyInterp::kCubic)}});
  spec.channels.push_back({ClipChannelKind::kExpression, "frown", ClipLayer::kMax,
                           {key(0.5f, 0.8f, KeyInterp::kLinear)}});
  spec.channels.push_back({ClipChannelKind::kExpression, "pucker", ClipLayer::kOverride,
                           {key(1.5f, 0.f, KeyInterp::kLinear), key(2.f, 0.7f, KeyInterp::kLinear)}});
  spec.channels.push_back({ClipChannelKind::kMuscle, "jaw", ClipLayer::kAdd,
                           {key(0.1f, 0.f, KeyInterp::kCubic), key(0.9f, 0.5f, KeyInterp::kCubic),
                            key(1.9f, 0.1f, KeyInterp::kCubic)}});
  const std::vector<ClipExpression> expressions = {
      {"open", {{"b", 0.6f}, {"d", 1.f}, {"jaw", 0.4f}}},
      {"frown", {{"a", 0.3f}, {"c_L", 0.9f}}},
      {"pucker", {{"a", 0.5f}, {"d", 0.2f}}},
  };
  CompiledClip clip;
  Diagnostics diag;
  EXPECT_TRUE(BuildClip(spec, kMuscles, expressions, &clip, &diag)) << diag.Format();
  return clip;
}

span<const uint8_t> Bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The format's fields (tests/binary_file_checks.h, docs/mclip-format.md).
using test::Entry;
using test::PutF32;
using test::PutU32;
using test::PutU64;
using test::Table;
using test::U32At;
using test::U64At;
uint64_t Checksum(const std::string& b) {
  uint64_t h = 0xcbf29ce484222325ull;
  std::string padded = b;
  padded.resize((b.size() + 7) / 8 * 8, '\0');
  for (size_t i = 0; i < padded.size() / 8; ++i) {
    const uint64_t w = i == 3 ? 0 : U64At(padded, 8 * i);
    h = ((h << 23 | h >> 41) ^ w) * 0x100000001b3ull;
  }
  return h;
}
void Rechecksum(std::string* b) { PutU64(b, 24, Checksum(*b)); }

Entry Find(const std::string& b, uint32_t id) {
  for (const Entry& e : Table(b))
    if (e.id == id) return e;
  ADD_FAILURE() << "no section " << id;
  return {};
}

std::string ReadError(const std::string& bytes) {
  CompiledClip clip;
  std::string error;
  EXPECT_FALSE(ReadClipBinary(Bytes(bytes), &clip, &error));
  EXPECT_FALSE(clip.built());
  return error;
}

std::vector<float> Sample(const CompiledClip& clip, float t) {
  std::vector<float> out(clip.muscle_count() + 1, -1.f);
  ClipSampleJob job;
  job.clip = &clip;
  job.time = t;
  job.out_activations = span<float>(out.data(), clip.muscle_count());
  job.out_jaw = span<float>(out.data() + clip.muscle_count(), 1);
  EXPECT_TRUE(job.Run());
  return out;
}

template <class T>
bool Same(span<const T> a, span<const T> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
}

TEST(ClipBinary, RoundTripSamplesBitIdentically) {
  for (ClipEnd end : {ClipEnd::kLoop, ClipEnd::kClamp}) {
    const CompiledClip clip = RichClip(end);
    const std::string bytes = WriteClipBinary(clip);
    CompiledClip back;
    std::string error;
    ASSERT_TRUE(ReadClipBinary(Bytes(bytes), &back, &error)) << error;
    EXPECT_TRUE(back.built());
    EXPECT_EQ(back.name(), "rich");
    EXPECT_EQ(back.end(), end);
    EXPECT_EQ(std::bit_cast<uint32_t>(back.duration()), std::bit_cast<uint32_t>(2.5f));
    EXPECT_EQ(back.muscle_count(), 5u);
    EXPECT_EQ(back.channel_count(), 7u);  // "c" drives c_L and c_R: two compiled channels
    EXPECT_EQ(back.expression_count(), 3u);
    EXPECT_TRUE(back.animates_jaw());
    EXPECT_TRUE(Same(back.kinds(), clip.kinds()));
    EXPECT_TRUE(Same(back.layers(), clip.layers()));
    EXPECT_TRUE(Same(back.targets(), clip.targets()));
    EXPECT_TRUE(Same(back.key_offsets(), clip.key_offsets()));
    EXPECT_TRUE(Same(back.key_times(), clip.key_times()));
    EXPECT_TRUE(Same(back.key_values(), clip.key_values()));
    EXPECT_TRUE(Same(back.key_tangents(), clip.key_tangents()));
    EXPECT_TRUE(Same(back.key_interps(), clip.key_interps()));
    EXPECT_TRUE(Same(back.expression_activations(), clip.expression_activations()));
    EXPECT_TRUE(Same(back.expression_masks(), clip.expression_masks()));
    EXPECT_TRUE(Same(back.expression_jaws(), clip.expression_jaws()));
    EXPECT_TRUE(Same(back.expression_jaw_masks(), clip.expression_jaw_masks()));
    // Sampled at 2001 times over [-1, 6] s (both ends and the loop's wrap) and odd values.
    std::vector<float> times = {std::nanf(""), std::numeric_limits<float>::infinity(),
                                -std::numeric_limits<float>::infinity(), 0.f, 2.5f};
    for (int i = 0; i <= 2000; ++i) times.push_back(-1.f + 7.f * float(i) / 2000.f);
    for (float t : times) {
      const std::vector<float> a = Sample(clip, t), b = Sample(back, t);
      EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << "t = " << t;
    }
  }
}

TEST(ClipBinary, HeaderAndChecksumAreTheFormats) {
  const CompiledClip clip = RichClip();
  const std::string bytes = WriteClipBinary(clip);
  EXPECT_EQ(bytes, WriteClipBinary(clip));  // deterministic
  EXPECT_EQ(bytes.substr(0, 4), "MCLP");
  EXPECT_TRUE(HasClipBinaryTag(Bytes(bytes)));
  EXPECT_FALSE(HasClipBinaryTag(Bytes(std::string("MRIG"))));
  EXPECT_EQ(U32At(bytes, 4), 1u);            // major 1, minor 0
  EXPECT_EQ(U32At(bytes, 8), 0u);            // flags
  EXPECT_EQ(U32At(bytes, 12), 14u);          // sections
  EXPECT_EQ(U64At(bytes, 16), bytes.size());
  EXPECT_EQ(U64At(bytes, 24), Checksum(bytes));
  EXPECT_EQ(U32At(bytes, 32), 40u);
  // Sections in id order, 8-aligned, not overlapping, payload = count x element size.
  const std::vector<Entry> table = Table(bytes);
  uint64_t end = 40 + 32 * table.size();
  for (size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(table[i].id, i + 1);
    EXPECT_EQ(table[i].offset % 8, 0u);
    EXPECT_GE(table[i].offset, end);
    if (table[i].element_size) {
      EXPECT_EQ(table[i].size, table[i].count * table[i].element_size);
    }
    end = table[i].offset + table[i].size;
  }
  // clip_params: f32 duration, u32 end, muscles, expressions, animates_jaw.
  const Entry params = Find(bytes, 2);
  EXPECT_EQ(params.size, 20u);
  EXPECT_EQ(U32At(bytes, params.offset), std::bit_cast<uint32_t>(2.5f));
  EXPECT_EQ(U32At(bytes, params.offset + 4), 1u);
  EXPECT_EQ(U32At(bytes, params.offset + 8), 5u);
  EXPECT_EQ(U32At(bytes, params.offset + 12), 3u);
  EXPECT_EQ(U32At(bytes, params.offset + 16), 1u);
  // Key counts: 4 + 2 + 2 (c_L, c_R) + 3 + 1 + 2 + 3 keys.
  EXPECT_EQ(Find(bytes, 7).count, 17u);
  EXPECT_EQ(Find(bytes, 6).count, 8u);  // 7 channels + 1
  EXPECT_EQ(Find(bytes, 11).count, 15u);  // 3 expressions x 5 muscles
}

TEST(ClipBinary, TruncationAtEveryByteIsRefused) {
  const std::string bytes = WriteClipBinary(RichClip());
  const std::vector<Entry> table = Table(bytes);
  for (size_t cut = 0; cut < bytes.size(); ++cut)
    test::ExpectTruncationNamed(table, cut, ReadError(bytes.substr(0, cut)));
}

TEST(ClipBinary, FlippedBytesAreRefused) {
  const std::string bytes = WriteClipBinary(RichClip());
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::string bad = bytes;
    bad[i] = char(bad[i] ^ 0x10);
    const std::string error = ReadError(bad);
    SCOPED_TRACE("byte " + std::to_string(i) + ": " + error);
    if (i < 4) EXPECT_NE(error.find("tag is not \"MCLP\""), std::string::npos);
    else if (i >= 40 + 32 * 14 || (i >= 24 && i < 32))
      EXPECT_NE(error.find("checksum mismatch"), std::string::npos);
    else EXPECT_FALSE(error.empty());
  }
}

// One field of one section set to a hostile value, the checksum made right (as a hostile file
// would), and the message the reader must give.
TEST(ClipBinary, HostileValuesAreRefusedWithTheirReason) {
  const std::string bytes = WriteClipBinary(RichClip());
  struct Case {
    uint32_t section;
    size_t byte;      // in the payload
    int width;        // 1: u8, 4: u32, -4: f32
    double value;
    const char* expected;
  };
  const float nan = std::nanf("");
  const float inf = std::numeric_limits<float>::infinity();
  // Channels (compiled order): 0 a, 1 c_L, 2 c_R, 3 open add, 4 frown max, 5 open override,
  // 6 jaw. Expressions: 0 open (names the jaw), 1 frown, 2 pucker. Keys: channel 0 [0, 4), 1 [4, 6), 2 [6, 8), 3 [8, 11), 4 [11], 5 [12, 14), 6 [14, 17).
  const std::vector<Case> cases = {
      {2, 0, -4, nan, "'clip_params' (id 2) at byte"},
      {2, 0, -4, -1.0, "duration -1; expected a finite number >= 0"},
      {2, 0, -4, 0.0, "a looping clip of duration 0; expected a duration > 0"},
      {2, 4, 4, 2, "end 2; expected 0 (clamp) or 1 (loop)"},
      {2, 8, 4, 4, "'expression_activations' (id 11) at byte"},
      {2, 8, 4, 4e9, "muscle count 4000000000"},
      {2, 12, 4, 4, "15 elements; expected 4 expressions x 5 muscles = 20"},
      {2, 16, 4, 0, "animates_jaw is 0, but the clip has a jaw channel"},
      {2, 16, 4, 2, "animates_jaw 2; expected 0 or 1"},
      {3, 1, 1, 3, "channel 1 has kind 3; expected 0 (muscle), 1 (expression) or 2 (jaw)"},
      {3, 0, 1, 2, "channel 6 is a second jaw channel"},
      {4, 4, 1, 7, "channel 4 has layer 7"},
      {4, 0, 1, 0, "channel 0 (a muscle channel) has layer 0; expected 2"},
      {5, 0, 4, 5, "channel 0 (a muscle channel) targets muscle 5; the clip has 5 muscles"},
      {5, 12, 4, 3, "channel 3 (an expression channel) targets expression 3; the clip has 3"},
      {5, 24, 4, 1, "channel 6 (the jaw channel) targets 1; expected 0"},
      {6, 0, 4, 1, "'key_offsets' (id 6) at byte"},
      {6, 0, 4, 1, "offset 0 is 1; expected 0"},
      {6, 8, 4, 3, "channel 1 has keys [4, 3); expected a non-empty range"},
      {6, 4, 4, 0, "channel 0 has keys [0, 0)"},
      {6, 28, 4, 16, "the last offset is 16; key_times has 17 keys"},
      {7, 4, -4, nan, "key 1 (channel 0) at t = nan"},
      {7, 4, -4, inf, "key 1 (channel 0) at t = inf"},
      {7, 4, -4, -0.5, "key 1 (channel 0) at t = -0.5"},
      {7, 8, -4, 0.5, "key 2 (channel 0) at t = 0.5 is not after the key before it (0.699999988)"},
      {7, 16 * 4, -4, 3.0, "key 16 (channel 6) at t = 3; expected a time in [0, 2.5]"},
      {8, 4, -4, 1.5, "'key_values' (id 8) at byte"},
      {8, 4, -4, 1.5, "key 1 (channel 0) has value 1.5; expected a value in [0, 1]"},
      {8, 0, -4, nan, "key 0 (channel 0) has value nan"},
      {9, 8, -4, inf, "key 2 (channel 0) has tangent inf; expected a finite slope"},
      {10, 9, 1, 3, "key 9 (channel 3) has interpolation 3"},
      {11, 4 * 6, -4, 1.25, "expression 1, muscle 1 has activation 1.25; expected [0, 1]"},
      {11, 0, -4, nan, "expression 0, muscle 0 has activation nan"},
      {12, 3, 1, 2, "expression 0, muscle 3 has mask 2; expected 0 or 1"},
      {13, 4, -4, -0.25, "expression 1 has jaw -0.25; expected [0, 1]"},
      {14, 0, 1, 7, "expression 0 has jaw mask 7; expected 0 or 1"},
  };
  for (const Case& c : cases) {
    std::string bad = bytes;
    const size_t at = Find(bytes, c.section).offset + c.byte;
    if (c.width == 1) bad[at] = char(uint8_t(c.value));
    else if (c.width == 4) PutU32(&bad, at, uint32_t(c.value));
    else PutF32(&bad, at, float(c.value));
    Rechecksum(&bad);
    const std::string error = ReadError(bad);
    EXPECT_NE(error.find(c.expected), std::string::npos)
        << "section " << c.section << " byte " << c.byte << ": expected \"" << c.expected
        << "\", got \"" << error << "\"";
  }
}

TEST(ClipBinary, CountsAndSectionsAreChecked) {
  const std::string bytes = WriteClipBinary(RichClip());
  {  // a huge element count is refused before anything is read or allocated
    std::string bad = bytes;
    for (size_t i = 0; i < 14; ++i)
      if (U32At(bad, 40 + 32 * i) == 7) PutU64(&bad, 40 + 32 * i + 24, uint64_t(1) << 60);
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("'key_times' (id 7)"), std::string::npos) << ReadError(bad);
  }
  {  // a key array shorter than the others
    const std::vector<Entry> table = Table(bytes);
    std::string bad = bytes;
    const size_t at = 40 + 32 * 8;  // key_tangents (id 9)
    ASSERT_EQ(table[8].id, 9u);
    PutU64(&bad, at + 16, table[8].size - 4);
    PutU64(&bad, at + 24, table[8].count - 1);
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("'key_tangents' (id 9) at byte " +
                                  std::to_string(table[8].offset) +
                                  ": 16 elements; key_times has 17 (one per key)"),
              std::string::npos)
        << ReadError(bad);
  }
  {  // a required section missing (its id made unknown: skipped as a newer minor's)
    std::string bad = bytes;
    PutU32(&bad, 40 + 32 * 4, 99);  // channel_targets
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("section 'channel_targets' (id 5): missing"), std::string::npos)
        << ReadError(bad);
  }
  {  // a newer major version
    std::string bad = bytes;
    PutU32(&bad, 4, 2);
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("format version 2.0 is newer than this reader's 1.0"),
              std::string::npos);
  }
  EXPECT_NE(ReadError("").find("a .mclip header is 40"), std::string::npos);
  // A .mrig is not a clip.
  std::string mrig = bytes;
  std::memcpy(mrig.data(), "MRIG", 4);
  EXPECT_NE(ReadError(mrig).find("not a compiled clip"), std::string::npos);
  // A clip never built writes a file the reader refuses.
  EXPECT_NE(ReadError(WriteClipBinary(CompiledClip())).find("0 channels; expected at least one"),
            std::string::npos)
      << ReadError(WriteClipBinary(CompiledClip()));
}

TEST(ClipBinary, FileHelperNamesThePath) {
  CompiledClip clip;
  std::string error;
  EXPECT_FALSE(LoadClipBinaryFile("/nonexistent/x.mclip", &clip, &error));
  EXPECT_EQ(error.rfind("/nonexistent/x.mclip: cannot open", 0), 0u) << error;
  EXPECT_FALSE(LoadClipBinaryFile("/tmp", &clip, &error));
  EXPECT_NE(error.find("not a regular file (expected a compiled clip)"), std::string::npos);
}

}  // namespace
}  // namespace mimetic
