// rig/offline/landmarks.h: facial landmark files (docs/landmarks-format.md).
//
// 68 points in the Multi-PIE / iBUG order ("ibug68"), in mesh units (millimetres for the
// sample head). A file gives the points directly, or vertex indices into a mesh (then the
// points are read off that mesh), or both.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "rig/offline/mesh.h"

namespace mimetic {

inline constexpr int kIbug68Count = 68;

struct Landmarks {
  std::string scheme = "ibug68";
  std::vector<float3> points;            // 68, or empty when only vertex_indices are known
  std::vector<int64_t> vertex_indices;   // empty, or 68 (-1 where unknown)
};

// The name of iBUG landmark `index` (0..67), e.g. "jaw 8 (chin)", "right eye outer corner";
// "" out of range. iBUG "right" is the subject's right (-X when the head faces +Z).
const char* Ibug68Name(int index);

// Parses the JSON text of a landmark file. Records every problem with its JSON path and what
// was expected (wrong count, non-finite numbers, wrong types, unknown keys, unknown scheme or
// format, unsupported version); returns false when any error was recorded. `where` prefixes
// the messages (usually the file name).
bool ParseLandmarks(const std::string& json_text, const std::string& where, Landmarks* out,
                    Diagnostics* diag);

// Reads a landmark file (ParseLandmarks on its contents).
bool LoadLandmarks(const std::string& path, Landmarks* out, Diagnostics* diag);

// The JSON text of `landmarks` (points always when present; "vertices" when given).
std::string LandmarksToJson(const Landmarks& landmarks);

// Writes the file atomically. Refuses (false, with a message) landmarks that would not load
// back: wrong counts, non-finite points, neither points nor vertices.
bool SaveLandmarks(const std::string& path, const Landmarks& landmarks, Diagnostics* diag);

// Fills `points` from `vertex_indices` on `mesh` where the file gave only indices (and checks
// the indices against the mesh: every index in [0, #V), -1 not allowed here). Returns false
// and records why otherwise.
bool ResolveLandmarkPoints(const MeshData& mesh, Landmarks* landmarks, Diagnostics* diag);

}  // namespace mimetic
