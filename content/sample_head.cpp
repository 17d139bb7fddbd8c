// content/sample_head.cpp: the procedural sample head.
//
// Shape: a signed-distance-like field built from anatomical parts joined with smooth unions
// (polynomial smooth min). Sampling: a spherical range image (the Cyberware form of Bando
// 2003 §6, with polar rows so that the crown and the underside of the nose and chin are seen
// at a useful angle) taken from a centre inside the head; each grid node takes the outermost
// crossing of its ray, so the result is always a single-valued surface.
//
// Proportions (adult, neutral; y = 0 at the eye corners, so the eyes sit halfway between the
// crown at +115 and the menton at -114):
//   brows +18, nasion +5, subnasale -47 (brow to nose base = nose base to chin: the classic
//   facial thirds), stomion -66 (a third of the way from the nose base to the chin), menton
//   -114; head breadth 146, head length ~200, bizygomatic ~136, bigonial ~104, intercanthal
//   30, biocular 90, nose width (alae) 34, nose protrusion ~20 from subnasale, mouth width 52.
#include "content/sample_head.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "fitting/landmarks.h"
#include "geometry/closest_point.h"
#include "geometry/normals.h"

namespace mimetic {
namespace {

// ---------------------------------------------------------------------------------------
// Small double-precision vector helpers (the field is evaluated in double so that the mesh
// is the same on every build that rounds IEEE doubles the same way).
struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double Dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double Len(V3 a) { return std::sqrt(Dot(a, a)); }

constexpr double kPiD = 3.14159265358979323846;
double Rad(double deg) { return deg * kPiD / 180.0; }

double Clamp01(double v) { return v < 0 ? 0 : (v > 1 ? 1 : v); }
double SmoothStep(double e0, double e1, double x) {
  const double t = Clamp01((x - e0) / (e1 - e0));
  return t * t * (3 - 2 * t);
}
double Gauss(double x, double sigma) { return std::exp(-(x * x) / (sigma * sigma)); }

// Polynomial smooth minimum (blend radius k) and maximum.
double SMin(double a, double b, double k) {
  const double h = std::max(k - std::fabs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}
double SMax(double a, double b, double k) { return -SMin(-a, -b, k); }

// Ellipsoid distance estimate (exact on the surface, a bound nearby).
double Ellipsoid(V3 p, V3 r) {
  const V3 q{p.x / r.x, p.y / r.y, p.z / r.z};
  const V3 q2{p.x / (r.x * r.x), p.y / (r.y * r.y), p.z / (r.z * r.z)};
  const double k0 = Len(q), k1 = Len(q2);
  if (k1 < 1e-12) return -std::min({r.x, r.y, r.z});
  return k0 * (k0 - 1.0) / k1;
}
// Capsule with radius varying linearly from ra (at a) to rb (at b).
double Capsule(V3 p, V3 a, V3 b, double ra, double rb) {
  const V3 ab = b - a;
  const double t = Clamp01(Dot(p - a, ab) / Dot(ab, ab));
  return Len(p - (a + ab * t)) - (ra + (rb - ra) * t);
}
// 2D distance from (x, y) to the segment (ax, ay)-(bx, by).
double Seg2(double x, double y, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double t = Clamp01(((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy));
  return std::hypot(x - ax - t * dx, y - ay - t * dy);
}

// ---------------------------------------------------------------------------------------
// Anatomy. All parts are mirror-symmetric: paired parts are evaluated at |x|.
constexpr double kMenton = -114.0;
constexpr V3 kRayCentre{0.0, 0.0, 10.0};

// Eyes: eyeball centre, lid radius (the lids are skin over a sphere about the eyeball);
// canthi.
constexpr V3 kEye{kSampleHeadEyeCentre.x, kSampleHeadEyeCentre.y, kSampleHeadEyeCentre.z};
constexpr double kLidRadius = 13.2;
constexpr double kInnerCanthusX = kSampleHeadInnerCanthusX, kOuterCanthusX = kSampleHeadOuterCanthusX;
double FissureT(double ax) { return Clamp01((ax - kInnerCanthusX) / (kOuterCanthusX - kInnerCanthusX)); }
// Closed-lid line: y of the fissure as a function of x (slightly lower in the middle).
double LidLineY(double ax) {
  const double t = FissureT(ax);
  return -1.5 + 1.5 * t - 2.0 * std::sin(kPiD * t);
}
// The open lids' margins (SampleHeadUpperLidY / SampleHeadLowerLidY in double).
double UpperLidY(double ax) { return LidLineY(ax) + kSampleHeadLidOpenUp * std::sin(kPiD * FissureT(ax)); }
double LowerLidY(double ax) { return LidLineY(ax) - kSampleHeadLidOpenDown * std::sin(kPiD * FissureT(ax)); }
// Mouth: the lips follow the dental arch, a bend of radius kArch about a vertical axis.
constexpr double kArch = 46.0;
constexpr double kStomionY = -66.0, kLipFrontZ = 99.0, kMouthHalfWidth = kSampleHeadMouthHalfWidth;
V3 MouthSpace(V3 q) { return {q.x, q.y, q.z + q.x * q.x / (2 * kArch)}; }
// The mouth line: y = kStomionY where the lips meet on the midline (z = kSampleHeadMouthZ),
// rising as the lips curve back with the arch (SampleHeadMouthLineY).
double MouthLineY(double z) {
  return kStomionY + kSampleHeadMouthLineRise * std::max(0.0, kSampleHeadMouthZ - z);
}

double HeadField(V3 p, bool ears) {
  const V3 q{std::fabs(p.x), p.y, p.z};

  // Cranium (top at kCrown) and the neck stump.
  double d = Ellipsoid(p - V3{0, 27, -8}, {73, 88, 98});
  d = SMin(d, Ellipsoid(p - V3{0, 45, -18}, {72, 67, 88}), 10);  // parietal fullness
  // Forehead: a slightly flatter, fuller front of the skull.
  d = SMin(d, Ellipsoid(p - V3{0, 38, 38}, {60, 52, 52}), 12);
  d = SMin(d, Capsule(p, {0, -40, -22}, {0, -260, -32}, 52, 54), 28);

  // Midface (maxilla and zygomatic body) and the muzzle over the dental arch.
  d = SMin(d, Ellipsoid(p - V3{0, -18, 24}, {62, 48, 66}), 16);
  d = SMin(d, Ellipsoid(p - V3{0, -60, 56}, {37, 30, 38}), 14);
  // Mandible: ramus, body to the chin, chin.
  const V3 gonion{51, -80, 2};
  d = SMin(d, Capsule(q, {58, -28, -8}, gonion, 11, 11), 22);
  d = SMin(d, Capsule(q, gonion, {17, -104, 72}, 10, 9), 20);
  d = SMin(d, Ellipsoid(p - V3{0, -99, 80}, {18, 14, 14}), 16);
  // Cheekbones and malar fat pads (their inner edge makes the nasolabial fold).
  d = SMin(d, Ellipsoid(q - V3{47, -11, 53}, {17, 9, 16}), 16);
  d = SMin(d, Ellipsoid(q - V3{31, -30, 70}, {17, 15, 12}), 14);
  d = SMin(d, Ellipsoid(q - V3{41, -56, 42}, {17, 24, 24}), 18);  // buccal fullness

  // Brow ridge (two arcs meeting at the glabella).
  d = SMin(d, Ellipsoid(q - V3{20, 16, 83}, {24, 8, 11}), 12);

  // Eye sockets and the lids over the eyeballs (the fissure between them is cut in the
  // topology, MakeSampleHead: the grid's rows are drawn apart there).
  d = SMax(d, -Ellipsoid(q - V3{kEye.x, 0.0, 87}, {19, 11, 17}), 8);
  double lid = Len(q - kEye) - kLidRadius;
  {
    const double across = Clamp01((q.x - kInnerCanthusX + 1) / 3.0) *
                          Clamp01((kOuterCanthusX + 1 - q.x) / 3.0);
    const double front = SmoothStep(kEye.z, kEye.z + 6, q.z);
    lid += 0.9 * Gauss(q.y - LidLineY(q.x), 0.9) * across * front;              // lid line
    lid += 0.35 * Gauss(q.y - (UpperLidY(q.x) + 4.0), 1.4) * across * front;    // lid crease
  }
  d = SMin(d, lid, 3);

  // Nose: a wedge with sloping sides along the dorsum line (nasion to tip), a rounded tip,
  // alae and nostrils.
  double nose;
  {
    const V3 top{0, 4, 89}, tip{0, -33, 111};
    const double t = Clamp01((p.y - top.y) / (tip.y - top.y));
    const double ridge_z = top.z + (tip.z - top.z) * t;
    const double half_round = 2.5 + 3.0 * t;  // the dorsum widens toward the tip
    const double ax = std::sqrt(p.x * p.x + half_round * half_round) - half_round;
    nose = 0.8 * ax + 0.6 * (p.z - ridge_z);            // sides at ~37 deg to the face plane
    nose = SMax(nose, p.y - top.y - 4, 6);                // fades out above the nasion
    nose = SMax(nose, tip.y - 6 - p.y, 4);                // ends under the tip
    nose = SMax(nose, ridge_z - 24 - p.z, 4);             // rooted in the face
  }
  nose = SMin(nose, Ellipsoid(p - V3{0, -35, 107.5}, {7.0, 7.5, 8.0}), 5);
  nose = SMin(nose, Ellipsoid(q - V3{12.0, -40.5, 96.5}, {5.5, 5.5, 8.0}), 5);
  nose = SMax(nose, -Ellipsoid(q - V3{6.0, -46.5, 103}, {3.4, 2.4, 6.0}), 1.5);
  d = SMin(d, nose, 5);

  // Lips and mouth line (in the arch-bent frame, raised with the mouth line toward the
  // corners, so the lips keep their shape about the line).
  V3 m = MouthSpace(q);
  m.y -= MouthLineY(q.z) - kStomionY;
  d = SMin(d, Ellipsoid(m - V3{0, -60.5, kLipFrontZ - 7}, {kMouthHalfWidth + 4, 6, 9}), 4);
  d = SMin(d, Ellipsoid(m - V3{0, -72.0, kLipFrontZ - 9}, {kMouthHalfWidth + 2, 6.5, 10}), 4);
  // The mouth line: a shallow crease where the lips meet (the slit itself is cut in the
  // topology, MakeSampleHead; a deep narrow slot would alias between the grid rows).
  d = SMax(d, -Ellipsoid(m - V3{0, kStomionY, kLipFrontZ}, {kMouthHalfWidth + 1, 1.8, 2.5}), 0.8);

  // Grooves as small displacements along the outward field direction.
  if (q.z > 40) {
    // Philtrum.
    d += 0.7 * Gauss(q.x - 0.0, 3.0) * SmoothStep(-47, -50, q.y) * SmoothStep(-60, -57, q.y);
    // Mouth corners (modiolus).
    d += 0.8 * Gauss(std::hypot(q.x - kMouthHalfWidth - 0.5, q.y - MouthLineY(q.z)), 2.5);
    // Nasolabial folds: from beside the ala down past the mouth corner.
    d += 1.0 * Gauss(Seg2(q.x, q.y, 20, -39, 31, -72), 2.5) * SmoothStep(60, 75, q.z);
  }

  // Ears: low relief (helix rim, concha bowl), just behind the jaw.
  if (ears) {
    const V3 e = q - V3{70, -8, -8};
    double ear = Ellipsoid(e, {8, 30, 17});
    ear = SMax(ear, -Ellipsoid(e - V3{8, -4, 3}, {5, 12, 8}), 3);  // concha
    d = SMin(d, ear, 6);
  }
  return d;
}

// ---------------------------------------------------------------------------------------
// Ray casting.
V3 Direction(double theta, double phi) {
  return {std::sin(phi) * std::sin(theta), std::cos(phi), std::sin(phi) * std::cos(theta)};
}

// The ray origin slides down the vertical axis x = 0, z = 10 as phi grows: from the eye
// level for the upper head and face, to the mouth level for the jaw and neck, so that the
// underside of the jaw is seen from below its line instead of behind it. The descent starts
// lower at the front (the mouth and chin keep the eye-level view) than at the sides. For a
// fixed theta the origin never rises as phi grows, so the rays of one half-plane cannot
// cross and the grid cannot fold.
V3 RayOrigin(double theta, double phi) {
  const double side = SmoothStep(Rad(25), Rad(55), std::fabs(theta));
  const double lo = Rad(175) + (Rad(128) - Rad(175)) * side;
  const double hi = Rad(200) + (Rad(158) - Rad(200)) * side;
  return {kRayCentre.x, kRayCentre.y - 60.0 * SmoothStep(lo, hi, phi), kRayCentre.z};
}

// Outermost crossing of the ray from `origin` along `dir`: march inward from far outside.
double CastRay(V3 origin, V3 dir, bool ears) {
  double r_out = 330.0;
  double r = r_out;
  for (int i = 0; i < 400 && r > 0; ++i) {
    const double f = HeadField(origin + dir * r, ears);
    if (f < 0) {
      double lo = r, hi = r_out;  // lo inside, hi outside
      for (int k = 0; k < 24; ++k) {  // the bracket is < 1 mm: 24 halvings reach 1e-7 mm
        const double mid = 0.5 * (lo + hi);
        if (HeadField(origin + dir * mid, ears) < 0) lo = mid;
        else hi = mid;
      }
      return 0.5 * (lo + hi);
    }
    r_out = r;
    r -= std::max(0.6 * f, 0.15);
  }
  return 1.0;  // not reached for this field (every origin is inside the head)
}

V3 SurfacePoint(double theta, double phi, bool ears) {
  const V3 o = RayOrigin(theta, phi);
  const V3 dir = Direction(theta, phi);
  return o + dir * CastRay(o, dir, ears);
}

// The first surface point met going from `p` along `dir` (p outside the head).
V3 ProjectAlong(V3 p, V3 dir, bool ears) {
  double t_out = 0.0, t = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const double f = HeadField(p + dir * t, ears);
    if (f < 0) {
      double lo = t_out, hi = t;  // lo outside, hi inside
      for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (lo + hi);
        if (HeadField(p + dir * mid, ears) < 0) hi = mid;
        else lo = mid;
      }
      return p + dir * (0.5 * (lo + hi));
    }
    t_out = t;
    t += std::max(0.6 * f, 0.1);
  }
  return p;
}

// Polar angle at which the ray in azimuth `theta` meets the surface at height y_cut.
double PhiEnd(double theta, double y_cut, bool ears) {
  double lo = Rad(100), hi = Rad(179);
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (SurfacePoint(theta, mid, ears).y > y_cut) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Inverts the cumulative density of `density` over [a, b] at `count + 1` evenly spaced
// quantiles (first = a, last = b).
template <typename F>
std::vector<double> Quantiles(F density, double a, double b, int count) {
  const int K = 8192;
  std::vector<double> cdf(K + 1, 0.0);
  const double h = (b - a) / K;
  for (int k = 0; k < K; ++k)
    cdf[k + 1] = cdf[k] + 0.5 * h * (density(a + k * h) + density(a + (k + 1) * h));
  std::vector<double> out(count + 1);
  out[0] = a;
  out[count] = b;
  int k = 0;
  for (int i = 1; i < count; ++i) {
    const double target = cdf[K] * i / count;
    while (k < K - 1 && cdf[k + 1] < target) ++k;
    const double t = (target - cdf[k]) / std::max(cdf[k + 1] - cdf[k], 1e-300);
    out[i] = a + (k + t) * h;
  }
  return out;
}

V3 ToV3(float3 v) { return {v.x, v.y, v.z}; }
float3 ToF3(V3 v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

// ---------------------------------------------------------------------------------------
// Landmarks, in the iBUG 68 order, placed the way an annotator marks a frontal photograph:
// each is an (x, y) position on the face, projected onto the surface along -Z. The jaw
// contour (0-16) is a silhouette in a photograph; here it is projected from outside toward
// a point inside the lower head, so it lies on the jaw line. Subject's left (+x) points are
// given; the right side mirrors them.
struct LandmarkTarget {
  V3 from;  // start point, outside the head
  V3 dir;   // unit direction toward the surface
};
std::array<LandmarkTarget, 68> LandmarkTargets() {
  std::array<LandmarkTarget, 68> t{};
  auto front = [](double x, double y) { return LandmarkTarget{{x, y, 200}, {0, 0, -1}}; };
  // Jaw contour, left half 8..16: menton, along the mandible to the jaw angle and up in front
  // of the ear to eye level.
  const V3 inner{0, -25, 10};
  const std::array<V3, 9> jaw = {{{0, -125, 95},
                                  {19, -120, 85},
                                  {36, -112, 72},
                                  {50, -100, 55},
                                  {60, -85, 35},
                                  {68, -66, 25},
                                  {74, -46, 20},
                                  {78, -25, 16},
                                  {80, -4, 14}}};
  for (int i = 0; i < 9; ++i) {
    const V3 d = inner - jaw[i];
    t[8 + i] = {jaw[i], d * (1.0 / Len(d))};
  }
  // Left brow 22 (inner) .. 26 (outer), along the brow ridge.
  t[22] = front(11, 17);
  t[23] = front(20, 20.5);
  t[24] = front(30, 22);
  t[25] = front(40, 20.5);
  t[26] = front(49, 15);
  // Nose bridge 27 (nasion, level with the eye corners) .. 30 (tip).
  t[27] = front(0, 1.5);
  t[28] = front(0, -10.5);
  t[29] = front(0, -22.5);
  t[30] = {{0, -34.5, 200}, {0, 0, -1}};
  // Lower nose: 33 the nose base centre, 34 between, 35 the left ala's lower edge.
  t[33] = {{0, -60, 130}, {0, 0.5, -0.866}};  // seen a little from below: the columella base
  t[34] = {{7, -59, 127}, {0, 0.5, -0.866}};
  t[35] = front(15.5, -42.5);
  // Left eye: 42 inner corner, 43-44 upper lid, 45 outer corner, 46-47 lower lid. These
  // targets only seed the projection: MakeSampleHead puts the eye's points on the open lids'
  // margins.
  t[42] = front(kInnerCanthusX + 0.5, LidLineY(kInnerCanthusX + 0.5));
  t[43] = front(26, LidLineY(26) + 0.6);
  t[44] = front(36, LidLineY(36) + 0.6);
  t[45] = front(kOuterCanthusX - 0.5, LidLineY(kOuterCanthusX - 0.5));
  t[46] = front(36, LidLineY(36) - 0.6);
  t[47] = front(26, LidLineY(26) - 0.6);
  // Outer lip 51 (top centre) .. 54 (left corner) .. 57 (bottom centre); inner lip on the
  // closed mouth line, just above (61-63) and below (65-67) it.
  // The mouth line's points: at the line's height where it meets the surface (z found by
  // projecting, a few fixed-point steps).
  auto on_line = [&](double x, double dy) {
    double y = kStomionY;
    for (int k = 0; k < 6; ++k) y = MouthLineY(ProjectAlong({x, y, 200}, {0, 0, -1}, true).z);
    return front(x, y + dy);
  };
  t[54] = on_line(kMouthHalfWidth, 0);
  t[53] = front(16, -60.5);
  t[52] = front(6, -57.5);
  t[51] = front(0, -58.0);
  t[55] = front(16, -72.5);
  t[56] = front(7, -76.0);
  t[57] = front(0, -76.5);
  t[64] = on_line(kMouthHalfWidth - 2.5, 0);
  t[63] = on_line(10, 0.5);
  t[62] = front(0, kStomionY + 0.5);
  t[65] = on_line(10, -0.5);
  t[66] = front(0, kStomionY - 0.5);
  // The subject's right side (-x) mirrors the left (iBUG pairs, IbugMirrorLandmark).
  for (int l = 0; l < 68; ++l) {
    const int r = IbugMirrorLandmark(l);
    if (r == l || !(t[size_t(l)].from.x > 0)) continue;
    const LandmarkTarget& left = t[size_t(l)];
    t[size_t(r)] = {{-left.from.x, left.from.y, left.from.z}, {-left.dir.x, left.dir.y, left.dir.z}};
  }
  return t;
}

}  // namespace

SampleHead MakeSampleHead(const SampleHeadOptions& options) {
  int N = std::clamp(options.columns, 16, 4096);
  N += N % 2;
  const int M = std::clamp(options.rows, 8, 4096);
  const double fd = std::max(1.0, static_cast<double>(options.face_density));
  const bool ears = options.ears;
  const double y_cut = kMenton - 1.0;

  // Columns: dense over the face (|theta| < 75 deg), sparse at the back; eye corners and
  // the nasolabial region (|theta| 15-45 deg) a little denser still.
  auto col_density = [&](double th) {
    const double a = std::fabs(th);
    return 1.0 + (fd - 1.0) * (1.0 - SmoothStep(Rad(70), Rad(110), a)) +
           0.5 * (fd - 1.0) * Gauss(a - Rad(30), Rad(14)) +
           0.6 * (fd - 1.0) * Gauss(a, Rad(9));  // the nose
  };
  std::vector<double> theta = Quantiles(col_density, -kPiD, kPiD, N);
  for (int j = 0; j <= N / 2; ++j) theta[N - j] = -theta[j];
  theta[N / 2] = 0.0;

  // Rows: every column is sampled densely in phi, and its rows are placed at equal steps of
  // arc length weighted by a height-dependent density (dense from the hairline to the chin,
  // denser still at the forehead, the lid line and the mouth line). The weight depends on
  // height only, so a row stays at about the same height around the head.
  auto row_density = [&](double y) {
    return 1.0 + (fd - 1.0) * SmoothStep(85, 70, y) * SmoothStep(-125, -105, y) +
           1.0 * (fd - 1.0) * Gauss(y - LidLineY(kEye.x), 4.0) +
           0.8 * (fd - 1.0) * Gauss(y - kStomionY, 4.0) +
           0.4 * (fd - 1.0) * Gauss(y - 45.0, 18.0);  // forehead
  };
  const int K = 600;  // phi samples per column

  SampleHead head;
  MeshData& mesh = head.mesh;
  const size_t ring = static_cast<size_t>(N) + 1;
  mesh.positions.resize(1 + ring * M);
  mesh.uvs.resize(mesh.positions.size());
  auto vid = [&](int i, int j) { return static_cast<uint32_t>(1 + (i - 1) * ring + j); };

  // Pole.
  {
    mesh.positions[0] = ToF3(SurfacePoint(0.0, 0.0, ears));
    mesh.positions[0].x = 0.f;
    mesh.uvs[0] = {0.5f, 0.f};
  }
  // Columns 0..N/2 are cast; the rest mirror them (exact symmetry).
  std::vector<double> arc(mesh.positions.size(), 0.0);  // unweighted arc length from the pole
  double arc_max = 0.0;
  std::vector<V3> pts(K + 1);
  std::vector<double> wlen(K + 1), len(K + 1);
  auto sample_column = [&](double th, double pe) {
    for (int k = 0; k <= K; ++k) {
      pts[k] = SurfacePoint(th, pe * k / K, ears);
      if (k == 0) {
        wlen[0] = len[0] = 0.0;
        continue;
      }
      const double seg = Len(pts[k] - pts[k - 1]);
      len[k] = len[k - 1] + seg;
      wlen[k] = wlen[k - 1] + seg * row_density(0.5 * (pts[k].y + pts[k - 1].y));
    }
  };
  // Weighted arc length at polar angle ph (linear in the samples, as the rows invert it).
  auto wlen_at = [&](double ph, double pe) {
    const double kf = std::clamp(ph / pe * K, 0.0, double(K));
    const int k = std::min(int(kf), K - 1);
    return wlen[k] + (kf - k) * (wlen[k + 1] - wlen[k]);
  };
  // The mouth line (MouthLineY) lies on one grid row, `i_mouth`: in the columns that cross
  // the mouth that row is moved onto the line (and its neighbours, so the
  // rows stay ordered, fading over 8 rows); beside the corners the move fades out over 10 mm. The row is the one
  // nearest the line on the midline.
  auto mouth_phi = [&](double th) {
    double lo = Rad(105), hi = Rad(150);
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      const V3 sp = SurfacePoint(th, mid, ears);
      if (sp.y > MouthLineY(sp.z)) lo = mid;
      else hi = mid;
    }
    return 0.5 * (lo + hi);
  };
  int i_mouth = 0;
  {
    const double pe = PhiEnd(0.0, y_cut, ears);
    sample_column(0.0, pe);
    i_mouth = int(std::lround(wlen_at(mouth_phi(0.0), pe) / wlen[K] * M));
  }
  head.mouth_row = i_mouth;
  auto len_at = [&](double ph, double pe) {  // unweighted arc length at polar angle ph
    const double kf = std::clamp(ph / pe * K, 0.0, double(K));
    const int k = std::min(int(kf), K - 1);
    return len[k] + (kf - k) * (len[k + 1] - len[k]);
  };
  // The eyes: the lid line (LidLineY) lies on one grid row, `i_lid` (the row nearest it at the
  // eyeball's centre). In the columns that cross an eye the row is moved onto the line, and
  // between the canthi it is cut: the row's vertex moves up to the upper lid's margin
  // (UpperLidY) and its twin down to the lower one's (LowerLidY), all on the field's surface
  // (the lids over the eyeball); the rows above, up to 14 mm over the line, and below, down to
  // 10 mm under it, are drawn along in polar angle (a monotone piecewise-linear map, so the
  // rows stay ordered). Beside the canthi the move onto the line fades out over 8 mm.
  auto phi_at = [&](double th, auto target_y) {  // where the column meets y = target_y(|x|)
    double lo = Rad(60), hi = Rad(120);
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      const V3 sp = SurfacePoint(th, mid, ears);
      if (sp.y > target_y(std::fabs(sp.x))) lo = mid;
      else hi = mid;
    }
    return 0.5 * (lo + hi);
  };
  auto lid_line = [](double ax) { return LidLineY(ax); };
  int i_lid = 0;
  {
    const double th = -std::atan2(kEye.x, kEye.z - kRayCentre.z);  // the right eye's centre
    const double pe = PhiEnd(th, y_cut, ears);
    sample_column(th, pe);
    i_lid = int(std::lround(wlen_at(phi_at(th, lid_line), pe) / wlen[K] * M));
  }
  head.lid_row = i_lid;
  // Per column (j <= N / 2, the right eye's; mirrored below): whether it lies strictly
  // between the canthi, and then its lower-lid margin point.
  std::vector<char> lid_cut(ring, 0);
  std::vector<float3> lid_twin(ring);
  std::vector<double> lid_twin_arc(ring, 0.0);
  std::vector<double> row_ph(M + 1), row_arc(M + 1);
  for (int j = 0; j <= N / 2; ++j) {
    const double pe = PhiEnd(theta[j], y_cut, ears);
    sample_column(theta[j], pe);
    double delta = 0.0, phi_mouth = -1.0;
    if (std::fabs(theta[j]) < Rad(40)) {
      const double ph = mouth_phi(theta[j]);
      const double ax = std::fabs(SurfacePoint(theta[j], ph, ears).x);
      const double fade = 1.0 - SmoothStep(kMouthHalfWidth + 2, kMouthHalfWidth + 12, ax);
      if (fade > 0) delta = fade * (wlen_at(ph, pe) - wlen[K] * i_mouth / M);
      if (fade == 1.0) phi_mouth = ph;
    }
    int k = 0;
    for (int i = 1; i <= M; ++i) {
      const double target =
          wlen[K] * i / M + delta * std::max(0.0, 1.0 - std::fabs(double(i - i_mouth)) / 8.0);
      while (k < K - 1 && wlen[k + 1] < target) ++k;
      const double t = Clamp01((target - wlen[k]) / std::max(wlen[k + 1] - wlen[k], 1e-300));
      row_ph[i] = i == M ? pe : (i == i_mouth && phi_mouth >= 0 ? phi_mouth : pe * (k + t) / K);
      row_arc[i] = len[k] + t * (len[k + 1] - len[k]);
    }
    const double ath = std::fabs(theta[j]);
    if (ath > Rad(2) && ath < Rad(70)) {
      const double ph_lid = phi_at(theta[j], lid_line);
      const double ax = std::fabs(SurfacePoint(theta[j], ph_lid, ears).x);
      const double out = std::max({kInnerCanthusX - ax, ax - kOuterCanthusX, 0.0});
      const double w = 1.0 - SmoothStep(0.0, 8.0, out);
      const double ph_row = row_ph[i_lid];
      // The band reaches 14 mm above and 10 mm below the lid line, and at least 4 degrees
      // beyond the row itself (toward the nose the rows run well below the lid line), so that
      // every column the fade touches is mapped and the map fades out smoothly.
      const double ph_top =
          std::min(phi_at(theta[j], [](double x) { return LidLineY(x) + 14.0; }), ph_row - Rad(4));
      const double ph_bot =
          std::max(phi_at(theta[j], [](double x) { return LidLineY(x) - 10.0; }), ph_row + Rad(4));
      const bool cut = ax > kInnerCanthusX && ax < kOuterCanthusX;
      double ph_u = ph_lid, ph_l = ph_lid;
      if (w > 0 && cut) {
        ph_u = phi_at(theta[j], [](double x) { return UpperLidY(x); });
        ph_l = phi_at(theta[j], [](double x) { return LowerLidY(x); });
      }
      ph_u = ph_row + w * (ph_u - ph_row);
      ph_l = ph_row + w * (ph_l - ph_row);
      if (w > 0 && ph_top < ph_u && ph_u <= ph_l && ph_l < ph_bot) {
        for (int i = 1; i < M; ++i) {
          const double ph = row_ph[i];
          if (i == i_lid) {
            row_ph[i] = ph_u;
          } else if (ph > ph_top && ph < ph_row) {
            row_ph[i] = ph_top + (ph - ph_top) * (ph_u - ph_top) / (ph_row - ph_top);
          } else if (ph > ph_row && ph < ph_bot) {
            row_ph[i] = ph_bot - (ph_bot - ph) * (ph_bot - ph_l) / (ph_bot - ph_row);
          } else {
            continue;
          }
          row_arc[i] = len_at(row_ph[i], pe);
        }
        if (cut) {
          lid_cut[j] = 1;
          lid_twin[j] = ToF3(SurfacePoint(theta[j], ph_l, ears));
          lid_twin_arc[j] = len_at(ph_l, pe);
        }
      }
    }
    for (int i = 1; i <= M; ++i) {
      const double ph = row_ph[i];
      float3 pos = ToF3(SurfacePoint(theta[j], ph, ears));
      if (j == 0 || j == N / 2) pos.x = 0.f;
      const double s_arc = row_arc[i];
      arc_max = std::max(arc_max, s_arc);
      const float u = static_cast<float>(0.5 + theta[j] / (2 * kPiD));
      mesh.positions[vid(i, j)] = pos;
      mesh.uvs[vid(i, j)] = {u, 0.f};
      arc[vid(i, j)] = s_arc;
      if (j != N - j) {
        mesh.positions[vid(i, N - j)] = {-pos.x, pos.y, pos.z};
        mesh.uvs[vid(i, N - j)] = {1.f - u, 0.f};
        arc[vid(i, N - j)] = s_arc;
      }
    }
  }
  for (size_t k = 1; k < mesh.positions.size(); ++k)
    mesh.uvs[k].y = static_cast<float>(arc[k] / arc_max);
  // The seam: column N repeats column 0 (u = 1 instead of 0).
  for (int i = 1; i <= M; ++i) {
    mesh.positions[vid(i, N)] = mesh.positions[vid(i, 0)];
    mesh.uvs[vid(i, 0)].x = 0.f;
    mesh.uvs[vid(i, N)].x = 1.f;
  }

  // The mouth slit (between the corner columns `jc` and N - jc, on row i_mouth): the lips are
  // cut apart along the mouth line. The row's vertices strictly between the corners stay with
  // the upper lip (moved up by half the slit's width) and get a twin for the lower lip (moved
  // down as much: the two must not weld, geometry/weld.h); the corners are shared. Behind
  // each lip an inner roll of kSampleHeadLipRollRows rows turns inward (along the dental arch's
  // normal) and away from the mouth line, up behind the upper lip and down behind the lower
  // one, tapering to nothing at the corners; each ends in an open boundary, so the hole runs
  // between the two roll ends and an open mouth shows the rolls' surfaces.
  const float3 up{0.f, 1.f, 0.f};
  int jc = N / 2;  // the corner column on the subject's right (x < 0); N - jc the left one
  while (jc > 0 && mesh.positions[vid(i_mouth, jc)].z > 0 &&
         std::fabs(mesh.positions[vid(i_mouth, jc)].x) < kSampleHeadMouthHalfWidth)
    --jc;
  const int jr = N - jc;
  const float corner_x = std::fabs(mesh.positions[vid(i_mouth, jc)].x);
  constexpr int R = kSampleHeadLipRollRows;
  // Roll profiles (mm; inward along the arch normal, up): the upper one rises faster than the
  // jaw's lip-line plane (docs/model.md §18: it climbs about 0.3 mm per mm toward the hinge)
  // so it stays with the skull; the lower one stays below it, so it goes with the jaw.
  static constexpr double kUpperIn[R] = {0.7, 1.6, 2.6, 3.5, 4.2},
                          kUpperUp[R] = {0.6, 1.5, 2.8, 4.6, 6.8},
                          kLowerIn[R] = {0.9, 2.0, 3.3, 4.7, 6.0},
                          kLowerUp[R] = {-0.4, -1.0, -1.9, -3.2, -5.0};
  constexpr float kHalfGap = kSampleHeadSlitWidth * 0.5f;
  constexpr float kSlitInset = kSampleHeadSlitInset;
  const uint32_t first_new = static_cast<uint32_t>(mesh.positions.size());
  const int inner = jr - jc - 1;  // columns strictly between the corners
  mesh.positions.resize(first_new + size_t(inner) * (2 * R + 1));
  mesh.uvs.resize(mesh.positions.size());
  // Upper roll row r (0 = the slit row) and lower roll row r (0 = the lower lip's slit twin)
  // at column j in [jc, jr].
  auto upper = [&](int r, int j) -> uint32_t {
    if (j == jc || j == jr) return vid(i_mouth, j);
    if (r == 0) return vid(i_mouth, j);
    return first_new + uint32_t(j - jc - 1) * (2 * R + 1) + uint32_t(r);
  };
  auto lower = [&](int r, int j) -> uint32_t {
    if (j == jc || j == jr) return vid(i_mouth, j);
    return first_new + uint32_t(j - jc - 1) * (2 * R + 1) + uint32_t(r == 0 ? 0 : R + r);
  };
  for (int j = jc + 1; j < jr; ++j) {
    const float3 p = mesh.positions[vid(i_mouth, j)];
    const float2 uv = mesh.uvs[vid(i_mouth, j)];
    const float3 in = NormalizeOr(float3{-p.x / float(kArch), 0.f, -1.f}, {0.f, 0.f, -1.f});
    const float taper = std::sqrt(std::max(0.f, 1.f - (p.x / corner_x) * (p.x / corner_x)));
    // The slit itself sits kSlitInset behind the surface (less toward the corners, none at
    // them), so the lips' outer surfaces turn into it: the upper lip's last row faces down and
    // the lower lip's first row up, which is what the jaw's weight reads to tell them apart.
    const float inset = kSlitInset;
    const float3 pu = p + up * kHalfGap + in * inset, pl = p - up * kHalfGap + in * inset;
    mesh.positions[vid(i_mouth, j)] = pu;
    mesh.positions[lower(0, j)] = pl;
    for (int r = 1; r <= R; ++r) {
      mesh.positions[upper(r, j)] =
          pu + (in * float(kUpperIn[r - 1]) + up * float(kUpperUp[r - 1])) * taper;
      mesh.positions[lower(r, j)] =
          pl + (in * float(kLowerIn[r - 1]) + up * float(kLowerUp[r - 1])) * taper;
    }
    // Texture space has no room for the rolls: they get a sliver (kRollDv per row, a tenth of a
    // texel of a 1024 map) beside the slit, continuing each lip's direction of v, so no
    // triangle is degenerate in texture space (curve wrinkles and thickness maps need area).
    constexpr float kRollDv = 1e-4f;
    for (int r = 0; r <= R; ++r) {
      mesh.uvs[upper(r, j)] = {uv.x, uv.y + kRollDv * float(r)};
      mesh.uvs[lower(r, j)] = {uv.x, uv.y - kRollDv * float(r)};
    }
  }

  // The lid fissures: on row i_lid, between the corner columns ec0 < ec1 of each eye (the
  // last columns outside the canthi; the right eye's from the outer canthus to the inner one,
  // the left's mirrored), the row's vertices are the upper lids' margin and get a twin on the
  // lower lid's margin; the corners are shared. Behind each margin an inner roll of
  // kSampleHeadLidRollRows rows turns in toward the eyeball's centre, ending
  // kSampleHeadLidRollGap outside the eyeball (less toward the canthi, tapering to nothing at
  // them), so the lid edge has a thickness and the hole's boundary runs round the eyeball.
  constexpr int RL = kSampleHeadLidRollRows;
  int ec0 = -1, ec1 = -1;  // the right eye's corner columns
  for (int j = 1; j < N / 2; ++j)
    if (lid_cut[size_t(j)]) {
      if (ec0 < 0) ec0 = j - 1;
      ec1 = j + 1;
    }
  for (int j = ec0 + 1; j < ec1; ++j) lid_cut[size_t(j)] = 1;  // contiguous (x is monotone along a row)
  const int eye_inner = ec0 < 0 ? 0 : ec1 - ec0 - 1;
  const uint32_t eye_first = static_cast<uint32_t>(mesh.positions.size());
  mesh.positions.resize(eye_first + 2 * size_t(eye_inner) * (2 * RL + 1));
  mesh.uvs.resize(mesh.positions.size());
  // Eye e (0 = the right, x < 0, columns ec0..ec1; 1 = the left, columns N - ec1..N - ec0).
  auto eye_c0 = [&](int e) { return e == 0 ? ec0 : N - ec1; };
  auto eye_c1 = [&](int e) { return e == 0 ? ec1 : N - ec0; };
  auto eye_base = [&](int e, int j) {
    return eye_first + uint32_t(e * eye_inner + (j - eye_c0(e) - 1)) * uint32_t(2 * RL + 1);
  };
  auto lid_upper = [&](int e, int r, int j) -> uint32_t {
    if (r == 0 || j == eye_c0(e) || j == eye_c1(e)) return vid(i_lid, j);
    return eye_base(e, j) + uint32_t(r);
  };
  auto lid_lower = [&](int e, int r, int j) -> uint32_t {
    if (j == eye_c0(e) || j == eye_c1(e)) return vid(i_lid, j);
    return eye_base(e, j) + uint32_t(r == 0 ? 0 : RL + r);
  };
  for (int j = ec0 + 1; j < ec1 && ec0 >= 0; ++j) {
    const float3 c{-kSampleHeadEyeCentre.x, kSampleHeadEyeCentre.y, kSampleHeadEyeCentre.z};
    const float3 pu = mesh.positions[vid(i_lid, j)], pl = lid_twin[size_t(j)];
    const float2 uvu = mesh.uvs[vid(i_lid, j)];
    const float vl = static_cast<float>(lid_twin_arc[size_t(j)] / arc_max);
    const float half = 0.5f * (kSampleHeadOuterCanthusX - kSampleHeadInnerCanthusX);
    const float xm = -(kSampleHeadInnerCanthusX + half);
    const float s = (pu.x - xm) / half;
    const float taper = std::sqrt(std::max(0.f, 1.f - s * s));
    mesh.positions[lid_lower(0, 0, j)] = pl;
    mesh.uvs[lid_lower(0, 0, j)] = {uvu.x, vl};
    for (int r = 1; r <= RL; ++r) {
      const float f = taper * float(r) / float(RL);
      const float3 eu = c + NormalizeOr(pu - c, {0.f, 0.f, 1.f}) * (kSampleHeadEyeballRadius + kSampleHeadLidRollGap);
      const float3 el = c + NormalizeOr(pl - c, {0.f, 0.f, 1.f}) * (kSampleHeadEyeballRadius + kSampleHeadLidRollGap);
      mesh.positions[lid_upper(0, r, j)] = pu + (eu - pu) * f;
      mesh.positions[lid_lower(0, r, j)] = pl + (el - pl) * f;
      // Texture space: the fissure between the two margins is unused; each roll takes a strip
      // of it (up to 0.4 of the gap) beside its margin, so no roll triangle is degenerate there.
      const float dv = (vl - uvu.y) * 0.4f * float(r) / float(RL);
      mesh.uvs[lid_upper(0, r, j)] = {uvu.x, uvu.y + dv};
      mesh.uvs[lid_lower(0, r, j)] = {uvu.x, vl - dv};
    }
    // The left eye: the mirror image (column N - j; u mirrored as the grid's).
    for (int r = 0; r <= RL; ++r)
      for (int side = 0; side < 2; ++side) {
        const uint32_t a = side == 0 ? lid_upper(0, r, j) : lid_lower(0, r, j);
        const uint32_t b = side == 0 ? lid_upper(1, r, N - j) : lid_lower(1, r, N - j);
        if (a < eye_first) continue;  // a grid vertex, mirrored with the grid
        const float3 p = mesh.positions[a];
        mesh.positions[b] = {-p.x, p.y, p.z};
        mesh.uvs[b] = {1.f - mesh.uvs[a].x, mesh.uvs[a].y};
      }
  }
  auto eye_of = [&](int j) {  // the eye whose slit spans quad column j (j .. j + 1), or -1
    if (ec0 < 0) return -1;
    for (int e = 0; e < 2; ++e)
      if (j >= eye_c0(e) && j < eye_c1(e)) return e;
    return -1;
  };

  // Triangles: a fan at the pole, then quads split along their shorter diagonal;
  // counter-clockwise seen from outside. A quad with a collapsed side (at a mouth corner) is
  // one triangle.
  mesh.indices.reserve((static_cast<size_t>(N) * (2 * M - 1) + size_t(4 * R) * (inner + 1)) * 3);
  for (int j = 0; j < N; ++j) {
    mesh.indices.insert(mesh.indices.end(), {0u, vid(1, j), vid(1, j + 1)});
  }
  auto quad = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t e) {
    if (a == c) return void(mesh.indices.insert(mesh.indices.end(), {a, e, b}));
    if (b == e) return void(mesh.indices.insert(mesh.indices.end(), {a, c, e}));
    const float ad = LengthSquared(mesh.positions[a] - mesh.positions[e]);
    const float bc = LengthSquared(mesh.positions[b] - mesh.positions[c]);
    // Mirrored quads compare the same two lengths, so the choice mirrors too.
    if (ad <= bc) {
      mesh.indices.insert(mesh.indices.end(), {a, c, e, a, e, b});
    } else {
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, e});
    }
  };
  for (int i = 1; i < M; ++i) {
    for (int j = 0; j < N; ++j) {
      uint32_t a = vid(i, j), b = vid(i, j + 1);
      if (i == i_mouth && j >= jc && j < jr) a = lower(0, j), b = lower(0, j + 1);
      if (i == i_lid && eye_of(j) >= 0) a = lid_lower(eye_of(j), 0, j), b = lid_lower(eye_of(j), 0, j + 1);
      quad(a, b, vid(i + 1, j), vid(i + 1, j + 1));
    }
  }
  for (int e = 0; e < 2 && ec0 >= 0; ++e)
    for (int r = 0; r < RL; ++r)
      for (int j = eye_c0(e); j < eye_c1(e); ++j) {
        quad(lid_upper(e, r, j), lid_upper(e, r, j + 1), lid_upper(e, r + 1, j), lid_upper(e, r + 1, j + 1));
        quad(lid_lower(e, r + 1, j), lid_lower(e, r + 1, j + 1), lid_lower(e, r, j), lid_lower(e, r, j + 1));
      }
  for (int r = 0; r < R; ++r)
    for (int j = jc; j < jr; ++j) {
      quad(upper(r, j), upper(r, j + 1), upper(r + 1, j), upper(r + 1, j + 1));
      quad(lower(r + 1, j), lower(r + 1, j + 1), lower(r, j), lower(r, j + 1));
    }

  if (options.normals) {
    // Area-weighted; the seam's two columns (the only vertices that share a position) get
    // one normal, so the seam does not show.
    VertexNormalOptions normal_options;
    normal_options.share_by_position = true;
    normal_options.fallback = {0.f, 1.f, 0.f};
    mesh.normals = ComputeVertexNormals(mesh, normal_options);
  }

  // Landmarks: project each target onto the field's surface, then onto the nearest mesh
  // point.
  const std::array<LandmarkTarget, 68> targets = LandmarkTargets();
  head.landmarks.resize(68);
  for (int l = 0; l < 68; ++l) {
    if (targets[l].from.x < 0) continue;  // mirrored below
    const V3 s = ProjectAlong(targets[l].from, targets[l].dir, ears);
    V3 best = s;
    double best_d2 = 1e300;
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
      const V3 a = ToV3(mesh.positions[mesh.indices[t]]);
      if (Dot(a - s, a - s) > 400.0) continue;  // far triangles (edges are < 20 mm here)
      const V3 b = ToV3(mesh.positions[mesh.indices[t + 1]]);
      const V3 e = ToV3(mesh.positions[mesh.indices[t + 2]]);
      const double sp[3] = {s.x, s.y, s.z}, ap[3] = {a.x, a.y, a.z}, bp[3] = {b.x, b.y, b.z},
                   ep[3] = {e.x, e.y, e.z};
      const TrianglePoint q = ClosestPointOnTriangle(sp, ap, bp, ep);
      const V3 c{q.point[0], q.point[1], q.point[2]};
      const double d2 = Dot(c - s, c - s);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = c;
      }
    }
    head.landmarks[l] = ToF3(best);
    if (targets[l].from.x == 0) head.landmarks[l].x = 0.f;
  }
  // The left eye's landmarks lie on its lid margins (on the margin's polyline, between the
  // two margin points whose x brackets theirs): 42 and 45 on the upper margin 0.5 mm inside
  // the canthi (where the lids meet; the closed-lid head's corner targets, so the face frame,
  // whose scale is |45 - 36|, stays), 43-44 on the upper margin and 47-46 on the lower one at
  // x = 26 and 36.
  if (ec0 >= 0) {
    const int c_in = N - ec1, c_out = N - ec0;
    auto on_margin = [&](bool upper_lid, float x) {
      for (int j = c_in; j < c_out; ++j) {
        const float3 a = mesh.positions[upper_lid ? lid_upper(1, 0, j) : lid_lower(1, 0, j)];
        const float3 b = mesh.positions[upper_lid ? lid_upper(1, 0, j + 1) : lid_lower(1, 0, j + 1)];
        if (a.x <= x && x <= b.x && b.x > a.x) return a + (b - a) * ((x - a.x) / (b.x - a.x));
      }
      return mesh.positions[vid(i_lid, c_in)];
    };
    head.landmarks[42] = on_margin(true, kSampleHeadInnerCanthusX + 0.5f);
    head.landmarks[45] = on_margin(true, kSampleHeadOuterCanthusX - 0.5f);
    head.landmarks[43] = on_margin(true, 26.f);
    head.landmarks[44] = on_margin(true, 36.f);
    head.landmarks[47] = on_margin(false, 26.f);
    head.landmarks[46] = on_margin(false, 36.f);
  }
  for (int l = 0; l < 68; ++l) {
    const int r = IbugMirrorLandmark(l);
    if (r == l || !(targets[size_t(l)].from.x > 0)) continue;
    const float3 p = head.landmarks[size_t(l)];
    head.landmarks[size_t(r)] = {-p.x, p.y, p.z};
  }
  return head;
}

MeshData MakeSampleHeadEyes(int rings, int segments) {
  rings = std::clamp(rings, 3, 256);
  segments = std::clamp(segments, 3, 1024);
  const uint32_t per_eye = uint32_t(2 + (rings - 1) * segments);
  MeshData left;  // the subject's left eye (+x)
  const V3 c = kEye;
  const double r = kSampleHeadEyeballRadius;
  auto add = [&](V3 n) {
    left.positions.push_back(ToF3(c + n * r));
    left.normals.push_back(ToF3(n));
  };
  add({0, 0, 1});
  for (int k = 1; k < rings; ++k) {
    const double a = kPiD * k / rings;
    for (int s = 0; s < segments; ++s) {
      const double b = 2 * kPiD * s / segments;
      add({std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a)});
    }
  }
  add({0, 0, -1});
  auto ring = [&](int k, int s) { return uint32_t(1 + (k - 1) * segments + (s % segments)); };
  for (int s = 0; s < segments; ++s) left.indices.insert(left.indices.end(), {0u, ring(1, s), ring(1, s + 1)});
  for (int k = 1; k + 1 < rings; ++k)
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = ring(k, s), b = ring(k, s + 1), cc = ring(k + 1, s), d = ring(k + 1, s + 1);
      left.indices.insert(left.indices.end(), {b, a, cc, b, cc, d});
    }
  for (int s = 0; s < segments; ++s)
    left.indices.insert(left.indices.end(), {per_eye - 1, ring(rings - 1, s + 1), ring(rings - 1, s)});
  // Both eyes: the right one mirrored (x -> -x, each triangle's order reversed so that it still
  // faces out), then the left one.
  MeshData eyes;
  for (size_t v = 0; v < left.positions.size(); ++v) {
    const float3 p = left.positions[v], n = left.normals[v];
    eyes.positions.push_back({-p.x, p.y, p.z});
    eyes.normals.push_back({-n.x, n.y, n.z});
  }
  for (size_t t = 0; t < left.indices.size(); t += 3)
    eyes.indices.insert(eyes.indices.end(), {left.indices[t], left.indices[t + 2], left.indices[t + 1]});
  eyes.positions.insert(eyes.positions.end(), left.positions.begin(), left.positions.end());
  eyes.normals.insert(eyes.normals.end(), left.normals.begin(), left.normals.end());
  for (uint32_t i : left.indices) eyes.indices.push_back(i + per_eye);
  return eyes;
}

}  // namespace mimetic
