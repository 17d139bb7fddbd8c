// io/golden_file.h: playback goldens (tests/golden/README.md, docs/expressions.md "Goldens"):
// a rig's output positions and normals at a few fixed times of a clip, in a small binary file,
// and the comparison the golden test runs against them.
//
// The file (little-endian; every field 4 bytes unless said):
//   offset 0   char[8]   magic "MMGOLDEN"
//          8   uint32    version (1)
//         12   uint32    vertex_count V: the rig's output vertices (Rig::vertex_count())
//         16   uint32    sample_count S: how many of them the file holds (S <= V, S >= 1)
//         20   uint32    frame_count F (>= 1)
//         24   float32   diagonal: the rest mesh's bounding-box diagonal, mesh units
//         28   uint32    indices[S]: the sampled vertices, strictly increasing, < V
//   then per frame f:   float32 time (seconds), float32 positions[3 S], float32 normals[3 S]
// The size is exactly 28 + 4 S + F (4 + 24 S) bytes; anything else is refused.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/span.h"
#include "expressions/runtime/clip.h"
#include "rig/runtime/rig.h"

namespace mimetic {

inline constexpr uint32_t kGoldenVersion = 1;
// The writer samples every k-th output vertex, k = ceil(V / kGoldenMaxSamples), so that a frame
// is at most 96 KiB (the full 100k-vertex head would be 2.4 MB a frame in float32).
inline constexpr uint32_t kGoldenMaxSamples = 4096;

struct GoldenFrame {
  float time = 0.f;              // seconds, as given to ClipSampleJob
  std::vector<float> positions;  // 3 per sample, mesh units
  std::vector<float> normals;    // 3 per sample, unit length
};

struct Golden {
  uint32_t vertex_count = 0;
  float diagonal = 0.f;
  std::vector<uint32_t> indices;  // the sampled vertices
  std::vector<GoldenFrame> frames;
};

// The vertices a golden of a rig with `vertex_count` output vertices samples: 0, k, 2k, ...
std::vector<uint32_t> GoldenSampleIndices(uint32_t vertex_count);

// The rig's full output (ClipSampleJob at `time`, then EvaluateJob with every skin layer the
// rig has): positions and normals, 3 floats per vertex. False when a job does not validate.
bool EvaluateClipFrame(const Rig& rig, const CompiledClip& clip, float time,
                       std::vector<float>* positions, std::vector<float>* normals);

// A golden of `rig` playing `clip` at `times` (the sampled vertices of every frame). False
// (with a message) when a job does not validate.
bool MakeGolden(const Rig& rig, const CompiledClip& clip, const std::vector<float>& times,
                Golden* out, Diagnostics* diag);

// The bytes of the file (layout above) and its reader: magic, version, sizes (exactly the
// size the header asks for, so a truncated file names how many bytes are missing), indices in
// range and increasing, finite numbers. Messages name `where` (the file).
std::string GoldenToBytes(const Golden& golden);
bool ParseGolden(const std::string& bytes, const std::string& where, Golden* out,
                 Diagnostics* diag);
bool LoadGolden(const std::string& path, Golden* out, Diagnostics* diag);
// Atomic (temp file + rename).
bool SaveGolden(const std::string& path, const Golden& golden, Diagnostics* diag);

// The comparison of one frame: a golden's frame against a rig's full output.
struct GoldenTolerance {
  double position = 1e-5;  // times the golden's diagonal: the largest position distance
  double normal = 1e-4;    // the largest distance between unit normals
};
struct GoldenMismatch {
  bool ok = true;
  std::string what;        // "position" or "normal" of the worst vertex; "" when ok
  uint32_t vertex = 0;     // its output index
  float3 expected{}, got{};
  double distance = 0;     // |expected - got|
  double limit = 0;        // the tolerance it broke, in the same units
  std::string message;     // "frame 2 (t = 0.5 s): vertex 1234 position: expected (..), got
                           // (..), distance 3e-4 > 2.5e-6"; "" when ok
};
// Compares frame `frame` of `golden` with `positions` / `normals` (3 floats per output vertex,
// Rig::vertex_count() vertices: a different count is a mismatch too). Reports the worst
// position over the limit if any, else the worst normal.
GoldenMismatch CompareGoldenFrame(const Golden& golden, size_t frame,
                                  const std::vector<float>& positions,
                                  const std::vector<float>& normals,
                                  const GoldenTolerance& tolerance = {});

}  // namespace mimetic
