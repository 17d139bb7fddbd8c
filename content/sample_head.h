// content/sample_head.h: the procedural sample head (no redistributable scan ships with
// Debian, so mimetic makes its own).
//
// The head is a smooth implicit solid built from anatomical parts (cranium, brow ridge, eye
// sockets with lids over the eyeballs, nose with alae and nostrils, cheekbones and cheek pads, nasolabial
// folds, lips with a mouth line, chin, mandible, ears, a neck stump). It is sampled the way a
// range scanner sees a head: one ray per (theta, phi) grid node from a centre inside the
// head, theta the azimuth about +Y (0 = +Z, the face), phi the polar angle from +Y. The grid
// rows and columns are spaced non-uniformly (denser over the face, forehead, eyes, mouth and
// nasolabial region) and triangulated; the crown is one pole vertex with a triangle fan and
// the mesh ends in an open boundary at the neck, level with the chin. The lips are cut apart
// along the mouth line (a slit with an inner lip roll behind each lip, another boundary), and
// each eye is open: an almond-shaped fissure between the canthi on the lid row, the upper and
// lower lid margins drawn apart on the lid surface, each with a short inner roll turning in
// toward the eyeball (one more boundary loop per eye).
//
// Units millimetres, +Y up, facing +Z, x = +subject's left. Deterministic: no RNG, no
// threads; the same options give the same bytes. Exactly mirror-symmetric in x.
#pragma once

#include <cmath>
#include <vector>

#include "core/math.h"
#include "geometry/mesh.h"

namespace mimetic {

// The mouth (x between the corners -26 and +26 mm, on the mouth line, y = -66 on the midline): the lips are
// cut apart by a slit (a real boundary in the topology) between the two corner vertices,
// kSampleHeadSlitWidth wide at rest, and each lip turns inward in an inner roll of
// kSampleHeadLipRollRows rows (MakeSampleHead).
constexpr float kSampleHeadMouthHalfWidth = 26.f;
constexpr float kSampleHeadSlitWidth = 0.1f;  // mm: above any weld tolerance (geometry/weld.h)
constexpr int kSampleHeadLipRollRows = 5;
// The slit sits this far (mm) behind the surface, inward along the dental arch's normal, so
// the lips' outer surfaces turn into it (MakeSampleHead).
constexpr float kSampleHeadSlitInset = 1.5f;
// The mouth line is not level: it rises toward the corners by kSampleHeadMouthLineRise mm per
// mm the lips lie behind their meeting point on the midline (z = kSampleHeadMouthZ), about
// 5 mm at the corners, so that it runs a little above the jaw's lip-line plane (docs/model.md
// §18: through the stomion and the hinge by the condyles, which on this head climbs about
// 0.3 mm per mm toward the hinge). A level line puts the upper lip by the corners inside the
// jaw's narrow blend band, where it is partly carried along and its triangles turn over at
// the full opening (tests/fitting/jaw_sample_head_test.cpp).
constexpr float kSampleHeadMouthLineRise = 0.4f;
constexpr float kSampleHeadMouthZ = 96.5f;
// The mouth line's height (mm) where the lips' surface is at depth z.
inline float SampleHeadMouthLineY(float z) {
  return -66.f + kSampleHeadMouthLineRise * (z < kSampleHeadMouthZ ? kSampleHeadMouthZ - z : 0.f);
}

// The eyes (the subject's left, +x; the right mirrors it). The palpebral fissure runs between
// the canthi (|x| = kSampleHeadInnerCanthusX .. kSampleHeadOuterCanthusX); the closed lid
// line is SampleHeadLidLineY, and the open lids' margins lie at SampleHeadUpperLidY above it
// and SampleHeadLowerLidY below it (an almond: sin-shaped, meeting at the canthi), on the lid
// surface (the skin over a sphere about the eyeball centre). Behind each margin an inner
// roll of kSampleHeadLidRollRows rows turns in toward the eyeball, ending kSampleHeadLidRollGap
// outside it (the lid edge's thickness). The eyeball (kSampleHeadEyeCentre, radius
// kSampleHeadEyeballRadius) is not part of the skin.
constexpr float kSampleHeadInnerCanthusX = 16.f, kSampleHeadOuterCanthusX = 45.f;
constexpr float kSampleHeadLidOpenUp = 6.5f, kSampleHeadLidOpenDown = 3.5f;  // mm, at mid-fissure
constexpr int kSampleHeadLidRollRows = 3;
constexpr float kSampleHeadLidRollGap = 0.2f;  // mm between the roll's end and the eyeball
constexpr float kSampleHeadEyeballRadius = 12.f;
constexpr float3 kSampleHeadEyeCentre{31.f, -0.5f, 66.f};
// Fraction of the way from the inner to the outer canthus at |x| = ax (clamped to [0, 1]).
inline float SampleHeadFissureT(float ax) {
  const float t = (ax - kSampleHeadInnerCanthusX) / (kSampleHeadOuterCanthusX - kSampleHeadInnerCanthusX);
  return t < 0 ? 0.f : (t > 1 ? 1.f : t);
}
inline float SampleHeadLidLineY(float ax) {
  const float t = SampleHeadFissureT(ax);
  return -1.5f + 1.5f * t - 2.f * std::sin(3.14159265358979f * t);
}
inline float SampleHeadUpperLidY(float ax) {
  return SampleHeadLidLineY(ax) + kSampleHeadLidOpenUp * std::sin(3.14159265358979f * SampleHeadFissureT(ax));
}
inline float SampleHeadLowerLidY(float ax) {
  return SampleHeadLidLineY(ax) - kSampleHeadLidOpenDown * std::sin(3.14159265358979f * SampleHeadFissureT(ax));
}

struct SampleHeadOptions {
  // Grid columns (azimuth steps around the head; the seam column is duplicated, so a row has
  // `columns + 1` vertices). Even; clamped to [16, 4096].
  int columns = 240;
  // Grid rows below the crown pole (each a ring of `columns + 1` vertices). Clamped to
  // [8, 4096]. Defaults give 1 + 140 * 241 = 33741 grid vertices (plus the mouth's).
  int rows = 140;
  // How much denser the face is sampled than the back of the head / the crown (>= 1).
  float face_density = 4.f;
  bool ears = true;  // low-relief ears (a range image cannot hold the gap behind an ear)
  bool normals = true;  // fill MeshData::normals (area-weighted, equal across the seam)
};

struct SampleHead {
  MeshData mesh;
  // 68 points in the Multi-PIE / iBUG order (docs/landmarks-format.md), on the mesh surface.
  std::vector<float3> landmarks;
  // The grid row (1..rows) that carries the mouth line: vertex 1 + (mouth_row - 1) *
  // (columns + 1) + j is column j's point on it (the upper lip's side of the slit between
  // the corners). Vertices after 1 + rows * (columns + 1) are the lower lip's slit twins and
  // the inner lip rolls (2 * kSampleHeadLipRollRows + 1 per column between the corners).
  int mouth_row = 0;
  // The grid row that carries the lid margins: in the columns between each eye's canthi its
  // vertex is the upper lid's margin point; the lower lid's margin point (a twin) and the two
  // lid rolls (2 * kSampleHeadLidRollRows + 1 vertices per column between the canthi) follow
  // the mouth's extra vertices, the subject's right eye (x < 0) first.
  int lid_row = 0;
};

// Builds the head. UVs: u = 0.5 + theta / (2 pi) (the cylindrical projection of Bando 2001
// §3.2 / 2003 §6 with the seam at the back: the seam column appears twice, u = 0 and u = 1,
// same positions); v = phi_ref / phi_ref_max, a latitude that grows monotonically down every
// column, 0 at the crown as glTF's top row (a plain height t = y would fold under the chin
// and at the crown).
SampleHead MakeSampleHead(const SampleHeadOptions& options = {});

// The eyeballs, a separate rigid mesh (the file's second mesh, "eyes": the skin's rig neither
// reads nor moves it). Two spheres of kSampleHeadEyeballRadius about kSampleHeadEyeCentre and
// its mirror image, the subject's right (x < 0) first; each a latitude-longitude sphere about
// the z axis: its front pole (the cornea's centre, looking along +z), `rings - 1` rings of
// `segments` vertices (ring k at the polar angle pi k / rings from +z), its back pole; so
// 2 + (rings - 1) * segments vertices and 2 * (rings - 1) * segments triangles per eye,
// counter-clockwise seen from outside. Normals: the exact outward ones; no uvs. The right eye
// is the left one's exact mirror image. rings clamped to [3, 256], segments to [3, 1024].
MeshData MakeSampleHeadEyes(int rings = 24, int segments = 48);

// The colour an eyeball is drawn with at a point of outward unit normal `n` (an eye looking
// along +z): a dark pupil within 12 degrees of +z, a blue-grey iris within 30, white sclera
// elsewhere. `mimetic render` and the viewer colour a mesh named "eyes" by it.
inline float3 SampleHeadEyeColor(float3 n) {
  return n.z > 0.978f ? float3{0.06f, 0.05f, 0.05f}
         : n.z > 0.866f ? float3{0.30f, 0.42f, 0.52f}
                        : float3{0.93f, 0.91f, 0.88f};
}

}  // namespace mimetic
