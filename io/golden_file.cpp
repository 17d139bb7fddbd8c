// io/golden_file.cpp: playback goldens (io/golden_file.h).
#include "io/golden_file.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "core/file_util.h"
#include "expressions/runtime/clip_sample_job.h"
#include "rig/runtime/evaluate_job.h"

namespace mimetic {
namespace {

constexpr char kMagic[8] = {'M', 'M', 'G', 'O', 'L', 'D', 'E', 'N'};
constexpr size_t kHeaderBytes = 28;

// Little-endian field writers and readers (the format is little-endian on every host).
void PutU32(std::string* s, uint32_t v) {
  for (int i = 0; i < 4; ++i) s->push_back(char((v >> (8 * i)) & 0xffu));
}
void PutF32(std::string* s, float f) {
  uint32_t v;
  std::memcpy(&v, &f, 4);
  PutU32(s, v);
}
uint32_t GetU32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t(uint8_t(s[at + size_t(i)])) << (8 * i);
  return v;
}
float GetF32(const std::string& s, size_t at) {
  const uint32_t v = GetU32(s, at);
  float f;
  std::memcpy(&f, &v, 4);
  return f;
}

std::string Vec(const float3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
  return buf;
}

}  // namespace

std::vector<uint32_t> GoldenSampleIndices(uint32_t vertex_count) {
  std::vector<uint32_t> out;
  if (vertex_count == 0) return out;
  const uint32_t k = (vertex_count + kGoldenMaxSamples - 1) / kGoldenMaxSamples;
  for (uint32_t v = 0; v < vertex_count; v += k) out.push_back(v);
  return out;
}

bool EvaluateClipFrame(const Rig& rig, const CompiledClip& clip, float time,
                       std::vector<float>* positions, std::vector<float>* normals) {
  std::vector<float> activations(rig.muscle_count(), 0.f);
  positions->assign(size_t(rig.vertex_count()) * 3, 0.f);
  normals->assign(size_t(rig.vertex_count()) * 3, 0.f);
  float jaw = 0.f;
  ClipSampleJob sample;
  sample.clip = &clip;
  sample.time = time;
  sample.out_activations = activations;
  sample.out_jaw = span<float>(&jaw, 1);
  if (!sample.Run()) return false;
  EvaluateContext context(rig);
  EvaluateJob evaluate;
  evaluate.rig = &rig;
  evaluate.context = &context;
  evaluate.activations = activations;
  evaluate.out_positions = *positions;
  evaluate.out_normals = *normals;
  evaluate.jaw = jaw;
  return evaluate.Run();
}

bool MakeGolden(const Rig& rig, const CompiledClip& clip, const std::vector<float>& times,
                Golden* out, Diagnostics* diag) {
  Golden g;
  g.vertex_count = rig.vertex_count();
  g.indices = GoldenSampleIndices(g.vertex_count);
  std::vector<float> positions, normals;
  for (size_t f = 0; f < times.size(); ++f) {
    if (!EvaluateClipFrame(rig, clip, times[f], &positions, &normals)) {
      diag->Error("golden", "evaluation failed at t = " + std::to_string(times[f]) +
                                " s (internal error: a job did not validate)");
      return false;
    }
    if (f == 0) {  // the diagonal of the rest mesh (the rig at activation 0)
      std::vector<float> rest_p, rest_n;
      std::vector<float> zeros(rig.muscle_count(), 0.f);
      rest_p.assign(positions.size(), 0.f);
      EvaluateContext context(rig);
      EvaluateJob job;
      job.rig = &rig;
      job.context = &context;
      job.activations = zeros;
      job.out_positions = rest_p;
      if (!job.Run()) return diag->Error("golden", "evaluation of the rest pose failed"), false;
      float3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
      for (size_t v = 0; v < rest_p.size() / 3; ++v) {
        lo = {std::fmin(lo.x, rest_p[3 * v]), std::fmin(lo.y, rest_p[3 * v + 1]),
              std::fmin(lo.z, rest_p[3 * v + 2])};
        hi = {std::fmax(hi.x, rest_p[3 * v]), std::fmax(hi.y, rest_p[3 * v + 1]),
              std::fmax(hi.z, rest_p[3 * v + 2])};
      }
      const double dx = double(hi.x) - lo.x, dy = double(hi.y) - lo.y, dz = double(hi.z) - lo.z;
      g.diagonal = float(std::sqrt(dx * dx + dy * dy + dz * dz));
    }
    GoldenFrame frame;
    frame.time = times[f];
    for (uint32_t v : g.indices)
      for (int c = 0; c < 3; ++c) {
        frame.positions.push_back(positions[3 * size_t(v) + size_t(c)]);
        frame.normals.push_back(normals[3 * size_t(v) + size_t(c)]);
      }
    g.frames.push_back(std::move(frame));
  }
  *out = std::move(g);
  return true;
}

std::string GoldenToBytes(const Golden& g) {
  std::string s(kMagic, 8);
  PutU32(&s, kGoldenVersion);
  PutU32(&s, g.vertex_count);
  PutU32(&s, uint32_t(g.indices.size()));
  PutU32(&s, uint32_t(g.frames.size()));
  PutF32(&s, g.diagonal);
  for (uint32_t i : g.indices) PutU32(&s, i);
  for (const GoldenFrame& f : g.frames) {
    PutF32(&s, f.time);
    for (float x : f.positions) PutF32(&s, x);
    for (float x : f.normals) PutF32(&s, x);
  }
  return s;
}

bool ParseGolden(const std::string& bytes, const std::string& where, Golden* out,
                 Diagnostics* diag) {
  if (bytes.size() < kHeaderBytes) {
    diag->Error(where, "is truncated: " + std::to_string(bytes.size()) +
                           " bytes, shorter than the 28-byte golden header (expected a "
                           "mimetic golden file, tests/golden/README.md)");
    return false;
  }
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) {
    diag->Error(where, "is not a mimetic golden file (expected the magic \"MMGOLDEN\" in its "
                       "first 8 bytes)");
    return false;
  }
  const uint32_t version = GetU32(bytes, 8);
  if (version != kGoldenVersion) {
    diag->Error(where, "golden version " + std::to_string(version) + ": this build reads "
                       "version " + std::to_string(kGoldenVersion));
    return false;
  }
  Golden g;
  g.vertex_count = GetU32(bytes, 12);
  const uint32_t samples = GetU32(bytes, 16), frames = GetU32(bytes, 20);
  g.diagonal = GetF32(bytes, 24);
  if (samples == 0 || samples > g.vertex_count || frames == 0) {
    diag->Error(where, "header: " + std::to_string(samples) + " samples of " +
                           std::to_string(g.vertex_count) + " vertices, " +
                           std::to_string(frames) + " frames; expected 1 <= samples <= "
                           "vertices and at least 1 frame");
    return false;
  }
  if (!(std::isfinite(g.diagonal) && g.diagonal > 0.f)) {
    diag->Error(where, "header: diagonal " + std::to_string(g.diagonal) +
                           "; expected a finite number > 0");
    return false;
  }
  const unsigned long long expected =
      kHeaderBytes + 4ull * samples + frames * (4ull + 24ull * samples);
  if (bytes.size() != expected) {
    diag->Error(where, std::string(bytes.size() < expected ? "is truncated" : "is too long") +
                           ": " + std::to_string(bytes.size()) + " bytes; expected " +
                           std::to_string(expected) + " for " + std::to_string(samples) +
                           " samples and " + std::to_string(frames) + " frames");
    return false;
  }
  size_t at = kHeaderBytes;
  for (uint32_t i = 0; i < samples; ++i, at += 4) {
    const uint32_t v = GetU32(bytes, at);
    if (v >= g.vertex_count || (i > 0 && v <= g.indices.back())) {
      diag->Error(where, "indices[" + std::to_string(i) + "] = " + std::to_string(v) +
                             ": expected strictly increasing vertex indices below " +
                             std::to_string(g.vertex_count));
      return false;
    }
    g.indices.push_back(v);
  }
  for (uint32_t f = 0; f < frames; ++f) {
    GoldenFrame frame;
    frame.time = GetF32(bytes, at);
    at += 4;
    frame.positions.resize(size_t(samples) * 3);
    frame.normals.resize(size_t(samples) * 3);
    for (float& x : frame.positions) x = GetF32(bytes, at), at += 4;
    for (float& x : frame.normals) x = GetF32(bytes, at), at += 4;
    bool finite = std::isfinite(frame.time);
    for (float x : frame.positions) finite = finite && std::isfinite(x);
    for (float x : frame.normals) finite = finite && std::isfinite(x);
    if (!finite) {
      diag->Error(where, "frame " + std::to_string(f) + ": a time, position or normal is not "
                         "finite");
      return false;
    }
    g.frames.push_back(std::move(frame));
  }
  *out = std::move(g);
  return true;
}

bool LoadGolden(const std::string& path, Golden* out, Diagnostics* diag) {
  std::string bytes;
  if (!ReadFile(path, &bytes, diag, 64 * kMiB, "golden file")) return false;
  return ParseGolden(bytes, path, out, diag);
}

bool SaveGolden(const std::string& path, const Golden& golden, Diagnostics* diag) {
  return WriteFileAtomic(path, GoldenToBytes(golden), diag);
}

GoldenMismatch CompareGoldenFrame(const Golden& golden, size_t frame,
                                  const std::vector<float>& positions,
                                  const std::vector<float>& normals,
                                  const GoldenTolerance& tolerance) {
  GoldenMismatch m;
  const std::string head = "frame " + std::to_string(frame) + (frame < golden.frames.size()
      ? " (t = " + std::to_string(golden.frames[frame].time) + " s)" : std::string()) + ": ";
  if (frame >= golden.frames.size() || positions.size() != size_t(golden.vertex_count) * 3 ||
      normals.size() != positions.size()) {
    m.ok = false;
    m.message = head + "the golden has " + std::to_string(golden.frames.size()) + " frames of " +
                std::to_string(golden.vertex_count) + " vertices; the rig gives " +
                std::to_string(positions.size() / 3) + " vertices";
    return m;
  }
  const GoldenFrame& g = golden.frames[frame];
  struct Worst { double d = -1; size_t s = 0; };
  Worst wp, wn;
  for (size_t s = 0; s < golden.indices.size(); ++s) {
    const size_t v = golden.indices[s];
    double dp = 0, dn = 0;
    for (int c = 0; c < 3; ++c) {
      const double ep = double(g.positions[3 * s + size_t(c)]) - positions[3 * v + size_t(c)];
      const double en = double(g.normals[3 * s + size_t(c)]) - normals[3 * v + size_t(c)];
      dp += ep * ep;
      dn += en * en;
    }
    dp = std::sqrt(dp), dn = std::sqrt(dn);
    if (!(dp <= wp.d)) wp = {std::isnan(dp) ? std::numeric_limits<double>::infinity() : dp, s};
    if (!(dn <= wn.d)) wn = {std::isnan(dn) ? std::numeric_limits<double>::infinity() : dn, s};
  }
  const double plimit = tolerance.position * double(golden.diagonal), nlimit = tolerance.normal;
  const bool pbad = wp.d > plimit, nbad = wn.d > nlimit;
  if (!pbad && !nbad) return m;
  m.ok = false;
  const bool pos = pbad;
  const Worst& w = pos ? wp : wn;
  const std::vector<float>& exp = pos ? g.positions : g.normals;
  const std::vector<float>& got = pos ? positions : normals;
  m.what = pos ? "position" : "normal";
  m.vertex = golden.indices[w.s];
  m.expected = {exp[3 * w.s], exp[3 * w.s + 1], exp[3 * w.s + 2]};
  m.got = {got[3 * size_t(m.vertex)], got[3 * size_t(m.vertex) + 1], got[3 * size_t(m.vertex) + 2]};
  m.distance = w.d;
  m.limit = pos ? plimit : nlimit;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g > %.3g", m.distance, m.limit);
  m.message = head + "worst vertex " + std::to_string(m.vertex) + " " + m.what + ": expected " +
              Vec(m.expected) + ", got " + Vec(m.got) + ", distance " + buf +
              (pos ? " (the limit: the tolerance times the diagonal)" : "");
  if (pos && nbad) {
    std::snprintf(buf, sizeof buf, "%.3g", wn.d);
    m.message += std::string("; the worst normal is off by ") + buf + " too";
  }
  return m;
}

}  // namespace mimetic
