// fitting/landmarks.h: facial landmarks (docs/landmarks-format.md); files: io/landmarks_file.h.
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
#include "geometry/mesh.h"

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

// The iBUG landmark that mirrors `index` across the face's midline (0 <-> 16, 36 <-> 45, ...;
// midline points such as 8, 27..30, 33, 51, 57, 62, 66 map to themselves). -1 when out of range.
int IbugMirrorLandmark(int index);

// Fills `points` from `vertex_indices` on `mesh` where the file gave only indices (and checks
// the indices against the mesh: every index in [0, #V), -1 not allowed here). Returns false
// and records why otherwise.
bool ResolveLandmarkPoints(const MeshData& mesh, Landmarks* landmarks, Diagnostics* diag);

}  // namespace mimetic
