// rig/runtime/rig_binary.cpp: the .mrig writer and reader (docs/mrig-format.md).
#include "rig/runtime/rig_binary.h"

#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include "core/binary_sections.h"

namespace mimetic {
namespace {

using binary::InSection;
using binary::LoadF32;
using binary::LoadU32;
using binary::Payload;
using binary::SectionDesc;


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
  // 1.2: fine-scale amplitude probes (optional; absent = none).
  kFineScaleParams = 40,
  kFineScaleProbes = 41,
  // 2.1: the eyeballs the lids slide on (optional; absent = none).
  kEyeCenters = 42,
  kEyePoints = 43,
  kEyeIndices = 44,
  kEyeRadii = 45,
  kEyeWeights = 46,
  // 2.2: the muscle wrinkles' activation gates (optional; absent = no gate).
  kMwGates = 47,
  kInfoUnits = 64,
  kInfoSourceVertexCount = 65,
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
    {kFineScaleParams, "fine_scale_params", 4, 1, false},
    {kFineScaleProbes, "fine_scale_probes", 48, 0, false},
    {kEyeCenters, "eye_centers", 4, 0, false},
    {kEyePoints, "eye_points", 4, 0, false},
    {kEyeIndices, "eye_indices", 4, 0, false},
    {kEyeRadii, "eye_radii", 4, 0, false},
    {kEyeWeights, "eye_weights", 4, 0, false},
    {kMwGates, "muscle_wrinkle_gates", 4, 0, false},
    {kInfoUnits, "info_units", 0, 1, false},
    {kInfoSourceVertexCount, "info_source_vertex_count", 4, 1, false},
};

constexpr binary::Format kFormat = {
    {kRigBinaryTag[0], kRigBinaryTag[1], kRigBinaryTag[2], kRigBinaryTag[3]},
    kRigBinaryMajor,
    kRigBinaryMinor,
    ".mrig",
    "compiled rig",
    "rebuild the rig with this version's `mimetic build`",
    kSections,
    std::size(kSections),
    2};  // 2.0: the four-lane checksum

class SectionWriter : public binary::SectionWriter {
 public:
  SectionWriter() : binary::SectionWriter(kFormat) {}
  void Float3s(uint32_t id, const std::vector<float3>& v) {
    Payload p(&Begin(id, v.size()));
    for (const float3& x : v) p.F32(x.x), p.F32(x.y), p.F32(x.z);
  }
  void Float2s(uint32_t id, const std::vector<float2>& v) {
    Payload p(&Begin(id, v.size()));
    for (const float2& x : v) p.F32(x.x), p.F32(x.y);
  }
};

class Reader : public binary::SectionReader {
 public:
  Reader(const std::vector<InSection>& known, std::string* error)
      : binary::SectionReader(kFormat, known, error) {}
  using binary::SectionReader::F32s;
  using binary::SectionReader::U32s;
  void Float3s(uint32_t id, std::vector<float3>* out) const {
    const InSection& s = Of(id);
    static_assert(sizeof(float3) == 12, "float3 is three packed floats");
    if (binary::CopyIfNative(s.data, s.count, out)) return;
    out->resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 12 * i;
      (*out)[size_t(i)] = {LoadF32(p), LoadF32(p + 4), LoadF32(p + 8)};
    }
  }
  void Float2s(uint32_t id, std::vector<float2>* out) const {
    const InSection& s = Of(id);
    static_assert(sizeof(float2) == 8, "float2 is two packed floats");
    if (binary::CopyIfNative(s.data, s.count, out)) return;
    out->resize(size_t(s.count));
    for (uint64_t i = 0; i < s.count; ++i) {
      const uint8_t* p = s.data + 8 * i;
      (*out)[size_t(i)] = {LoadF32(p), LoadF32(p + 4)};
    }
  }
};

// Shrinkage probes (curve wrinkles, fine-scale): 48 bytes each, point, side count, then two
// sides of v2, v3, beta, rest_length2, rest_length3.
void WriteProbes(SectionWriter* w, uint32_t id, const std::vector<ShrinkageProbe>& probes) {
  Payload p(&w->Begin(id, probes.size()));
  for (const ShrinkageProbe& q : probes) {
    p.U32(q.point), p.U32(q.side_count);
    for (const ShrinkageSide& s : q.sides)
      p.U32(s.v2), p.U32(s.v3), p.F32(s.beta), p.F32(s.rest_length2), p.F32(s.rest_length3);
  }
}
void ReadProbes(const InSection& s, std::vector<ShrinkageProbe>* out) {
  out->resize(size_t(s.count));
  for (uint64_t i = 0; i < s.count; ++i) {
    const uint8_t* p = s.data + 48 * i;
    ShrinkageProbe& q = (*out)[size_t(i)];
    q.point = LoadU32(p);
    q.side_count = LoadU32(p + 4);
    for (int k = 0; k < 2; ++k) {
      const uint8_t* e = p + 8 + 20 * k;
      q.sides[k] = {LoadU32(e), LoadU32(e + 4), LoadF32(e + 8), LoadF32(e + 12), LoadF32(e + 16)};
    }
  }
}

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
  return binary::Checksum(file, binary::ChecksumLanes(kFormat, file));
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
  WriteProbes(&w, kCwProbes, c.probes);
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
  if (!d.fine_scale.empty()) {
    w.F32s(kFineScaleParams, {d.fine_scale.rest_amplitude});
    WriteProbes(&w, kFineScaleProbes, d.fine_scale.probes);
  }
  if (!d.eyes.empty()) {
    const RigEyes& e = d.eyes;
    std::vector<float> centers;
    for (const float3& c : e.centers) centers.insert(centers.end(), {c.x, c.y, c.z});
    w.F32s(kEyeCenters, centers);
    w.U32s(kEyePoints, e.points);
    w.U32s(kEyeIndices, e.eyes);
    w.F32s(kEyeRadii, e.radii);
    w.F32s(kEyeWeights, e.weights);
  }
  {  // 2.2's gates: written only when some table has one (a 2.1 reader then reads the rest)
    std::vector<float> gates;
    bool any = false;
    for (const RigMuscleWrinkles& m : d.muscle_wrinkles) gates.push_back(m.gate), any |= m.gate != 0.f;
    if (any) w.F32s(kMwGates, gates);
  }
  if (info) {
    w.Strings(kInfoUnits, {info->units});
    w.U32s(kInfoSourceVertexCount, {info->source_vertex_count});
  }

  return w.Finish();
}

namespace {

// ReadRigBinaryData, with the file's checksum already computed (LoadRigBinaryFile) or not.
bool ReadData(span<const uint8_t> bytes, const uint64_t* checksum, RigData* out,
              RigBinaryInfo* info, std::string* error);

// ReadRigBinary, the same way.
bool ReadRig(span<const uint8_t> bytes, const uint64_t* checksum, Rig* out, RigBinaryInfo* info,
             std::string* error) {
  RigData data;
  if (!ReadData(bytes, checksum, &data, info, error)) return false;
  if (!Rig::Build(std::move(data), out)) {
    if (error)
      *error = "Rig::Build: the tables fail the rig's check (an index out of range, a malformed "
               "CSR table, inconsistent sizes or active ranges)";
    return false;
  }
  return true;
}

}  // namespace

bool ReadRigBinaryData(span<const uint8_t> bytes, RigData* out, RigBinaryInfo* info,
                       std::string* error) {
  return ReadData(bytes, nullptr, out, info, error);
}

namespace {

bool ReadData(span<const uint8_t> bytes, const uint64_t* checksum, RigData* out,
              RigBinaryInfo* info, std::string* error) {
  std::string local_error;
  if (!error) error = &local_error;
  std::vector<InSection> known;
  if (!binary::ReadSections(bytes, kFormat, &known, error, checksum)) return false;
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
  ReadProbes(r.Of(kCwProbes), &c.probes);
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
    std::string missing;  // "'NAME' (id N)" of each absent one
    for (uint32_t id : ids) {
      if (r.Of(id).data != nullptr) {
        ++present;
        continue;
      }
      for (const SectionDesc& desc : kSections)
        if (desc.id == id)
          missing += std::string(missing.empty() ? "" : ", ") + "'" + desc.name + "' (id " +
                     std::to_string(id) + ")";
    }
    if (present != 0 && present != 5) {
      *error = "sections 'tension_region_*' (ids 35-39): the tension regions need all five "
               "sections; " + std::to_string(present) + " are present, missing " + missing;
      return false;
    }
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
  {  // 1.2's fine-scale probes: both sections or none (Rig::Build checks the rest)
    const bool params = r.Of(kFineScaleParams).data != nullptr;
    const bool probes = r.Of(kFineScaleProbes).data != nullptr;
    if (params != probes) {
      *error = std::string("sections 'fine_scale_*' (ids 40-41): the fine-scale amplitudes "
                           "need both sections; one is present, missing ") +
               (params ? "'fine_scale_probes' (id 41)" : "'fine_scale_params' (id 40)");
      return false;
    }
    if (params) {
      std::vector<float> v;
      r.F32s(kFineScaleParams, &v);
      d.fine_scale.rest_amplitude = v[0];
      ReadProbes(r.Of(kFineScaleProbes), &d.fine_scale.probes);
    }
  }
  {  // 2.1's eyes: all five sections or none (Rig::Build checks the indices and values)
    const uint32_t ids[] = {kEyeCenters, kEyePoints, kEyeIndices, kEyeRadii, kEyeWeights};
    int present = 0;
    for (uint32_t id : ids) present += r.Of(id).data != nullptr;
    if (present != 0 && present != 5) {
      *error = "sections 'eye_*' (ids 42-46): the eyes need all five sections; " +
               std::to_string(present) + " are present";
      return false;
    }
    if (present == 5) {
      RigEyes& e = d.eyes;
      std::vector<float> centers;
      r.F32s(kEyeCenters, &centers);
      r.U32s(kEyePoints, &e.points);
      r.U32s(kEyeIndices, &e.eyes);
      r.F32s(kEyeRadii, &e.radii);
      r.F32s(kEyeWeights, &e.weights);
      const InSection& s = r.Of(kEyePoints);
      if (centers.size() % 3 != 0 || e.eyes.size() != e.points.size() ||
          e.radii.size() != e.points.size() || e.weights.size() != e.points.size())
        return r.Fail(s, std::to_string(e.points.size()) + " held points need as many eye "
                         "indices, radii and weights, and the centres three floats each; got " +
                         std::to_string(e.eyes.size()) + " indices, " +
                         std::to_string(e.radii.size()) + " radii, " +
                         std::to_string(e.weights.size()) + " weights, " +
                         std::to_string(centers.size()) + " centre floats");
      for (size_t i = 0; i + 2 < centers.size(); i += 3)
        e.centers.push_back({centers[i], centers[i + 1], centers[i + 2]});
    }
  }
  if (r.Of(kMwGates).data != nullptr) {  // 2.2's gates: one per muscle-wrinkle table
    std::vector<float> gates;
    r.F32s(kMwGates, &gates);
    if (gates.size() != d.muscle_wrinkles.size())
      return r.Fail(r.Of(kMwGates), std::to_string(gates.size()) + " gates for " +
                                        std::to_string(d.muscle_wrinkles.size()) +
                                        " muscle-wrinkle tables; expected one per table");
    for (size_t i = 0; i < gates.size(); ++i) d.muscle_wrinkles[i].gate = gates[i];
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

}  // namespace

bool ReadRigBinary(span<const uint8_t> bytes, Rig* out, RigBinaryInfo* info, std::string* error) {
  return ReadRig(bytes, nullptr, out, info, error);
}

bool ReadRigBinaryFile(const std::string& path, std::string* out, std::string* error,
                       size_t max_bytes) {
  std::string local_error;
  return binary::ReadFileBytes(path, kFormat.what, max_bytes, out, error ? error : &local_error);
}

bool LoadRigBinaryFile(const std::string& path, Rig* out, RigBinaryInfo* info,
                       std::string* error) {
  // Read in pieces, each checksummed while in cache (one pass over the file's memory fewer).
  std::unique_ptr<uint8_t[]> bytes;
  size_t size = 0;
  uint64_t checksum = 0;
  std::string why;
  if (!binary::ReadFileBuffer(path, kFormat, kMaxRigBinaryFileBytes, &bytes, &size, &checksum,
                              &why) ||
      !ReadRig(span<const uint8_t>(bytes.get(), size), &checksum, out, info, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return true;
}

}  // namespace mimetic
