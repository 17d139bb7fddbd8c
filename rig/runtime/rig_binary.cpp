// rig/runtime/rig_binary.cpp: the .mrig writer and reader (docs/mrig-format.md).
#include "rig/runtime/rig_binary.h"

#include <bit>
#include <cstdio>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include <sys/stat.h>

namespace mimetic {
namespace {

// Section ids of format 1.x. Adding a RigData array: one id here, one row in kSections, one
// Put in WriteRigBinary and one Get in ReadRigBinaryData (a new id in a new minor version is
// skipped by older readers; make it optional so that files of the older minor still load).
enum SectionId : uint32_t {
  kRestPoints = 1,
  kTriangles = 2,
  kPointTriangleOffsets = 3,
  kPointTriangles = 4,
  kActiveRanges = 5,
  kVertexPoints = 6,
  kVertexIndices = 7,
  kVertexUvs = 8,
  kLayers = 9,
  kPointThickness = 10,
  kRestTriangleAreas = 11,
  kMinAreaRatio = 12,
  kMuscleNames = 13,
  kMuscleCount = 14,
  kMuscleOffsets = 15,
  kMuscleEntries = 16,
  kMuscleWrinkleTable = 17,
  kMwPoints = 18,
  kMwPhase = 19,
  kMwAttenuation = 20,
  kMwProfile = 21,
  kMwEdgeOffsets = 22,
  kMwEdgeNeighbors = 23,
  kMwEdgeRestLengths = 24,
  kMwEdgeWeights = 25,
  kCwNames = 26,
  kCwParams = 27,
  kCwPoints = 28,
  kCwOffsets = 29,
  kCwEntries = 30,
  kCwProbes = 31,
  kJawParams = 32,
  kJawPoints = 33,
  kJawWeights = 34,
  // 1.1: tension regions (optional; absent = none).
  kTensionNames = 35,
  kTensionReferences = 36,
  kTensionOffsets = 37,
  kTensionPoints = 38,
  kTensionWeights = 39,
  kInfoUnits = 64,
  kInfoSourceVertexCount = 65,
};

// element_size 0: a string table (u32 offsets[count + 1], then the characters).
struct SectionDesc {
  uint32_t id;
  const char* name;
  uint32_t element_size;
  uint64_t fixed_count;  // 0: any count
  bool required;
};

// The muscle-wrinkle table: per wrinkled muscle, muscle, half_cycle, furrow_depth, shape and
// the length of each of its 8 arrays (in the order of kMwPoints .. kMwEdgeWeights).
constexpr uint32_t kMwArrays = 8;
constexpr uint32_t kMwRecordBytes = 4 * (4 + kMwArrays);

constexpr SectionDesc kSections[] = {
    {kRestPoints, "rest_points", 12, 0, true},
    {kTriangles, "triangles", 4, 0, true},
    {kPointTriangleOffsets, "point_triangle_offsets", 4, 0, true},
    {kPointTriangles, "point_triangles", 4, 0, true},
    {kActiveRanges, "active_ranges", 4, 3, true},
    {kVertexPoints, "vertex_points", 4, 0, true},
    {kVertexIndices, "vertex_indices", 4, 0, true},
    {kVertexUvs, "vertex_uvs", 8, 0, true},
    {kLayers, "layers", 4, 3, true},
    {kPointThickness, "point_thickness", 4, 0, true},
    {kRestTriangleAreas, "rest_triangle_areas", 4, 0, true},
    {kMinAreaRatio, "min_area_ratio", 4, 1, true},
    {kMuscleNames, "muscle_names", 0, 0, true},
    {kMuscleCount, "muscle_count", 4, 1, true},
    {kMuscleOffsets, "muscle_offsets", 4, 0, true},
    {kMuscleEntries, "muscle_entries", 16, 0, true},
    {kMuscleWrinkleTable, "muscle_wrinkle_table", kMwRecordBytes, 0, true},
    {kMwPoints, "muscle_wrinkle_points", 4, 0, true},
    {kMwPhase, "muscle_wrinkle_phase", 4, 0, true},
    {kMwAttenuation, "muscle_wrinkle_attenuation", 4, 0, true},
    {kMwProfile, "muscle_wrinkle_profile", 4, 0, true},
    {kMwEdgeOffsets, "muscle_wrinkle_edge_offsets", 4, 0, true},
    {kMwEdgeNeighbors, "muscle_wrinkle_edge_neighbors", 4, 0, true},
    {kMwEdgeRestLengths, "muscle_wrinkle_edge_rest_lengths", 4, 0, true},
    {kMwEdgeWeights, "muscle_wrinkle_edge_weights", 4, 0, true},
    {kCwNames, "curve_wrinkle_names", 0, 0, true},
    {kCwParams, "curve_wrinkle_params", 24, 0, true},
    {kCwPoints, "curve_wrinkle_points", 4, 0, true},
    {kCwOffsets, "curve_wrinkle_offsets", 4, 0, true},
    {kCwEntries, "curve_wrinkle_entries", 16, 0, true},
    {kCwProbes, "curve_wrinkle_probes", 48, 0, true},
    {kJawParams, "jaw_params", 4, 10, true},
    {kJawPoints, "jaw_points", 4, 0, true},
    {kJawWeights, "jaw_weights", 4, 0, true},
    {kTensionNames, "tension_region_names", 0, 0, false},
    {kTensionReferences, "tension_region_references", 4, 0, false},
    {kTensionOffsets, "tension_region_offsets", 4, 0, false},
    {kTensionPoints, "tension_region_points", 4, 0, false},
    {kTensionWeights, "tension_region_weights", 4, 0, false},
    {kInfoUnits, "info_units", 0, 1, false},
    {kInfoSourceVertexCount, "info_source_vertex_count", 4, 1, false},
};

const SectionDesc* FindSection(uint32_t id) {
  for (const SectionDesc& d : kSections)
    if (d.id == id) return &d;
  return nullptr;
}

// ---- little-endian scalars ----------------------------------------------------------------

inline uint32_t LoadU32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
inline uint16_t LoadU16(const uint8_t* p) { return uint16_t(p[0] | p[1] << 8); }
inline uint64_t LoadU64(const uint8_t* p) {
  if constexpr (std::endian::native == std::endian::little) {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
  }
  return LoadU32(p) | uint64_t(LoadU32(p + 4)) << 32;
}
inline float LoadF32(const uint8_t* p) { return std::bit_cast<float>(LoadU32(p)); }

inline void StoreU32(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v), p[1] = uint8_t(v >> 8), p[2] = uint8_t(v >> 16), p[3] = uint8_t(v >> 24);
}
inline void StoreU16(uint8_t* p, uint16_t v) { p[0] = uint8_t(v), p[1] = uint8_t(v >> 8); }
inline void StoreU64(uint8_t* p, uint64_t v) {
  StoreU32(p, uint32_t(v));
  StoreU32(p + 4, uint32_t(v >> 32));
}

// ---- writer -------------------------------------------------------------------------------

struct OutSection {
  uint32_t id = 0;
  uint32_t element_size = 0;
  uint64_t count = 0;
  std::vector<uint8_t> payload;
};

class Payload {
 public:
  explicit Payload(OutSection* s) : s_(s) {}
  void U32(uint32_t v) {
    const size_t n = s_->payload.size();
    s_->payload.resize(n + 4);
    StoreU32(&s_->payload[n], v);
  }
  void F32(float v) { U32(std::bit_cast<uint32_t>(v)); }
  void Bytes(const std::string& s) { s_->payload.insert(s_->payload.end(), s.begin(), s.end()); }

 private:
  OutSection* s_;
};

class SectionWriter {
 public:
  OutSection& Begin(uint32_t id, uint64_t count) {
    const SectionDesc* d = FindSection(id);
    OutSection s;
    s.id = id;
    s.element_size = d->element_size;
    s.count = count;
    sections_.push_back(std::move(s));
    return sections_.back();
  }
  void U32s(uint32_t id, const std::vector<uint32_t>& v) {
    Payload p(&Begin(id, v.size()));
    for (uint32_t x : v) p.U32(x);
  }
  void F32s(uint32_t id, const std::vector<float>& v) {
    Payload p(&Begin(id, v.size()));
    for (float x : v) p.F32(x);
  }
  void Float3s(uint32_t id, const std::vector<float3>& v) {
    Payload p(&Begin(id, v.size()));
    for (const float3& x : v) p.F32(x.x), p.F32(x.y), p.F32(x.z);
  }
  void Float2s(uint32_t id, const std::vector<float2>& v) {
    Payload p(&Begin(id, v.size()));
    for (const float2& x : v) p.F32(x.x), p.F32(x.y);
  }
  void Strings(uint32_t id, const std::vector<std::string>& v) {
    Payload p(&Begin(id, v.size()));
    uint32_t at = 0;
    p.U32(0);
    for (const std::string& s : v) p.U32(at += uint32_t(s.size()));
    for (const std::string& s : v) p.Bytes(s);
  }
  std::vector<OutSection>& sections() { return sections_; }

 private:
  std::vector<OutSection> sections_;
};

size_t Align8(size_t n) { return (n + 7) & ~size_t{7}; }

// ---- reader -------------------------------------------------------------------------------

struct InSection {
  const SectionDesc* desc = nullptr;
  uint64_t offset = 0, size = 0, count = 0;
  const uint8_t* data = nullptr;
};

std::string SectionWhere(const SectionDesc& d, uint64_t offset) {
  return "section '" + std::string(d.name) + "' (id " + std::to_string(d.id) + ") at byte " +
         std::to_string(offset);
}

class Reader {
 public:
  Reader(const InSection* sections, std::string* error) : sections_(sections), error_(error) {}

  const InSection& Of(uint32_t id) const {
    for (size_t i = 0; i < std::size(kSections); ++i)
      if (kSections[i].id == id) return sections_[i];
    return sections_[0];  // not reached: every id is in kSections
  }
  bool Fail(const InSection& s, const std::string& what) {
    *error_ = SectionWhere(*s.desc, s.offset) + ": " + what;
    return false;
  }
  // Elements [first, first + n) of a fixed-size section, already bounds-checked by the table.
  void U32s(const InSection& s, uint64_t first, uint64_t n, std::vector<uint32_t>* out) {
    out->resize(size_t(n));
    const uint8_t* p = s.data + 4 * first;
    for (uint64_t i = 0; i < n; ++i) (*out)[size_t(i)] = LoadU32(p + 4 * i);
  }
  void F32s(const InSection& s, uint64_t first, uint64_t n, std::vector<float>* out) {
    out->resize(size_t(n));
    const uint8_t* p = s.data + 4 * first;
    for (uint64_t i = 0; i < n; ++i) (*out)[size_t(i)] = LoadF32(p + 4 * i);
  }
  void U32s(uint32_t id, std::vector<uint32_t>* out) {
    const InSection& s = Of(id);
    U32s(s, 0, s.count, out);
  }
  void F32s(uint32_t id, std::vector<float>* out) {
    const InSection& s = Of(id);
    F32s(s, 0, s.count, out);
  }
  void Float3s(uint32_t id, std::vector<float3>* out) {
    const InSection& s = Of(id);
    out->resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 12 * i;
      (*out)[size_t(i)] = {LoadF32(p), LoadF32(p + 4), LoadF32(p + 8)};
    }
  }
  void Float2s(uint32_t id, std::vector<float2>* out) {
    const InSection& s = Of(id);
    out->resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 8 * i;
      (*out)[size_t(i)] = {LoadF32(p), LoadF32(p + 4)};
    }
  }
  bool Strings(uint32_t id, std::vector<std::string>* out) {
    const InSection& s = Of(id);
    if (!s.data) return true;  // optional and absent
    const uint64_t table = 4 * (s.count + 1);  // the table check made sure it fits
    const uint64_t chars = s.size - table;
    const uint8_t* c = s.data + table;
    out->clear();
    out->reserve(size_t(s.count));
    uint32_t prev = LoadU32(s.data);
    if (prev != 0) return Fail(s, "string offset 0 is " + std::to_string(prev) + "; expected 0");
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint32_t next = LoadU32(s.data + 4 * (i + 1));
      if (next < prev || next > chars)
        return Fail(s, "string " + std::to_string(i) + " ends at " + std::to_string(next) +
                           ", outside [" + std::to_string(prev) + ", " + std::to_string(chars) +
                           "]");
      out->emplace_back(reinterpret_cast<const char*>(c + prev), next - prev);
      prev = next;
    }
    if (prev != chars)
      return Fail(s, "the strings hold " + std::to_string(prev) + " bytes; the section has " +
                         std::to_string(chars) + " after its offsets");
    return true;
  }

 private:
  const InSection* sections_;
  std::string* error_;
};

}  // namespace

uint64_t Fnv1a64(span<const uint8_t> bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (uint8_t b : bytes) {
    h ^= b;
    h *= 0x100000001b3ull;
  }
  return h;
}

uint64_t RigBinaryChecksum(span<const uint8_t> file) {
  if (file.size() < kRigBinaryHeaderBytes) return 0;
  // FNV-1a's offset basis and prime over 64-bit little-endian words (8x fewer serial steps than
  // bytes: the 33 MB sample head checks in a few ms), the state rotated before each word so that
  // high input bits reach the low bits; word 3 (bytes [24, 32), the checksum) counts as 0 and
  // the tail is zero padded.
  uint64_t h = 0xcbf29ce484222325ull;
  const size_t words = file.size() / 8;
  const uint8_t* p = file.data();
  for (size_t i = 0; i < words; ++i) {
    const uint64_t w = i == 3 ? 0 : LoadU64(p + 8 * i);
    h = (std::rotl(h, 23) ^ w) * 0x100000001b3ull;
  }
  if (file.size() % 8) {
    uint8_t tail[8] = {};
    std::memcpy(tail, p + 8 * words, file.size() % 8);
    h = (std::rotl(h, 23) ^ LoadU64(tail)) * 0x100000001b3ull;
  }
  return h;
}

bool HasRigBinaryTag(span<const uint8_t> bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), kRigBinaryTag, 4) == 0;
}

std::string WriteRigBinary(const RigData& d, const RigBinaryInfo* info) {
  SectionWriter w;
  w.Float3s(kRestPoints, d.rest_points);
  w.U32s(kTriangles, d.triangles);
  w.U32s(kPointTriangleOffsets, d.point_triangle_offsets);
  w.U32s(kPointTriangles, d.point_triangles);
  w.U32s(kActiveRanges, {d.active.points, d.active.normal_points, d.active.triangles});
  w.U32s(kVertexPoints, d.vertex_points);
  w.U32s(kVertexIndices, d.vertex_indices);
  w.Float2s(kVertexUvs, d.vertex_uvs);
  w.U32s(kLayers, {uint32_t(d.layers.thickness), uint32_t(d.layers.muscle_wrinkles),
                   uint32_t(d.layers.curve_wrinkles)});
  w.F32s(kPointThickness, d.point_thickness);
  w.F32s(kRestTriangleAreas, d.rest_triangle_areas);
  w.F32s(kMinAreaRatio, {d.min_area_ratio});
  w.Strings(kMuscleNames, d.muscle_names);
  w.U32s(kMuscleCount, {d.muscles.muscle_count});
  w.U32s(kMuscleOffsets, d.muscles.offsets);
  {
    Payload p(&w.Begin(kMuscleEntries, d.muscles.entries.size()));
    for (const MuscleInfluence& e : d.muscles.entries)
      p.U32(e.muscle), p.F32(e.displacement.x), p.F32(e.displacement.y), p.F32(e.displacement.z);
  }
  {
    Payload p(&w.Begin(kMuscleWrinkleTable, d.muscle_wrinkles.size()));
    for (const RigMuscleWrinkles& m : d.muscle_wrinkles) {
      p.U32(m.muscle), p.F32(m.half_cycle), p.F32(m.furrow_depth), p.F32(m.shape);
      for (size_t n : {m.points.size(), m.phase.size(), m.attenuation.size(), m.profile.size(),
                       m.edge_offsets.size(), m.edge_neighbors.size(),
                       m.edge_rest_lengths.size(), m.edge_weights.size()})
        p.U32(uint32_t(n));
    }
    auto concat_u32 = [&](uint32_t id, std::vector<uint32_t> RigMuscleWrinkles::*field) {
      uint64_t n = 0;
      for (const RigMuscleWrinkles& m : d.muscle_wrinkles) n += (m.*field).size();
      Payload q(&w.Begin(id, n));
      for (const RigMuscleWrinkles& m : d.muscle_wrinkles)
        for (uint32_t x : m.*field) q.U32(x);
    };
    auto concat_f32 = [&](uint32_t id, std::vector<float> RigMuscleWrinkles::*field) {
      uint64_t n = 0;
      for (const RigMuscleWrinkles& m : d.muscle_wrinkles) n += (m.*field).size();
      Payload q(&w.Begin(id, n));
      for (const RigMuscleWrinkles& m : d.muscle_wrinkles)
        for (float x : m.*field) q.F32(x);
    };
    concat_u32(kMwPoints, &RigMuscleWrinkles::points);
    concat_f32(kMwPhase, &RigMuscleWrinkles::phase);
    concat_f32(kMwAttenuation, &RigMuscleWrinkles::attenuation);
    concat_f32(kMwProfile, &RigMuscleWrinkles::profile);
    concat_u32(kMwEdgeOffsets, &RigMuscleWrinkles::edge_offsets);
    concat_u32(kMwEdgeNeighbors, &RigMuscleWrinkles::edge_neighbors);
    concat_f32(kMwEdgeRestLengths, &RigMuscleWrinkles::edge_rest_lengths);
    concat_f32(kMwEdgeWeights, &RigMuscleWrinkles::edge_weights);
  }
  const RigCurveWrinkles& c = d.curve_wrinkles;
  w.Strings(kCwNames, c.names);
  {
    Payload p(&w.Begin(kCwParams, c.wrinkles.size()));
    for (const CurveWrinkleParams& q : c.wrinkles)
      p.U32(uint32_t(q.profile)), p.U32(uint32_t(q.modulation)), p.F32(q.depth), p.F32(q.width),
          p.F32(q.rest_amplitude), p.F32(q.rest_length);
  }
  w.U32s(kCwPoints, c.points);
  w.U32s(kCwOffsets, c.offsets);
  {
    Payload p(&w.Begin(kCwEntries, c.entries.size()));
    for (const CurveWrinkleEntry& e : c.entries)
      p.U32(e.wrinkle), p.F32(e.distance), p.F32(e.profile), p.U32(e.has_profile);
  }
  {
    Payload p(&w.Begin(kCwProbes, c.probes.size()));
    for (const ShrinkageProbe& q : c.probes) {
      p.U32(q.point), p.U32(q.side_count);
      for (const ShrinkageSide& s : q.sides)
        p.U32(s.v2), p.U32(s.v3), p.F32(s.beta), p.F32(s.rest_length2), p.F32(s.rest_length3);
    }
  }
  const RigJaw& jaw = d.jaw;
  w.F32s(kJawParams, {jaw.pivot.x, jaw.pivot.y, jaw.pivot.z, jaw.axis.x, jaw.axis.y, jaw.axis.z,
                      jaw.range, jaw.translation.x, jaw.translation.y, jaw.translation.z});
  w.U32s(kJawPoints, jaw.points);
  w.F32s(kJawWeights, jaw.weights);
  if (!d.tension_regions.empty()) {
    const RigTensionRegions& g = d.tension_regions;
    w.Strings(kTensionNames, g.names);
    w.F32s(kTensionReferences, g.references);
    w.U32s(kTensionOffsets, g.offsets);
    w.U32s(kTensionPoints, g.points);
    w.F32s(kTensionWeights, g.weights);
  }
  if (info) {
    w.Strings(kInfoUnits, {info->units});
    w.U32s(kInfoSourceVertexCount, {info->source_vertex_count});
  }

  // Layout: header, section table, then each payload at an 8-byte boundary (zero padding).
  std::vector<OutSection>& sections = w.sections();
  const size_t table_end =
      kRigBinaryHeaderBytes + kRigBinarySectionEntryBytes * sections.size();
  size_t at = table_end;
  std::vector<size_t> offsets;
  for (const OutSection& s : sections) {
    at = Align8(at);
    offsets.push_back(at);
    at += s.payload.size();
  }
  std::string out(at, '\0');
  uint8_t* b = reinterpret_cast<uint8_t*>(out.data());
  for (size_t i = 0; i < sections.size(); ++i) {
    uint8_t* e = b + kRigBinaryHeaderBytes + kRigBinarySectionEntryBytes * i;
    StoreU32(e, sections[i].id);
    StoreU32(e + 4, sections[i].element_size);
    StoreU64(e + 8, offsets[i]);
    StoreU64(e + 16, sections[i].payload.size());
    StoreU64(e + 24, sections[i].count);
    if (!sections[i].payload.empty())
      std::memcpy(b + offsets[i], sections[i].payload.data(), sections[i].payload.size());
  }
  std::memcpy(b, kRigBinaryTag, 4);
  StoreU16(b + 4, kRigBinaryMajor);
  StoreU16(b + 6, kRigBinaryMinor);
  StoreU32(b + 8, 0);  // flags
  StoreU32(b + 12, uint32_t(sections.size()));
  StoreU64(b + 16, out.size());
  StoreU32(b + 32, uint32_t(kRigBinaryHeaderBytes));
  StoreU32(b + 36, 0);  // reserved
  StoreU64(b + 24, RigBinaryChecksum(span<const uint8_t>(b, out.size())));
  return out;
}

bool ReadRigBinaryData(span<const uint8_t> bytes, RigData* out, RigBinaryInfo* info,
                       std::string* error) {
  std::string local_error;
  if (!error) error = &local_error;
  const uint64_t size = bytes.size();
  const uint8_t* b = bytes.data();
  auto fail = [&](const std::string& where, const std::string& what) {
    *error = where + ": " + what;
    return false;
  };
  if (size < kRigBinaryHeaderBytes)
    return fail("header", "the file is " + std::to_string(size) + " bytes; a .mrig header is " +
                              std::to_string(kRigBinaryHeaderBytes) + " (truncated)");
  if (!HasRigBinaryTag(bytes))
    return fail("header at byte 0", "the tag is not \"MRIG\" (not a compiled rig)");
  const uint16_t major = LoadU16(b + 4), minor = LoadU16(b + 6);
  const std::string version = std::to_string(major) + "." + std::to_string(minor);
  if (major > kRigBinaryMajor)
    return fail("header at byte 4",
                "format version " + version + " is newer than this reader's " +
                    std::to_string(kRigBinaryMajor) + "." + std::to_string(kRigBinaryMinor) +
                    " (a newer major version); rebuild the rig with this version's "
                    "`mimetic build`");
  if (major == 0) return fail("header at byte 4", "format version " + version + " is not valid");
  const uint32_t flags = LoadU32(b + 8);
  if (flags != 0)
    return fail("header at byte 8", "flags are " + std::to_string(flags) +
                                        "; format 1 defines none (expected 0)");
  if (LoadU32(b + 32) != kRigBinaryHeaderBytes || LoadU32(b + 36) != 0)
    return fail("header at byte 32", "header size " + std::to_string(LoadU32(b + 32)) +
                                         " / reserved " + std::to_string(LoadU32(b + 36)) +
                                         "; expected " + std::to_string(kRigBinaryHeaderBytes) +
                                         " / 0");
  const uint64_t section_count = LoadU32(b + 12);
  if (section_count > (size - kRigBinaryHeaderBytes) / kRigBinarySectionEntryBytes)
    return fail("section table at byte " + std::to_string(kRigBinaryHeaderBytes),
                std::to_string(section_count) + " entries of " +
                    std::to_string(kRigBinarySectionEntryBytes) +
                    " bytes extend past the end of the file (" + std::to_string(size) +
                    " bytes; truncated or corrupt)");
  const uint64_t table_end = kRigBinaryHeaderBytes + kRigBinarySectionEntryBytes * section_count;

  // Every entry's bounds and counts before any payload is read.
  InSection known[std::size(kSections)];
  uint64_t prev_end = table_end;
  for (uint64_t i = 0; i < section_count; ++i) {
    const uint64_t at = kRigBinaryHeaderBytes + kRigBinarySectionEntryBytes * i;
    const uint8_t* e = b + at;
    const uint32_t id = LoadU32(e), element_size = LoadU32(e + 4);
    const uint64_t offset = LoadU64(e + 8), bytes_size = LoadU64(e + 16), count = LoadU64(e + 24);
    const SectionDesc* d = FindSection(id);
    const std::string where =
        d ? SectionWhere(*d, offset)
          : "section table entry " + std::to_string(i) + " (unknown id " + std::to_string(id) +
                ") at byte " + std::to_string(at);
    if (offset < prev_end || offset % 8 != 0)
      return fail(where, "offset " + std::to_string(offset) +
                             " overlaps the table or the section before it, or is not a "
                             "multiple of 8 (expected at least " + std::to_string(prev_end) + ")");
    if (offset > size || bytes_size > size - offset)
      return fail(where, "its " + std::to_string(bytes_size) +
                             " bytes extend past the end of the file (" + std::to_string(size) +
                             " bytes; truncated or corrupt)");
    prev_end = offset + bytes_size;
    if (!d) continue;  // a newer minor version's section: skipped
    const size_t k = size_t(d - kSections);
    if (known[k].desc) return fail(where, "appears twice in the section table");
    if (element_size != d->element_size)
      return fail(where, "element size " + std::to_string(element_size) + "; expected " +
                             std::to_string(d->element_size));
    if (d->fixed_count && count != d->fixed_count)
      return fail(where, std::to_string(count) + " elements; expected " +
                             std::to_string(d->fixed_count));
    if (element_size > 0) {
      if (count > bytes_size / element_size || count * element_size != bytes_size)
        return fail(where, std::to_string(count) + " elements of " +
                               std::to_string(element_size) + " bytes do not make its " +
                               std::to_string(bytes_size) + " bytes");
    } else if (count >= bytes_size / 4) {  // a string table: count + 1 offsets at least
      return fail(where, std::to_string(count) + " strings need " +
                             "more than its " + std::to_string(bytes_size) + " bytes");
    }
    known[k] = {d, offset, bytes_size, count, b + offset};
  }
  if (LoadU64(b + 16) != size)
    return fail("header at byte 16", "total size " + std::to_string(LoadU64(b + 16)) +
                                         " bytes; the file has " + std::to_string(size) +
                                         " (truncated or corrupt)");
  const uint64_t stored = LoadU64(b + 24);
  const uint64_t computed = RigBinaryChecksum(bytes);
  if (stored != computed) {
    char hex[80];
    std::snprintf(hex, sizeof hex, "stored %016llx, computed %016llx",
                  (unsigned long long)stored, (unsigned long long)computed);
    return fail("header at byte 24",
                std::string("checksum mismatch (") + hex + "): the file is corrupt");
  }
  for (size_t k = 0; k < std::size(kSections); ++k)
    if (kSections[k].required && !known[k].desc)
      return fail("section '" + std::string(kSections[k].name) + "' (id " +
                      std::to_string(kSections[k].id) + ")",
                  "missing from the section table");
  // Absent optional sections read as empty.
  for (size_t k = 0; k < std::size(kSections); ++k)
    if (!known[k].desc) known[k] = {&kSections[k], 0, 0, 0, nullptr};

  Reader r(known, error);
  RigData d;
  r.Float3s(kRestPoints, &d.rest_points);
  r.U32s(kTriangles, &d.triangles);
  r.U32s(kPointTriangleOffsets, &d.point_triangle_offsets);
  r.U32s(kPointTriangles, &d.point_triangles);
  {
    std::vector<uint32_t> a;
    r.U32s(kActiveRanges, &a);
    d.active = {a[0], a[1], a[2]};
  }
  r.U32s(kVertexPoints, &d.vertex_points);
  r.U32s(kVertexIndices, &d.vertex_indices);
  r.Float2s(kVertexUvs, &d.vertex_uvs);
  {
    std::vector<uint32_t> l;
    r.U32s(kLayers, &l);
    for (size_t i = 0; i < 3; ++i)
      if (l[i] > 1)
        return r.Fail(r.Of(kLayers), "layer " + std::to_string(i) + " is " +
                                         std::to_string(l[i]) + "; expected 0 or 1");
    d.layers = {l[0] != 0, l[1] != 0, l[2] != 0};
  }
  r.F32s(kPointThickness, &d.point_thickness);
  r.F32s(kRestTriangleAreas, &d.rest_triangle_areas);
  {
    std::vector<float> m;
    r.F32s(kMinAreaRatio, &m);
    d.min_area_ratio = m[0];
  }
  if (!r.Strings(kMuscleNames, &d.muscle_names)) return false;
  {
    std::vector<uint32_t> m;
    r.U32s(kMuscleCount, &m);
    d.muscles.muscle_count = m[0];
  }
  r.U32s(kMuscleOffsets, &d.muscles.offsets);
  {
    const InSection& s = r.Of(kMuscleEntries);
    d.muscles.entries.resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 16 * i;
      d.muscles.entries[size_t(i)] = {LoadU32(p), {LoadF32(p + 4), LoadF32(p + 8), LoadF32(p + 12)}};
    }
  }
  {
    // The table's lengths must add up to each array section's count before any is sliced.
    const InSection& t = r.Of(kMuscleWrinkleTable);
    const uint32_t ids[kMwArrays] = {kMwPoints,     kMwPhase,          kMwAttenuation,
                                     kMwProfile,    kMwEdgeOffsets,    kMwEdgeNeighbors,
                                     kMwEdgeRestLengths, kMwEdgeWeights};
    uint64_t totals[kMwArrays] = {};
    for (uint64_t m = 0; m < t.count; ++m)
      for (uint32_t a = 0; a < kMwArrays; ++a)
        totals[a] += LoadU32(t.data + kMwRecordBytes * m + 16 + 4 * a);  // < 2^32 * 2^32
    for (uint32_t a = 0; a < kMwArrays; ++a)
      if (totals[a] != r.Of(ids[a]).count)
        return r.Fail(r.Of(ids[a]), std::to_string(r.Of(ids[a]).count) +
                                        " elements; the muscle_wrinkle_table's lengths add up "
                                        "to " + std::to_string(totals[a]));
    uint64_t first[kMwArrays] = {};
    d.muscle_wrinkles.resize(size_t(t.count));
    for (uint64_t m = 0; m < t.count; ++m) {
      const uint8_t* p = t.data + kMwRecordBytes * m;
      RigMuscleWrinkles& w = d.muscle_wrinkles[size_t(m)];
      w.muscle = LoadU32(p);
      w.half_cycle = LoadF32(p + 4);
      w.furrow_depth = LoadF32(p + 8);
      w.shape = LoadF32(p + 12);
      std::vector<uint32_t>* u32s[] = {&w.points, nullptr, nullptr, nullptr,
                                       &w.edge_offsets, &w.edge_neighbors, nullptr, nullptr};
      std::vector<float>* f32s[] = {nullptr, &w.phase, &w.attenuation, &w.profile,
                                    nullptr, nullptr, &w.edge_rest_lengths, &w.edge_weights};
      for (uint32_t a = 0; a < kMwArrays; ++a) {
        const uint64_t n = LoadU32(p + 16 + 4 * a);
        if (u32s[a]) r.U32s(r.Of(ids[a]), first[a], n, u32s[a]);
        else r.F32s(r.Of(ids[a]), first[a], n, f32s[a]);
        first[a] += n;
      }
    }
  }
  RigCurveWrinkles& c = d.curve_wrinkles;
  if (!r.Strings(kCwNames, &c.names)) return false;
  {
    const InSection& s = r.Of(kCwParams);
    c.wrinkles.resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 24 * i;
      const uint32_t profile = LoadU32(p), modulation = LoadU32(p + 4);
      if (profile > uint32_t(CurveWrinkleProfile::kYangZhangExact) ||
          modulation > uint32_t(CurveWrinkleModulation::kArea))
        return r.Fail(s, "wrinkle " + std::to_string(i) + " has profile " +
                             std::to_string(profile) + " and modulation " +
                             std::to_string(modulation) + "; expected 0..2 and 0..1");
      c.wrinkles[size_t(i)] = {CurveWrinkleProfile(profile), CurveWrinkleModulation(modulation),
                               LoadF32(p + 8), LoadF32(p + 12), LoadF32(p + 16), LoadF32(p + 20)};
    }
  }
  r.U32s(kCwPoints, &c.points);
  r.U32s(kCwOffsets, &c.offsets);
  {
    const InSection& s = r.Of(kCwEntries);
    c.entries.resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 16 * i;
      c.entries[size_t(i)] = {LoadU32(p), LoadF32(p + 4), LoadF32(p + 8), LoadU32(p + 12)};
    }
  }
  {
    const InSection& s = r.Of(kCwProbes);
    c.probes.resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 48 * i;
      ShrinkageProbe& q = c.probes[size_t(i)];
      q.point = LoadU32(p);
      q.side_count = LoadU32(p + 4);
      for (int k = 0; k < 2; ++k) {
        const uint8_t* e = p + 8 + 20 * k;
        q.sides[k] = {LoadU32(e), LoadU32(e + 4), LoadF32(e + 8), LoadF32(e + 12), LoadF32(e + 16)};
      }
    }
  }
  {
    std::vector<float> j;
    r.F32s(kJawParams, &j);
    d.jaw.pivot = {j[0], j[1], j[2]};
    d.jaw.axis = {j[3], j[4], j[5]};
    d.jaw.range = j[6];
    d.jaw.translation = {j[7], j[8], j[9]};
    r.U32s(kJawPoints, &d.jaw.points);
    r.F32s(kJawWeights, &d.jaw.weights);
  }
  {  // 1.1's tension regions: all five sections or none (Rig::Build checks the rest)
    const uint32_t ids[] = {kTensionNames, kTensionReferences, kTensionOffsets, kTensionPoints,
                            kTensionWeights};
    int present = 0;
    for (uint32_t id : ids) present += r.Of(id).data != nullptr;
    if (present != 0 && present != 5)
      return fail("sections 'tension_region_*' (ids 35-39)",
                  "the tension regions need all five sections (ids 35-39); " +
                      std::to_string(present) + " are present");
    if (present == 5) {
      RigTensionRegions& g = d.tension_regions;
      if (!r.Strings(kTensionNames, &g.names)) return false;
      r.F32s(kTensionReferences, &g.references);
      r.U32s(kTensionOffsets, &g.offsets);
      r.U32s(kTensionPoints, &g.points);
      r.F32s(kTensionWeights, &g.weights);
      const InSection& s = r.Of(kTensionOffsets);
      if (g.references.size() != g.names.size() || g.offsets.size() != g.names.size() + 1 ||
          g.weights.size() != g.points.size() || g.offsets.back() != g.points.size())
        return r.Fail(s, std::to_string(g.names.size()) + " regions need as many references, " +
                             "one more offset and as many weights as points, the last offset "
                             "equal to the point count; got " +
                             std::to_string(g.references.size()) + " references, " +
                             std::to_string(g.offsets.size()) + " offsets, " +
                             std::to_string(g.points.size()) + " points, " +
                             std::to_string(g.weights.size()) + " weights");
    }
  }
  RigBinaryInfo file_info;
  {
    std::vector<std::string> units;
    if (!r.Strings(kInfoUnits, &units)) return false;
    if (!units.empty()) file_info.units = units[0];
    if (r.Of(kInfoSourceVertexCount).data) {
      std::vector<uint32_t> n;
      r.U32s(kInfoSourceVertexCount, &n);
      file_info.source_vertex_count = n[0];
    }
  }
  *out = std::move(d);
  if (info) *info = std::move(file_info);
  return true;
}

bool ReadRigBinary(span<const uint8_t> bytes, Rig* out, RigBinaryInfo* info, std::string* error) {
  RigData data;
  if (!ReadRigBinaryData(bytes, &data, info, error)) return false;
  if (!Rig::Build(std::move(data), out)) {
    if (error)
      *error = "Rig::Build: the tables fail the rig's check (an index out of range, a malformed "
               "CSR table, inconsistent sizes or active ranges)";
    return false;
  }
  return true;
}

bool ReadRigBinaryFile(const std::string& path, std::string* out, std::string* error,
                       size_t max_bytes) {
  std::string local_error;
  if (!error) error = &local_error;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    *error = "cannot open: no such file or not readable";
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    *error = "is not a regular file (expected a compiled rig)";
    return false;
  }
  if (uint64_t(st.st_size) > max_bytes) {
    *error = "is larger than the " + std::to_string(max_bytes >> 20) +
             " MiB limit for a compiled rig (" + std::to_string(st.st_size) + " bytes)";
    return false;
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    *error = "cannot open";
    return false;
  }
  out->assign(size_t(st.st_size), '\0');
  const size_t got = out->empty() ? 0 : std::fread(out->data(), 1, out->size(), f);
  const bool more = std::fgetc(f) != EOF;  // the file grew since stat
  const bool bad = std::ferror(f) != 0;
  std::fclose(f);
  if (bad || got != out->size() || more) {
    *error = "read error (the file changed while it was read)";
    return false;
  }
  return true;
}

bool LoadRigBinaryFile(const std::string& path, Rig* out, RigBinaryInfo* info,
                       std::string* error) {
  std::string bytes, why;
  if (!ReadRigBinaryFile(path, &bytes, &why) ||
      !ReadRigBinary(span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()),
                                         bytes.size()),
                     out, info, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return true;
}

}  // namespace mimetic
