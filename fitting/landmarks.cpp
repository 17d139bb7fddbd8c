// fitting/landmarks.cpp: the iBUG-68 landmark scheme (names, mirror pairs) and landmarks on a
// mesh. The landmark file format is io/landmarks_file.cpp.
#include "fitting/landmarks.h"

#include <string>

namespace mimetic {
namespace {

const char* const kNames[kIbug68Count] = {
    "jaw 0 (right, level with the eyes)", "jaw 1", "jaw 2", "jaw 3", "jaw 4 (right jaw angle)",
    "jaw 5", "jaw 6", "jaw 7", "jaw 8 (chin, menton)", "jaw 9", "jaw 10", "jaw 11",
    "jaw 12 (left jaw angle)", "jaw 13", "jaw 14", "jaw 15", "jaw 16 (left, level with the eyes)",
    "right brow outer end", "right brow 18", "right brow 19 (top)", "right brow 20",
    "right brow inner end", "left brow inner end", "left brow 23", "left brow 24 (top)",
    "left brow 25", "left brow outer end", "nose bridge top (nasion)", "nose bridge 28",
    "nose bridge 29", "nose tip (pronasale)", "right nostril outer (ala)", "right nostril 32",
    "nose base centre (subnasale)", "left nostril 34", "left nostril outer (ala)",
    "right eye outer corner", "right eye upper lid outer", "right eye upper lid inner",
    "right eye inner corner", "right eye lower lid inner", "right eye lower lid outer",
    "left eye inner corner", "left eye upper lid inner", "left eye upper lid outer",
    "left eye outer corner", "left eye lower lid outer", "left eye lower lid inner",
    "right mouth corner (outer lip)", "upper lip outer 49", "upper lip outer 50 (right peak)",
    "upper lip top centre", "upper lip outer 52 (left peak)", "upper lip outer 53",
    "left mouth corner (outer lip)", "lower lip outer 55", "lower lip outer 56",
    "lower lip bottom centre", "lower lip outer 58", "lower lip outer 59",
    "right mouth corner (inner lip)", "upper lip inner 61", "upper lip inner centre",
    "upper lip inner 63", "left mouth corner (inner lip)", "lower lip inner 65",
    "lower lip inner centre", "lower lip inner 67"};

// Left/right pairs of the iBUG-68 scheme (the subject's right first); midline points pair with
// themselves.
constexpr int kMirrorPairs[][2] = {
    {0, 16},  {1, 15},  {2, 14},  {3, 13},  {4, 12},  {5, 11},  {6, 10},  {7, 9},
    {17, 26}, {18, 25}, {19, 24}, {20, 23}, {21, 22}, {31, 35}, {32, 34}, {36, 45},
    {37, 44}, {38, 43}, {39, 42}, {40, 47}, {41, 46}, {48, 54}, {49, 53}, {50, 52},
    {55, 59}, {56, 58}, {60, 64}, {61, 63}, {65, 67}};

}  // namespace

const char* Ibug68Name(int index) {
  return index >= 0 && index < kIbug68Count ? kNames[index] : "";
}

int IbugMirrorLandmark(int index) {
  if (index < 0 || index >= kIbug68Count) return -1;
  for (const auto& p : kMirrorPairs) {
    if (p[0] == index) return p[1];
    if (p[1] == index) return p[0];
  }
  return index;  // on the midline
}

bool ResolveLandmarkPoints(const MeshData& mesh, Landmarks* lm, Diagnostics* diag) {
  Diagnostics local;
  Diagnostics& d = diag ? *diag : local;
  if (!lm) return false;
  const size_t before = d.ErrorCount();
  if (lm->vertex_indices.empty()) {
    if (lm->points.size() != static_cast<size_t>(kIbug68Count))
      d.Error("landmarks", "no vertex indices and " + std::to_string(lm->points.size()) +
                               " points; expected 68 points");
    return d.ErrorCount() == before;
  }
  const int64_t nv = static_cast<int64_t>(mesh.positions.size());
  std::vector<float3> pts = lm->points;
  pts.resize(lm->vertex_indices.size());
  for (size_t i = 0; i < lm->vertex_indices.size(); ++i) {
    const int64_t v = lm->vertex_indices[i];
    if (v < 0 && lm->points.empty()) {
      d.Error("landmarks: vertices[" + std::to_string(i) + "]",
              "is -1 (unknown) and no point is given; expected a vertex index");
    } else if (v >= nv) {
      d.Error("landmarks: vertices[" + std::to_string(i) + "]",
              "is " + std::to_string(v) + "; expected an index below the mesh's " +
                  std::to_string(nv) + " vertices");
    } else if (v >= 0 && lm->points.empty()) {
      pts[i] = mesh.positions[static_cast<size_t>(v)];
    }
  }
  if (d.ErrorCount() != before) return false;
  lm->points = std::move(pts);
  return true;
}

}  // namespace mimetic
