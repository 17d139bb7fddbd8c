// The compiled rig (.mrig, docs/mrig-format.md): a round trip evaluates bit-identically to the
// rig it was written from; the bytes are deterministic; a truncated, corrupted or hostile file
// is an error naming what is wrong, never a crash. (The sample head's round trip through the
// command is in tests/tools/build_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

#include "content/procedural.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/rig_binary.h"
#include "binary_file_checks.h"

namespace mimetic {
namespace {

// A surface rig with every section non-empty: thickness, a wrinkle region on every muscle and
// three curve wrinkles (one of each profile); not refined, to stay small.
Rig SurfaceRig() {
  const MeshData mesh = MakeSurfaceMesh(31, 31, 100.f, 100.f, 10.f);
  RigSpec spec = MakeSurfaceRigSpec(4, 100.f, 100.f, 10.f, 0.3f, 3.f);
  AddEverySkinLayer(&spec, 0.3f, 4.f);
  // Two tension regions (format 1.1's optional sections), weights from the rest x.
  TensionRegionSpec left{"left", 0.05f, {}}, right{"right", 0.2f, {}};
  for (const float3& p : mesh.positions) {
    const float u = std::min(std::max((p.x + 50.f) / 100.f, 0.f), 1.f);
    left.weights.push_back(1.f - u);
    right.weights.push_back(u);
  }
  spec.tension_regions = {left, right};
  // Fine-scale fields (format 1.2's optional sections 40-41).
  FineScaleSpec fine;
  fine.fields[0].anchors = {{0, {0.6f, 0.f, 0.f}}, {960, {0.3f, 0.3f, 0.f}}};
  fine.fields[1].anchors = {{480, {0.f, 0.5f, 0.f}}};
  fine.rest_amplitude = 0.35f;
  spec.fine_scale = fine;
  Rig rig;
  Diagnostics diag;
  EXPECT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  return rig;
}

const Rig& Surface() {
  static const Rig rig = SurfaceRig();
  return rig;
}

span<const uint8_t> Bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The format's fields (tests/binary_file_checks.h, docs/mrig-format.md).
using test::Entry;
using test::PutU32;
using test::PutU64;
using test::Table;
using test::U32At;
using test::U64At;
// The checksum of docs/mrig-format.md, written into [24, 32): one lane for major version 1,
// four interleaved lanes (word i into lane i % 4, lane l from basis ^ l, then the four lanes
// through the same step from the basis) from major version 2.
uint64_t Step(uint64_t h, uint64_t w) { return (h << 23 | h >> 41) ^ w; }
uint64_t ChecksumOf(const std::string& b, bool four_lanes) {
  const uint64_t basis = 0xcbf29ce484222325ull, prime = 0x100000001b3ull;
  std::string padded = b;
  padded.resize((b.size() + 7) / 8 * 8, '\0');
  uint64_t lane[4] = {basis, basis ^ 1, basis ^ 2, basis ^ 3};
  for (size_t i = 0; i < padded.size() / 8; ++i) {
    const uint64_t w = i == 3 ? 0 : U64At(padded, 8 * i);
    uint64_t& h = four_lanes ? lane[i % 4] : lane[0];
    h = Step(h, w) * prime;
  }
  if (!four_lanes) return lane[0];
  uint64_t h = basis;
  for (uint64_t l : lane) h = Step(h, l) * prime;
  return h;
}
void Rechecksum(std::string* b) { PutU64(b, 24, ChecksumOf(*b, U32At(*b, 4) % 65536 >= 2)); }

Entry Find(const std::string& b, uint32_t id) {
  for (const Entry& e : Table(b))
    if (e.id == id) return e;
  ADD_FAILURE() << "no section " << id;
  return {};
}

// `b` rebuilt without the sections of `ids` (docs/mrig-format.md: the table shrinks, the other
// payloads move up in table order, each at the next multiple of 8, and the header's count, size
// and checksum follow), a file the writer could have written without them.
std::string DropSections(const std::string& b, const std::vector<uint32_t>& ids) {
  std::vector<Entry> kept;
  for (const Entry& e : Table(b))
    if (std::find(ids.begin(), ids.end(), e.id) == ids.end()) kept.push_back(e);
  std::string out = b.substr(0, 40);
  out.resize(40 + 32 * kept.size(), '\0');
  for (size_t i = 0; i < kept.size(); ++i) {
    out.resize((out.size() + 7) / 8 * 8, '\0');
    const Entry& e = kept[i];
    const size_t at = 40 + 32 * i;
    PutU32(&out, at, e.id);
    PutU32(&out, at + 4, e.element_size);
    PutU64(&out, at + 8, out.size());
    PutU64(&out, at + 16, e.size);
    PutU64(&out, at + 24, e.count);
    out += b.substr(size_t(e.offset), size_t(e.size));
  }
  PutU32(&out, 12, uint32_t(kept.size()));
  PutU64(&out, 16, out.size());
  Rechecksum(&out);
  return out;
}

// Positions and normals of EvaluateJob, every layer on.
std::vector<float> Evaluate(const Rig& rig, span<const float> act, float jaw = 0.f) {
  EvaluateContext ctx(rig);
  std::vector<float> pos(3 * rig.vertex_count()), nrm(3 * rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = pos;
  job.out_normals = nrm;
  job.jaw = jaw;
  std::vector<float> fine(2 * rig.vertex_count());
  job.out_fine_amplitudes = fine;
  EXPECT_TRUE(job.Run());
  pos.insert(pos.end(), nrm.begin(), nrm.end());
  pos.insert(pos.end(), fine.begin(), fine.end());  // the fine-scale amplitudes too
  return pos;
}

std::string ReadError(const std::string& bytes) {
  RigData data;
  std::string error;
  EXPECT_FALSE(ReadRigBinaryData(Bytes(bytes), &data, nullptr, &error));
  return error;
}

// The reader's error for `bytes` with section `id` (of fixed-size elements) one element short:
// its table entry's count and size lowered by one element, the checksum mended.
std::string ErrorWithOneFewer(const std::string& bytes, uint32_t id) {
  std::string bad = bytes;
  const Entry e = Find(bytes, id);
  PutU64(&bad, e.at + 24, e.count - 1);
  PutU64(&bad, e.at + 16, e.size - e.element_size);
  Rechecksum(&bad);
  return ReadError(bad);
}

TEST(RigBinary, RoundTripEvaluatesBitIdentically) {
  const Rig& rig = Surface();
  ASSERT_TRUE(rig.layers().thickness && rig.layers().muscle_wrinkles &&
              rig.layers().curve_wrinkles);
  ASSERT_FALSE(rig.muscle_wrinkles().empty());
  ASSERT_FALSE(rig.curve_wrinkles().entries.empty());
  const RigBinaryInfo info{"mm", 961};
  const std::string bytes = WriteRigBinary(rig.data(), &info);
  Rig loaded;
  RigBinaryInfo loaded_info;
  std::string error;
  ASSERT_TRUE(ReadRigBinary(Bytes(bytes), &loaded, &loaded_info, &error)) << error;
  EXPECT_EQ(loaded_info.units, "mm");
  EXPECT_EQ(loaded_info.source_vertex_count, 961u);
  ASSERT_EQ(loaded.vertex_count(), rig.vertex_count());
  EXPECT_EQ(loaded.muscle_names(), rig.muscle_names());
  EXPECT_EQ(loaded.curve_wrinkles().names, rig.curve_wrinkles().names);
  ASSERT_FALSE(rig.fine_scale().empty());
  EXPECT_EQ(loaded.fine_scale().probes.size(), rig.fine_scale().probes.size());
  EXPECT_EQ(loaded.fine_scale().rest_amplitude, 0.35f);
  for (float level : {0.f, 0.35f, 1.f}) {
    std::vector<float> act(rig.muscle_count());
    for (size_t m = 0; m < act.size(); ++m) act[m] = level * (m % 2 ? 1.f : 0.6f);
    const std::vector<float> want = Evaluate(rig, act), got = Evaluate(loaded, act);
    ASSERT_EQ(want.size(), got.size());
    EXPECT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0)
        << "activation level " << level;
  }
  // Writing the loaded rig again gives the same bytes.
  EXPECT_EQ(WriteRigBinary(loaded.data(), &loaded_info), bytes);
}

TEST(RigBinary, FineScaleSectionsComeTogetherAndOldFilesHaveNone) {
  // A rig without fine-scale fields writes neither section and reads back empty.
  RigData plain = Surface().data();
  plain.fine_scale = RigFineScale();
  const std::string none = WriteRigBinary(plain, nullptr);
  Rig loaded;
  std::string error;
  ASSERT_TRUE(ReadRigBinary(Bytes(none), &loaded, nullptr, &error)) << error;
  EXPECT_TRUE(loaded.fine_scale().empty());
  // One of the two sections alone is refused, naming them: rename section 41's id in the
  // table (entries of 32 bytes from byte 40, id first) to an unknown one.
  const std::string bytes = WriteRigBinary(Surface().data(), nullptr);
  std::string edited = bytes;
  const uint32_t count = U32At(bytes, 12);
  bool found = false;
  for (uint32_t i = 0; i < count; ++i)
    if (U32At(bytes, 40 + 32 * i) == 41) PutU32(&edited, 40 + 32 * i, 63), found = true;
  ASSERT_TRUE(found);
  Rechecksum(&edited);
  EXPECT_NE(ReadError(edited).find("sections 'fine_scale_*' (ids 40-41)"), std::string::npos)
      << ReadError(edited);
  EXPECT_NE(ReadError(edited).find("one is present, missing 'fine_scale_probes' (id 41)"),
            std::string::npos)
      << ReadError(edited);
  // Either one removed from the file: the message names the absent one.
  const std::string no_params = ReadError(DropSections(bytes, {40}));
  EXPECT_NE(no_params.find("missing 'fine_scale_params' (id 40)"), std::string::npos) << no_params;
  const std::string no_probes = ReadError(DropSections(bytes, {41}));
  EXPECT_NE(no_probes.find("missing 'fine_scale_probes' (id 41)"), std::string::npos) << no_probes;
}

// Two eyeballs on the surface, every fifth active point sliding on one of them (the eyes
// sections 42-46 of docs/mrig-format.md 2.1).
RigData SurfaceWithEyes() {
  RigData data = Surface().data();
  data.eyes.centers = {{0.f, 0.f, -30.f}, {5.f, 5.f, -40.f}};
  for (uint32_t p = 0; p < data.active.points; p += 5) {
    data.eyes.points.push_back(p);
    data.eyes.eyes.push_back(p % 2);
    data.eyes.radii.push_back(Length(data.rest_points[p] - data.eyes.centers[p % 2]));
    data.eyes.weights.push_back(0.25f + 0.75f * float(p % 3) / 2.f);
  }
  return data;
}

// `loaded` evaluates to the bits `rig` does at activations `act` and each jaw opening.
void ExpectSameBits(const Rig& rig, const Rig& loaded, const std::vector<float>& act,
                    std::initializer_list<float> jaws = {0.f}) {
  for (float jaw : jaws) {
    const std::vector<float> want = Evaluate(rig, act, jaw), got = Evaluate(loaded, act, jaw);
    ASSERT_EQ(want.size(), got.size());
    EXPECT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0) << "jaw " << jaw;
  }
}

TEST(RigBinary, TheJawRoundTrips) {
  RigData data = Surface().data();
  for (uint32_t p = 0; p < data.active.points; p += 3) {
    data.jaw.points.push_back(p);
    data.jaw.weights.push_back(0.25f + 0.5f * float(p % 2));
  }
  data.jaw.pivot = {0.f, -60.f, -20.f};
  data.jaw.axis = {1.f, 0.f, 0.f};
  data.jaw.range = 0.3f;
  data.jaw.translation = {0.f, 0.f, 1.5f};
  Rig rig;
  ASSERT_TRUE(Rig::Build(data, &rig));
  const std::string bytes = WriteRigBinary(rig.data());
  Rig loaded;
  std::string error;
  ASSERT_TRUE(ReadRigBinary(Bytes(bytes), &loaded, nullptr, &error)) << error;
  EXPECT_EQ(loaded.jaw().points, rig.jaw().points);
  const std::vector<float> act(rig.muscle_count(), 0.4f);
  ExpectSameBits(rig, loaded, act, {0.f, 0.6f, 1.f});
  EXPECT_NE(Evaluate(rig, act, 1.f), Evaluate(rig, act, 0.f));  // the jaw did something
  // A hostile jaw point (past the active points) is refused by Rig::Build.
  std::string bad = bytes;
  PutU32(&bad, Find(bytes, 33).offset, 0xfffffff0u);
  Rechecksum(&bad);
  EXPECT_FALSE(ReadRigBinary(Bytes(bad), &loaded, nullptr, &error));
  EXPECT_NE(error.find("Rig::Build"), std::string::npos) << error;
}

TEST(RigBinary, WritingTwiceGivesTheSameBytes) {
  const std::string a = WriteRigBinary(Surface().data()), b = WriteRigBinary(Surface().data());
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.substr(0, 4), "MRIG");
  EXPECT_EQ(U64At(a, 16), a.size());
}

// Cut anywhere (the header, the table, each section's start, middle and last byte): the message
// names the first section that does not fit. On the plain surface and on the surface with
// eyes (whose sections 42-46 come last).
TEST(RigBinary, TruncationNamesTheSection) {
  // With a gate, the optional section 47 (muscle_wrinkle_gates) comes last.
  RigData gated = SurfaceWithEyes();
  ASSERT_FALSE(gated.muscle_wrinkles.empty());
  gated.muscle_wrinkles[0].gate = 0.5f;
  for (const RigData& data : {Surface().data(), SurfaceWithEyes(), gated}) {
    const std::string bytes = WriteRigBinary(data, nullptr);
    const std::vector<Entry> table = Table(bytes);
    ASSERT_GE(table.size(), 34u);
    const bool has_gate = data.muscle_wrinkles[0].gate > 0.f;
    SCOPED_TRACE(data.eyes.empty() ? "no eyes" : has_gate ? "with eyes and a gate" : "with eyes");
    if (!data.eyes.empty()) {
      ASSERT_EQ(table.back().id, has_gate ? 47u : 46u);
    }
    std::vector<size_t> cuts = {0, 3, 39};
    for (size_t k = 40; k < 40 + 32 * table.size(); k += 13) cuts.push_back(k);
    for (const Entry& e : table) {
      cuts.push_back(e.offset);                   // the boundary before it
      cuts.push_back(e.offset + e.size / 2);      // inside it
      if (e.size > 0) cuts.push_back(e.offset + e.size - 1);
    }
    for (size_t cut : cuts)
      if (cut < bytes.size())
        test::ExpectTruncationNamed(table, cut, ReadError(bytes.substr(0, cut)));
  }
}

TEST(RigBinary, FlippedBytesAreRefused) {
  const std::string bytes = WriteRigBinary(Surface().data(), nullptr);
  const size_t table_end = 40 + 32 * Table(bytes).size();
  std::vector<size_t> at;
  for (size_t i = 0; i < table_end; ++i) at.push_back(i);
  for (size_t i = table_end; i < bytes.size(); i += 97) at.push_back(i);
  at.push_back(bytes.size() - 1);
  for (size_t i : at) {
    for (uint8_t mask : {uint8_t(0x01), uint8_t(0xff)}) {
      std::string bad = bytes;
      bad[i] = char(bad[i] ^ mask);
      const std::string error = ReadError(bad);
      SCOPED_TRACE("byte " + std::to_string(i) + ": " + error);
      EXPECT_FALSE(error.empty());
      if (i >= table_end || (i >= 24 && i < 32)) {
        EXPECT_NE(error.find("checksum mismatch"), std::string::npos);
      }
      if (i < 4) {
        EXPECT_NE(error.find("tag"), std::string::npos);
      }
    }
  }
}

TEST(RigBinary, HugeElementCountIsRefusedBeforeAllocation) {
  const std::string bytes = WriteRigBinary(Surface().data(), nullptr);
  for (uint32_t id : {1u, 2u, 13u, 16u, 17u, 31u}) {
    const Entry e = Find(bytes, id);
    // A count no memory holds (resize would throw): refused by the table check first.
    for (uint64_t count : {uint64_t(1) << 62, e.count + 1, ~uint64_t(0)}) {
      std::string bad = bytes;
      PutU64(&bad, e.at + 24, count);
      Rechecksum(&bad);
      const std::string error = ReadError(bad);
      EXPECT_NE(error.find("(id " + std::to_string(id) + ")"), std::string::npos) << error;
    }
    // A size past the end of the file, with a count to match.
    std::string bad = bytes;
    PutU64(&bad, e.at + 16, uint64_t(1) << 40);
    PutU64(&bad, e.at + 24, (uint64_t(1) << 40) / std::max<uint32_t>(e.element_size, 1));
    Rechecksum(&bad);
    const std::string error = ReadError(bad);
    EXPECT_NE(error.find("(id " + std::to_string(id) + ")"), std::string::npos) << error;
  }
  // The muscle-wrinkle table's lengths must add up to the arrays' counts.
  std::string bad = bytes;
  const Entry t = Find(bytes, 17);
  PutU32(&bad, t.offset + 16, 0xfffffff0u);  // first record's row count
  Rechecksum(&bad);
  EXPECT_NE(ReadError(bad).find("muscle_wrinkle_points"), std::string::npos) << ReadError(bad);
}

uint64_t FirstTwoSidedProbe() {
  const std::vector<ShrinkageProbe>& probes = Surface().curve_wrinkles().probes;
  for (size_t i = 0; i < probes.size(); ++i)
    if (probes[i].side_count == 2) return i;
  ADD_FAILURE() << "no probe with two sides";
  return 0;
}

TEST(RigBinary, HostileIndicesAreRefusedByRigBuild) {
  const std::string bytes = WriteRigBinary(Surface().data(), nullptr);
  struct Edit {
    uint32_t id;
    uint64_t byte;  // within the section's payload
    uint32_t value;
    const char* what;
  };
  const Entry offsets = Find(bytes, 3);
  const Edit edits[] = {
      {2, 4, 0xfffffff0u, "triangle corner"},
      {3, 8 * 4, 0xfffffff0u, "point-triangle offset"},
      {3, offsets.size - 4, 0xfffffff0u, "last point-triangle offset"},
      {4, 0, 0x7fffffffu, "point-triangle index"},
      {5, 0, 0xffffffffu, "active point count"},
      {6, 0, 0x10000000u, "vertex point"},
      {7, 0, 0x10000000u, "vertex index"},
      {15, 4, 0x7fffffffu, "muscle offset"},
      {16, 0, 1000u, "muscle influence's muscle"},
      {17, 0, 999u, "wrinkled muscle"},
      {18, 0, 0xfffffffeu, "muscle-wrinkle point"},
      {22, 4, 0xfffffffeu, "muscle-wrinkle edge offset"},
      {23, 0, 0xfffffffeu, "muscle-wrinkle edge neighbour"},
      {28, 0, 0xfffffffeu, "curve-wrinkle point"},
      {29, 4, 0xfffffffeu, "curve-wrinkle offset"},
      {30, 0, 77u, "curve-wrinkle entry's wrinkle"},
      {31, 0, 0xfffffffeu, "probe point"},
      {31, 4, 3u, "probe side count"},
      {31, 48 * FirstTwoSidedProbe() + 28, 0xfffffffeu, "second side v2 of a probe"},
      {38, 0, 0xfffffff0u, "tension-region point"},
      {37, 4, 0u, "tension-region offsets out of order"},
  };
  for (const Edit& e : edits) {
    std::string bad = bytes;
    const Entry s = Find(bytes, e.id);
    ASSERT_LT(e.byte + 4, s.size + 1) << e.what;
    PutU32(&bad, s.offset + e.byte, e.value);
    Rechecksum(&bad);
    RigData data;
    std::string error;
    EXPECT_TRUE(ReadRigBinaryData(Bytes(bad), &data, nullptr, &error)) << e.what << ": " << error;
    Rig rig;
    EXPECT_FALSE(ReadRigBinary(Bytes(bad), &rig, nullptr, &error)) << e.what;
    EXPECT_NE(error.find("Rig::Build"), std::string::npos) << e.what << ": " << error;
  }
  // Values the reader itself refuses.
  {
    std::string bad = bytes;
    PutU32(&bad, Find(bytes, 9).offset, 2);  // a layer flag
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("'layers'"), std::string::npos);
  }
  {
    std::string bad = bytes;
    PutU32(&bad, Find(bytes, 27).offset, 3);  // a curve profile
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("'curve_wrinkle_params'"), std::string::npos);
  }
  {
    std::string bad = bytes;
    PutU32(&bad, Find(bytes, 13).offset + 4, 0xffffff00u);  // a string's end
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("'muscle_names'"), std::string::npos);
  }
}

// Format 1.1's tension regions are five sections, all or none: a file with some of them (a
// section's id changed to one no version knows, so the reader skips it as a newer minor's) is
// refused naming the sections and the count; with all five renamed the rig loads without
// regions; counts that do not agree are refused naming the offsets section.
// docs/model.md §24: the eyeballs the lids slide on (format 2.1's optional sections 42-46).
TEST(RigBinary, TheEyesRoundTripAndComeTogether) {
  ASSERT_TRUE(Surface().data().eyes.empty());
  const RigData data = SurfaceWithEyes();
  Rig rig;
  ASSERT_TRUE(Rig::Build(data, &rig));
  const std::string bytes = WriteRigBinary(rig.data());
  Rig loaded;
  std::string error;
  ASSERT_TRUE(ReadRigBinary(Bytes(bytes), &loaded, nullptr, &error)) << error;
  EXPECT_EQ(loaded.eyes().points, rig.eyes().points);
  EXPECT_EQ(loaded.eyes().eyes, rig.eyes().eyes);
  EXPECT_EQ(loaded.eyes().radii, rig.eyes().radii);
  EXPECT_EQ(loaded.eyes().weights, rig.eyes().weights);
  ASSERT_EQ(loaded.eyes().centers.size(), 2u);
  EXPECT_EQ(std::memcmp(&loaded.eyes().centers[1], &data.eyes.centers[1], 12), 0);
  const std::vector<float> act(rig.muscle_count(), 0.7f);
  ExpectSameBits(rig, loaded, act);
  EXPECT_NE(Evaluate(rig, act), Evaluate(Surface(), act));  // the eyes did something
  EXPECT_EQ(WriteRigBinary(loaded.data()), bytes);
  // Any of the five alone missing: refused, naming them.
  for (uint32_t id = 42; id <= 46; ++id) {
    const std::string e = ReadError(DropSections(bytes, {id}));
    EXPECT_NE(e.find("sections 'eye_*' (ids 42-46): the eyes need all five sections; 4 are "
                     "present"),
              std::string::npos)
        << id << ": " << e;
  }
  // All five missing: no eyes (a 2.0 file), the plain rig.
  ASSERT_TRUE(ReadRigBinary(Bytes(DropSections(bytes, {42, 43, 44, 45, 46})), &loaded, nullptr,
                            &error))
      << error;
  EXPECT_TRUE(loaded.eyes().empty());
  // Fewer radii than points: refused by the reader, with the counts.
  {
    const std::string e = ErrorWithOneFewer(bytes, 45);
    EXPECT_NE(e.find("held points need as many eye indices, radii and weights"),
              std::string::npos)
        << e;
  }
  // An eye index past the centres, and a weight above 1: refused by Rig::Build.
  for (uint32_t id : {44u, 46u}) {
    std::string bad = bytes;
    const uint32_t value = id == 44 ? 2u : 0x3fc00000u;  // index 2 of 2 centres; 1.5f
    PutU32(&bad, Find(bytes, id).offset, value);
    Rechecksum(&bad);
    EXPECT_FALSE(ReadRigBinary(Bytes(bad), &loaded, nullptr, &error)) << id;
    EXPECT_NE(error.find("Rig::Build"), std::string::npos) << error;
  }
}

// docs/model.md §6's gate, format 2.2's optional section 47: one value per muscle-wrinkle table.
TEST(RigBinary, TheWrinkleGatesRoundTripAndOldFilesHaveNone) {
  auto has_gates = [](const std::string& b) {
    for (const Entry& e : Table(b))
      if (e.id == 47) return true;
    return false;
  };
  // Without a gate the section is not written (a 2.1 reader reads the same file).
  const std::string plain = WriteRigBinary(Surface().data());
  EXPECT_FALSE(has_gates(plain));
  RigData data = Surface().data();
  ASSERT_FALSE(data.muscle_wrinkles.empty());
  data.muscle_wrinkles[0].gate = 0.5f;
  Rig rig;
  ASSERT_TRUE(Rig::Build(data, &rig));
  const std::string bytes = WriteRigBinary(rig.data());
  ASSERT_TRUE(has_gates(bytes));
  EXPECT_EQ(Find(bytes, 47).count, data.muscle_wrinkles.size());
  Rig loaded;
  std::string error;
  ASSERT_TRUE(ReadRigBinary(Bytes(bytes), &loaded, nullptr, &error)) << error;
  for (size_t k = 0; k < data.muscle_wrinkles.size(); ++k)
    EXPECT_EQ(loaded.muscle_wrinkles()[k].gate, data.muscle_wrinkles[k].gate) << k;
  const std::vector<float> act(rig.muscle_count(), 0.3f);  // G = 0.648 < 1: the gate acts
  ExpectSameBits(rig, loaded, act);
  EXPECT_NE(Evaluate(rig, act), Evaluate(Surface(), act));
  EXPECT_EQ(WriteRigBinary(loaded.data()), bytes);
  // The section dropped (a 2.1 file): no gate, the plain rig's bits.
  ASSERT_TRUE(ReadRigBinary(Bytes(DropSections(bytes, {47})), &loaded, nullptr, &error)) << error;
  EXPECT_EQ(loaded.muscle_wrinkles()[0].gate, 0.f);
  ExpectSameBits(Surface(), loaded, act);
  // One gate too few: refused by the reader, with the counts.
  {
    const Entry gates = Find(bytes, 47);
    ASSERT_EQ(gates.element_size, 4u);
    const std::string e = ErrorWithOneFewer(bytes, 47);
    EXPECT_NE(e.find(std::to_string(gates.count - 1) + " gates for " +
                     std::to_string(gates.count) + " muscle-wrinkle tables"),
              std::string::npos)
        << e;
  }
  // A gate above 1 or NaN: refused by Rig::Build.
  for (const uint32_t value : {0x3fc00000u, 0x7fc00000u}) {  // 1.5f, NaN
    std::string bad = bytes;
    PutU32(&bad, Find(bytes, 47).offset, value);
    Rechecksum(&bad);
    EXPECT_FALSE(ReadRigBinary(Bytes(bad), &loaded, nullptr, &error)) << value;
    EXPECT_NE(error.find("Rig::Build"), std::string::npos) << error;
  }
}

TEST(RigBinary, TensionRegionsNeedAllFiveSections) {
  const std::string bytes = WriteRigBinary(Surface().data(), nullptr);
  ASSERT_EQ(Surface().tension_region_count(), 2u);
  const char* const names[] = {"tension_region_names", "tension_region_references",
                               "tension_region_offsets", "tension_region_points",
                               "tension_region_weights"};
  {
    // The sections physically removed from a valid file: every proper subset of the five
    // (1-4 present) is refused, the message naming each absent section and no present one.
    for (uint32_t keep = 1; keep < 31; ++keep) {
      std::vector<uint32_t> drop;
      for (uint32_t i = 0; i < 5; ++i)
        if (!(keep >> i & 1)) drop.push_back(35 + i);
      const std::string bad = DropSections(bytes, drop);
      ASSERT_EQ(bad.size() < bytes.size(), true);
      ASSERT_EQ(Table(bad).size() + drop.size(), Table(bytes).size());
      const std::string error = ReadError(bad);
      EXPECT_NE(error.find("the tension regions need all five sections; " +
                           std::to_string(5 - drop.size()) + " are present, missing"),
                std::string::npos)
          << keep << ": " << error;
      for (uint32_t i = 0; i < 5; ++i) {
        const std::string named =
            "'" + std::string(names[i]) + "' (id " + std::to_string(35 + i) + ")";
        EXPECT_EQ(error.find(named) != std::string::npos, !(keep >> i & 1))
            << keep << ", " << named << ": " << error;
      }
    }
    // All five removed: a rig without regions, otherwise the same.
    Rig rig;
    std::string error;
    ASSERT_TRUE(ReadRigBinary(Bytes(DropSections(bytes, {35, 36, 37, 38, 39})), &rig, nullptr,
                              &error))
        << error;
    EXPECT_EQ(rig.tension_region_count(), 0u);
    std::vector<float> act(rig.muscle_count(), 0.5f);
    EXPECT_EQ(Evaluate(rig, act), Evaluate(Surface(), act));
    // The helper itself: dropping nothing gives the writer's bytes back.
    EXPECT_EQ(DropSections(bytes, {}), bytes);
  }
  for (uint32_t missing = 35; missing <= 39; ++missing) {
    std::string bad = bytes;
    PutU32(&bad, 4, 2 | 7 << 16);  // 2.7: unknown ids are skipped, not refused
    PutU32(&bad, Find(bytes, missing).at, 4000 + missing);
    Rechecksum(&bad);
    const std::string error = ReadError(bad);
    EXPECT_NE(error.find("tension regions need all five sections; 4 are present, missing '" +
                         std::string(names[missing - 35]) + "' (id " +
                         std::to_string(missing) + ")"),
              std::string::npos) << missing << ": " << error;
  }
  {
    std::string none = bytes;
    PutU32(&none, 4, 2 | 7 << 16);
    for (uint32_t id = 35; id <= 39; ++id) PutU32(&none, Find(bytes, id).at, 4000 + id);
    Rechecksum(&none);
    Rig rig;
    std::string error;
    ASSERT_TRUE(ReadRigBinary(Bytes(none), &rig, nullptr, &error)) << error;
    EXPECT_EQ(rig.tension_region_count(), 0u);
    EXPECT_EQ(rig.vertex_count(), Surface().vertex_count());
  }
  {
    // One name fewer than the references (the names section's count): refused.
    std::string bad = bytes;
    const Entry names = Find(bytes, 35);
    PutU64(&bad, names.at + 24, names.count - 1);
    Rechecksum(&bad);
    const std::string error = ReadError(bad);
    EXPECT_NE(error.find("tension_region"), std::string::npos) << error;
  }
}

TEST(RigBinary, VersionsAndUnknownSections) {
  const RigBinaryInfo info{"cm", 12};
  const std::string bytes = WriteRigBinary(Surface().data(), &info);
  EXPECT_EQ(U32At(bytes, 4), 2u | 2u << 16);  // version 2.2
  EXPECT_EQ(U64At(bytes, 24), ChecksumOf(bytes, true));
  {
    // A 1.1 file (the same sections, the one-lane checksum) still loads, to the same rig.
    std::string old = bytes;
    PutU32(&old, 4, 1 | 1 << 16);
    PutU64(&old, 24, ChecksumOf(old, false));
    Rig rig;
    std::string error;
    ASSERT_TRUE(ReadRigBinary(Bytes(old), &rig, nullptr, &error)) << error;
    std::vector<float> act(rig.muscle_count(), 0.5f);
    EXPECT_EQ(Evaluate(rig, act), Evaluate(Surface(), act));
    // ... but not with the four-lane checksum, and a 2.0 file not with the one-lane one.
    PutU64(&old, 24, ChecksumOf(old, true));
    EXPECT_NE(ReadError(old).find("checksum mismatch"), std::string::npos) << ReadError(old);
    std::string two = bytes;
    PutU64(&two, 24, ChecksumOf(two, false));
    EXPECT_NE(ReadError(two).find("checksum mismatch"), std::string::npos) << ReadError(two);
  }
  {
    std::string newer = bytes;
    PutU32(&newer, 4, 3 | 0 << 16);  // major 3
    Rechecksum(&newer);
    EXPECT_NE(ReadError(newer).find("newer"), std::string::npos) << ReadError(newer);
  }
  {
    // A newer minor version with a section this reader does not know: skipped.
    std::string newer = bytes;
    PutU32(&newer, 4, 2 | 7 << 16);
    PutU32(&newer, Find(bytes, 65).at, 4000);  // the optional source-vertex-count section
    Rechecksum(&newer);
    Rig rig;
    RigBinaryInfo got;
    std::string error;
    EXPECT_TRUE(ReadRigBinary(Bytes(newer), &rig, &got, &error)) << error;
    EXPECT_EQ(got.units, "cm");
    EXPECT_EQ(got.source_vertex_count, 0u);
  }
  {
    // A required section's id changed: it is missing.
    std::string bad = bytes;
    PutU32(&bad, Find(bytes, 2).at, 4000);
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("'triangles' (id 2)"), std::string::npos) << ReadError(bad);
  }
  {
    std::string bad = bytes;
    PutU32(&bad, Find(bytes, 2).at, 1);  // two rest_points sections
    Rechecksum(&bad);
    EXPECT_NE(ReadError(bad).find("twice"), std::string::npos) << ReadError(bad);
  }
  EXPECT_NE(ReadError("").find("header"), std::string::npos);
  EXPECT_NE(ReadError(std::string(64, 'x')).find("tag"), std::string::npos);
}

}  // namespace
}  // namespace mimetic
