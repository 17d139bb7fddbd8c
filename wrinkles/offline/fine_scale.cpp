#include "wrinkles/offline/fine_scale.h"

#include <Eigen/Sparse>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "geometry/topology.h"

namespace mimetic {

namespace {

// max(lo, min(hi, floor(v))) and the same of ceil(v), NaN -> lo: std::floor and std::ceil
// are long inline sequences without SSE4.1; these are one conversion each, the same integers.
inline int FloorIn(float v, int lo, int hi) {
  if (!(v >= float(lo))) return lo;
  if (v >= float(hi)) return hi;
  const int i = int(v);
  return i - (float(i) > v ? 1 : 0);
}
inline int CeilIn(float v, int lo, int hi) {
  if (!(v >= float(lo))) return lo;
  if (v >= float(hi)) return hi;
  const int i = int(v);
  return i + (float(i) < v ? 1 : 0);
}

bool Finite(float3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
float Dot2(float2 a, float2 b) { return a.x * b.x + a.y * b.y; }
float2 Sub2(float2 a, float2 b) { return {a.x - b.x, a.y - b.y}; }

// Area-weighted point normals (unit, or 0 for an isolated point).
std::vector<float3> PointNormals(const FineScaleMesh& m) {
  std::vector<float3> n(m.points.size(), float3{});
  for (size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
    const uint32_t a = m.triangles[t], b = m.triangles[t + 1], c = m.triangles[t + 2];
    if (a >= n.size() || b >= n.size() || c >= n.size()) continue;
    const float3 f = Cross(m.points[b] - m.points[a], m.points[c] - m.points[a]);
    n[a] += f;
    n[b] += f;
    n[c] += f;
  }
  for (float3& v : n) v = NormalizeOr(v, float3{});
  return n;
}

// Cotangent weight of the angle at `o` opposite edge (a, b), clamped to a small positive
// value (Eck et al.'s harmonic-map springs; the clamp keeps the system positive definite on
// obtuse triangles).
double Cot(float3 o, float3 a, float3 b) {
  const float3 u = a - o, v = b - o;
  const double c = Dot(u, v), s = Length(Cross(u, v));
  return s > 1e-30 ? c / s : 0.0;
}

// The cotangent Laplacian's edge weights: sum over the two triangles of 1/2 cot, >= 1e-6.
struct EdgeWeights {
  std::vector<Eigen::Triplet<double>> triplets;  // off-diagonal -w, both ways
  std::vector<double> diagonal;
};
EdgeWeights CotangentWeights(const FineScaleMesh& m) {
  std::vector<std::pair<uint64_t, double>> edges;
  edges.reserve(m.triangles.size());
  const size_t n = m.points.size();
  for (size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
    const uint32_t c[3] = {m.triangles[t], m.triangles[t + 1], m.triangles[t + 2]};
    if (c[0] >= n || c[1] >= n || c[2] >= n) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = c[(k + 1) % 3], b = c[(k + 2) % 3];
      const double w = 0.5 * Cot(m.points[c[k]], m.points[a], m.points[b]);
      edges.push_back({uint64_t(std::min(a, b)) << 32 | std::max(a, b), w});
    }
  }
  std::sort(edges.begin(), edges.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  EdgeWeights out;
  out.diagonal.assign(n, 0.0);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    double w = 0.0;
    for (; j < edges.size() && edges[j].first == edges[i].first; ++j) w += edges[j].second;
    w = std::max(w, 1e-6);
    const uint32_t a = uint32_t(edges[i].first >> 32), b = uint32_t(edges[i].first);
    out.triplets.emplace_back(a, b, -w);
    out.triplets.emplace_back(b, a, -w);
    out.diagonal[a] += w;
    out.diagonal[b] += w;
    i = j;
  }
  return out;
}

// Solves L x = 0 on the free points with x fixed at `fixed` (fixed[p] >= 0: its row in
// `values`), for `dims` columns of values. Points with no edge to anything keep `isolated`.
bool HarmonicSolve(const FineScaleMesh& m, const std::vector<int>& fixed,
                   const Eigen::MatrixXd& values, Eigen::MatrixXd* out) {
  const size_t n = m.points.size();
  const EdgeWeights w = CotangentWeights(m);
  std::vector<int> free_index(n, -1);
  int free_count = 0;
  for (size_t p = 0; p < n; ++p)
    if (fixed[p] < 0) free_index[p] = free_count++;
  out->setZero(Eigen::Index(n), values.cols());
  for (size_t p = 0; p < n; ++p)
    if (fixed[p] >= 0) out->row(Eigen::Index(p)) = values.row(fixed[p]);
  if (free_count == 0) return true;
  std::vector<Eigen::Triplet<double>> a;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(free_count, values.cols());
  for (size_t p = 0; p < n; ++p)
    if (free_index[p] >= 0)
      a.emplace_back(free_index[p], free_index[p], w.diagonal[p] > 0.0 ? w.diagonal[p] : 1.0);
  for (const auto& t : w.triplets) {
    const int r = free_index[size_t(t.row())];
    if (r < 0) continue;
    const int c = free_index[size_t(t.col())];
    if (c >= 0)
      a.emplace_back(r, c, t.value());
    else
      rhs.row(r) -= t.value() * out->row(t.col());
  }
  Eigen::SparseMatrix<double> A(free_count, free_count);
  A.setFromTriplets(a.begin(), a.end());
  // A component without a fixed point is singular; a tiny diagonal shift keeps it solvable
  // (its points go to 0, i.e. no field there).
  for (int i = 0; i < free_count; ++i) A.coeffRef(i, i) += 1e-9 * (A.coeff(i, i) + 1.0);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) return false;
  for (size_t p = 0; p < n; ++p)
    if (free_index[p] >= 0) out->row(Eigen::Index(p)) = x.row(free_index[p]);
  return true;
}

// Harmonic interpolation of several fields on one mesh with ONE factorization: L is
// factored over F, the points that are no field's anchor (U = the union of the anchors); the
// harmonic extensions H = -L_FF^-1 L_FU of the |U| unit values give every field's free
// points from its values on U, x_F = H x_U. For field k, the points of U that are not its
// anchors (Z) are unknowns that must be harmonic too: (L x)_z = 0, i.e.
// (L_ZU + L_ZF H) x_U = 0, a |Z| x |Z| dense solve. The same solution as one solve per field.
bool HarmonicFields(const FineScaleMesh& m, const std::vector<std::vector<uint32_t>>& anchors,
                    const std::vector<Eigen::MatrixXd>& values, std::vector<Eigen::MatrixXd>* out) {
  const size_t n = m.points.size();
  const EdgeWeights w = CotangentWeights(m);
  Eigen::SparseMatrix<double, Eigen::RowMajor> L{Eigen::Index(n), Eigen::Index(n)};
  {
    std::vector<Eigen::Triplet<double>> t = w.triplets;
    for (size_t p = 0; p < n; ++p)
      t.emplace_back(Eigen::Index(p), Eigen::Index(p), w.diagonal[p] > 0.0 ? w.diagonal[p] : 1.0);
    L.setFromTriplets(t.begin(), t.end());
  }
  std::vector<int> u_index(n, -1), f_index(n, -1);
  std::vector<uint32_t> U;
  for (const auto& a : anchors)
    for (uint32_t p : a)
      if (u_index[p] < 0) u_index[p] = int(U.size()), U.push_back(p);
  int nf = 0;
  std::vector<uint32_t> F;
  for (size_t p = 0; p < n; ++p)
    if (u_index[p] < 0) f_index[p] = nf++, F.push_back(uint32_t(p));
  const int nu = int(U.size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nf, nu);
  if (nf > 0) {
    std::vector<Eigen::Triplet<double>> a;
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(nf, nu);
    for (int r = 0; r < nf; ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(L, F[size_t(r)]); it; ++it) {
        const int c = int(it.col());
        if (f_index[size_t(c)] >= 0)
          a.emplace_back(r, f_index[size_t(c)], it.value() + (c == int(F[size_t(r)]) ? 1e-9 * (it.value() + 1.0) : 0.0));
        else
          B(r, u_index[size_t(c)]) -= it.value();
      }
    Eigen::SparseMatrix<double> A(nf, nf);
    A.setFromTriplets(a.begin(), a.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
    if (solver.info() != Eigen::Success) return false;
    H = solver.solve(B);
    if (solver.info() != Eigen::Success || !H.allFinite()) return false;
  }
  out->assign(anchors.size(), Eigen::MatrixXd());
  for (size_t k = 0; k < anchors.size(); ++k) {
    const Eigen::Index cols = values[k].cols();
    Eigen::MatrixXd xu = Eigen::MatrixXd::Zero(nu, cols);
    std::vector<uint8_t> known(size_t(nu), 0);
    for (size_t i = 0; i < anchors[k].size(); ++i) {  // a repeated point: the last value wins
      xu.row(u_index[anchors[k][i]]) = values[k].row(Eigen::Index(i));
      known[size_t(u_index[anchors[k][i]])] = 1;
    }
    std::vector<int> Z;
    for (int j = 0; j < nu; ++j)
      if (!known[size_t(j)]) Z.push_back(j);
    if (!Z.empty()) {
      // M = L_ZU + L_ZF H, row by row.
      Eigen::MatrixXd M = Eigen::MatrixXd::Zero(Eigen::Index(Z.size()), nu);
      for (size_t zi = 0; zi < Z.size(); ++zi)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(L, U[size_t(Z[zi])]); it; ++it) {
          const size_t c = size_t(it.col());
          if (f_index[c] >= 0)
            M.row(Eigen::Index(zi)) += it.value() * H.row(f_index[c]);
          else
            M(Eigen::Index(zi), u_index[c]) += it.value();
        }
      Eigen::MatrixXd Mz(Eigen::Index(Z.size()), Eigen::Index(Z.size()));
      for (size_t j = 0; j < Z.size(); ++j) Mz.col(Eigen::Index(j)) = M.col(Z[j]);
      const Eigen::MatrixXd rhs = -(M * xu);  // the unknown rows of xu are 0 here
      const Eigen::MatrixXd xz = Mz.fullPivLu().solve(rhs);
      if (!xz.allFinite()) return false;
      for (size_t j = 0; j < Z.size(); ++j) xu.row(Z[j]) = xz.row(Eigen::Index(j));
    }
    Eigen::MatrixXd& x = (*out)[k];
    x.setZero(Eigen::Index(n), cols);
    const Eigen::MatrixXd xf = H * xu;
    for (int r = 0; r < nf; ++r) x.row(F[size_t(r)]) = xf.row(r);
    for (int j = 0; j < nu; ++j) x.row(U[size_t(j)]) = xu.row(j);
  }
  return true;
}

// The 3D tangent vector v of triangle (e1, e2 from corner 0) expressed in its texture chart:
// v ~ a e1 + b e2 -> a g1 + b g2. False for a degenerate triangle.
bool ToTexture(float3 e1, float3 e2, float2 g1, float2 g2, float3 v, float2* out) {
  const double a11 = Dot(e1, e1), a12 = Dot(e1, e2), a22 = Dot(e2, e2);
  const double det = a11 * a22 - a12 * a12;
  if (!(det > 1e-30 * a11 * a22) || std::abs(g1.x * g2.y - g1.y * g2.x) < 1e-20f) return false;
  const double b1 = Dot(v, e1), b2 = Dot(v, e2);
  const double a = (a22 * b1 - a12 * b2) / det, b = (a11 * b2 - a12 * b1) / det;
  *out = float2{float(a * g1.x + b * g2.x), float(a * g1.y + b * g2.y)};
  return true;
}

float2 Unit2(float2 v) {
  const float l = std::sqrt(Dot2(v, v));
  return l > 1e-30f ? float2{v.x / l, v.y / l} : float2{0.f, 0.f};
}

}  // namespace

float MaxMagnitude(FurrowParameterSet set) {
  return set == FurrowParameterSet::kBando2001 ? 2.f : 1.f;
}

FurrowParams FurrowParamsFor(FurrowParameterSet set, float m, float k_scale) {
  const float top = MaxMagnitude(set);
  m = m > 0.f ? (m < top ? m : top) : 0.f;  // NaN -> 0
  FurrowParams p;
  if (set == FurrowParameterSet::kBando2001) {  // 003 eq. 5.1-5.6, x = m in [0, 2]
    p.segments = int(std::floor(30.f - 10.f * m));
    p.max_angle = 1.f - 0.4f * m;
    p.length = k_scale * (4.f + m);
    p.spacing = k_scale * (1.f + 6.f * m);
    p.width = k_scale * m;
    p.intensity = 1.f - 0.25f * m * m;  // f_depth = 0.25 x^2 is the depth below white
  } else {  // 000 eq. 1
    p.segments = int(std::floor(30.f - 20.f * m));
    p.max_angle = 0.5f - 0.4f * m;
    p.length = 4.f + 2.f * m;
    p.intensity = 1.f - m * m;
    p.width = 2.f * m;
    p.spacing = 1.f + 12.f * m;
  }
  return p;
}

bool ValidateFineScaleSpec(const FineScaleSpec& spec, size_t vertex_count,
                           const std::string& where, Diagnostics* diag) {
  bool ok = true;
  auto error = [&](const std::string& key, const std::string& what) {
    diag->Error(where + key, what);
    ok = false;
  };
  const float top = MaxMagnitude(spec.parameters);
  for (int f = 0; f < 2; ++f) {
    const std::string fw = ".fields[" + std::to_string(f) + "]";
    const DirectionFieldSpec& field = spec.fields[f];
    if (field.anchors.empty()) error(fw + ".anchors", "a direction field needs at least one vector");
    for (size_t i = 0; i < field.anchors.size(); ++i) {
      const DirectionAnchor& a = field.anchors[i];
      const std::string aw = fw + ".anchors[" + std::to_string(i) + "]";
      if (a.vertex >= vertex_count)
        error(aw + ".vertex", "vertex " + std::to_string(a.vertex) + " is out of range (the mesh has " +
                                  std::to_string(vertex_count) + " vertices)");
      if (!Finite(a.vector)) {
        error(aw + ".vector", "must be finite");
      } else {
        const float len = Length(a.vector);
        if (!(len > 1e-6f))
          error(aw + ".vector", "has zero length (the direction is undefined)");
        else if (len > top * 1.0001f)
          error(aw + ".vector", "magnitude " + std::to_string(len) + " exceeds " +
                                    std::to_string(top) + ", the largest of these parameters");
      }
      if (!(a.weight > 0.f) || !std::isfinite(a.weight)) error(aw + ".weight", "must be > 0 and finite");
    }
  }
  if (!(spec.k_scale > 0.f && spec.k_scale <= 16.f)) error(".k_scale", "must be in (0, 16]");
  if (!(spec.k_noise >= 0.f && spec.k_noise <= 1.f)) error(".k_noise", "must be in [0, 1]");
  if (!(spec.k_bump >= 0.f && spec.k_bump <= 64.f)) error(".k_bump", "must be in [0, 64]");
  if (!(spec.rest_amplitude >= 0.f && spec.rest_amplitude <= 1.f))
    error(".rest_amplitude", "must be in [0, 1]");
  return ok;
}

bool InterpolateDirectionField(const FineScaleMesh& mesh, span<const uint32_t> anchor_points,
                               span<const float3> anchor_vectors,
                               span<const float> anchor_weights, FieldInterpolation method,
                               const std::string& where, std::vector<float3>* out,
                               Diagnostics* diag) {
  const size_t n = mesh.points.size();
  if (anchor_points.empty() || anchor_points.size() != anchor_vectors.size()) {
    diag->Error(where, "a direction field needs at least one vector");
    return false;
  }
  for (size_t i = 0; i < anchor_points.size(); ++i) {
    if (anchor_points[i] >= n || !Finite(anchor_vectors[i])) {
      diag->Error(where + ".anchors[" + std::to_string(i) + "]",
                  "is out of range or not finite");
      return false;
    }
  }
  const std::vector<float3> normals = PointNormals(mesh);
  auto tangent = [&](uint32_t p, float3 v) { return v - Dot(v, normals[p]) * normals[p]; };
  out->assign(n, float3{});
  if (method == FieldInterpolation::kInverseDistance) {  // 003 eq. 3.1
    for (uint32_t p = 0; p < n; ++p) {
      double sx = 0, sy = 0, sz = 0, sw = 0;
      bool exact = false;
      for (size_t i = 0; i < anchor_points.size(); ++i) {
        const float d = Length(mesh.points[p] - mesh.points[anchor_points[i]]);
        if (d <= 0.f) {  // the anchor itself (or a point on it)
          (*out)[p] = anchor_vectors[i];
          exact = true;
          break;
        }
        const double w = (anchor_weights.size() > i ? anchor_weights[i] : 1.f) / d;
        sx += w * anchor_vectors[i].x;
        sy += w * anchor_vectors[i].y;
        sz += w * anchor_vectors[i].z;
        sw += w;
      }
      if (!exact) (*out)[p] = float3{float(sx / sw), float(sy / sw), float(sz / sw)};
    }
  } else {  // 000 §5.1: spring energy with the anchors fixed
    const FieldAnchors one{anchor_points, anchor_vectors, anchor_weights};
    std::vector<float3> fields[1];
    if (!InterpolateDirectionFields(mesh, span<const FieldAnchors>(&one, 1), method, where, fields,
                                    diag))
      return false;
    *out = std::move(fields[0]);
    return true;
  }
  for (uint32_t p = 0; p < n; ++p) (*out)[p] = tangent(p, (*out)[p]);
  return true;
}

bool InterpolateDirectionFields(const FineScaleMesh& mesh, span<const FieldAnchors> fields,
                                FieldInterpolation method, const std::string& where,
                                std::vector<float3>* out, Diagnostics* diag) {
  if (method == FieldInterpolation::kInverseDistance) {
    for (size_t k = 0; k < fields.size(); ++k)
      if (!InterpolateDirectionField(mesh, fields[k].points, fields[k].vectors, fields[k].weights,
                                     method, where, &out[k], diag))
        return false;
    return true;
  }
  const size_t n = mesh.points.size();
  std::vector<std::vector<uint32_t>> anchors(fields.size());
  std::vector<Eigen::MatrixXd> values(fields.size());
  for (size_t k = 0; k < fields.size(); ++k) {
    const FieldAnchors& f = fields[k];
    const std::string fw = fields.size() > 1 ? where + ".fields[" + std::to_string(k) + "]" : where;
    if (f.points.empty() || f.points.size() != f.vectors.size()) {
      diag->Error(fw, "a direction field needs at least one vector");
      return false;
    }
    values[k].resize(Eigen::Index(f.points.size()), 3);
    for (size_t i = 0; i < f.points.size(); ++i) {
      if (f.points[i] >= n || !Finite(f.vectors[i])) {
        diag->Error(fw + ".anchors[" + std::to_string(i) + "]", "is out of range or not finite");
        return false;
      }
      anchors[k].push_back(f.points[i]);
      values[k](Eigen::Index(i), 0) = f.vectors[i].x;
      values[k](Eigen::Index(i), 1) = f.vectors[i].y;
      values[k](Eigen::Index(i), 2) = f.vectors[i].z;
    }
  }
  std::vector<Eigen::MatrixXd> x;
  if (!HarmonicFields(mesh, anchors, values, &x)) {
    diag->Error(where, "the harmonic interpolation's sparse solve failed");
    return false;
  }
  const std::vector<float3> normals = PointNormals(mesh);
  for (size_t k = 0; k < fields.size(); ++k) {
    out[k].resize(n);
    for (uint32_t p = 0; p < n; ++p) {
      const float3 v{float(x[k](p, 0)), float(x[k](p, 1)), float(x[k](p, 2))};
      out[k][p] = v - Dot(v, normals[p]) * normals[p];
    }
  }
  return true;
}

bool MakeTextureSpace(const FineScaleMesh& mesh, TextureProjection projection,
                      bool minimize_distortion, const std::string& where,
                      std::vector<float2>* corner_uvs, Diagnostics* diag) {
  const size_t n = mesh.points.size(), corners = mesh.triangles.size();
  if (projection == TextureProjection::kAuto)
    projection = mesh.corner_uvs.size() == corners && corners > 0 ? TextureProjection::kUv
                                                                  : TextureProjection::kCylindrical;
  if (projection == TextureProjection::kUv) {
    if (mesh.corner_uvs.size() != corners || corners == 0) {
      diag->Error(where + ".texture_space", "\"uv\" needs texture coordinates, and the mesh has none");
      return false;
    }
    if (minimize_distortion) {
      diag->Error(where + ".minimize_distortion", "applies to a projection, not to the mesh's own uvs");
      return false;
    }
    corner_uvs->assign(mesh.corner_uvs.begin(), mesh.corner_uvs.end());
    return true;
  }
  float3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  for (float3 p : mesh.points) {
    lo = float3{std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = float3{std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  if (n == 0 || !(hi.y > lo.y)) {
    diag->Error(where + ".texture_space", "the mesh is empty or flat in y; nothing to project");
    return false;
  }
  const float3 c = (lo + hi) * 0.5f;
  std::vector<float2> uv(n);
  const float span_xy = std::max(hi.x - lo.x, hi.y - lo.y);
  for (size_t p = 0; p < n; ++p) {
    const float3 x = mesh.points[p];
    if (projection == TextureProjection::kPlanar) {
      uv[p] = float2{(x.x - c.x) / span_xy + 0.5f, 0.5f - (x.y - c.y) / span_xy};
    } else {  // 003 eq. 3.2 about the vertical axis through the box centre
      float s = std::atan2(x.x - c.x, x.z - c.z);  // 0 at +z, growing toward +x
      if (s < 0.f) s += 2.f * kPi;
      uv[p] = float2{s / (2.f * kPi), 1.f - (x.y - lo.y) / (hi.y - lo.y)};
    }
  }
  corner_uvs->resize(corners);
  bool seam = false;
  for (size_t t = 0; t + 2 < corners; t += 3) {
    for (int k = 0; k < 3; ++k) (*corner_uvs)[t + k] = uv[mesh.triangles[t + k]];
    if (projection == TextureProjection::kCylindrical) {
      // A triangle across the seam (u jumps by ~1): its corners in one chart, u past 1 (the
      // texture space wraps around, 000 §4).
      const float u0 = (*corner_uvs)[t].x;
      for (int k = 1; k < 3; ++k) {
        float& u = (*corner_uvs)[t + k].x;
        if (u - u0 > 0.5f) { u -= 1.f; seam = true; }
        if (u0 - u > 0.5f) { u += 1.f; seam = true; }
      }
    }
  }
  if (!minimize_distortion) return true;
  if (seam) {
    diag->Error(where + ".minimize_distortion",
                "needs a projection without a seam (the cylindrical one cuts this mesh); use "
                "\"planar\" or leave it off");
    return false;
  }
  // 000 §4: boundary points fixed, interior points harmonic.
  const CsrTable pt = BuildPointTriangles(mesh.triangles, n);
  std::vector<std::pair<uint64_t, int>> edge_count;
  for (size_t t = 0; t + 2 < corners; t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = mesh.triangles[t + k], b = mesh.triangles[t + (k + 1) % 3];
      edge_count.push_back({uint64_t(std::min(a, b)) << 32 | std::max(a, b), 1});
    }
  std::sort(edge_count.begin(), edge_count.end());
  std::vector<int> fixed(n, -1);
  std::vector<uint32_t> boundary;
  for (size_t i = 0; i < edge_count.size();) {
    size_t j = i;
    while (j < edge_count.size() && edge_count[j].first == edge_count[i].first) ++j;
    if (j - i == 1) {
      boundary.push_back(uint32_t(edge_count[i].first >> 32));
      boundary.push_back(uint32_t(edge_count[i].first));
    }
    i = j;
  }
  (void)pt;
  if (boundary.empty()) {
    diag->Error(where + ".minimize_distortion", "the mesh is closed (no boundary to hold fixed)");
    return false;
  }
  std::sort(boundary.begin(), boundary.end());
  boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
  Eigen::MatrixXd values(Eigen::Index(boundary.size()), 2);
  for (size_t i = 0; i < boundary.size(); ++i) {
    fixed[boundary[i]] = int(i);
    values(Eigen::Index(i), 0) = uv[boundary[i]].x;
    values(Eigen::Index(i), 1) = uv[boundary[i]].y;
  }
  Eigen::MatrixXd x;
  if (!HarmonicSolve(mesh, fixed, values, &x)) {
    diag->Error(where + ".minimize_distortion", "the harmonic map's sparse solve failed");
    return false;
  }
  for (size_t t = 0; t < corners; ++t) {
    const uint32_t p = mesh.triangles[t];
    (*corner_uvs)[t] = float2{float(x(p, 0)), float(x(p, 1))};
  }
  return true;
}

float2 TextureDirectionAt(const FineScaleMesh& mesh, span<const float2> corner_uvs,
                          span<const uint32_t> offsets, span<const uint32_t> tris,
                          span<const float3> field, uint32_t point) {
  if (point + 1 >= offsets.size() || point >= field.size()) return {0.f, 0.f};
  for (uint32_t k = offsets[point]; k < offsets[point + 1]; ++k) {
    const size_t t = tris[k];
    if (3 * t + 2 >= mesh.triangles.size() || 3 * t + 2 >= corner_uvs.size()) continue;
    int c = 0;
    while (c < 3 && mesh.triangles[3 * t + c] != point) ++c;
    if (c == 3) continue;
    const uint32_t a = mesh.triangles[3 * t + c], b = mesh.triangles[3 * t + (c + 1) % 3],
                   d = mesh.triangles[3 * t + (c + 2) % 3];
    const float2 ua = corner_uvs[3 * t + c], ub = corner_uvs[3 * t + (c + 1) % 3],
                 ud = corner_uvs[3 * t + (c + 2) % 3];
    float2 v;
    if (ToTexture(mesh.points[b] - mesh.points[a], mesh.points[d] - mesh.points[a], Sub2(ub, ua),
                  Sub2(ud, ua), field[point], &v))
      return Unit2(v);
  }
  return {0.f, 0.f};
}

namespace {

// The pixels x of each row whose centres can pass the barycentric test of RasterizeInto:
// each barycentric is linear, w_k(X, Y) = (u_k(Y) + v_k X) inv with u_k linear in Y, so its
// bound w_k >= eps is X >= or <= A_k + B_k Y (in double, set up once per triangle); the span
// is widened by a pixel each way so that float rounding of the exact test never finds a pixel
// outside it. The test itself decides, as before.
class RowSpans {
 public:
  RowSpans(const float2 px[3], float inv, float eps) {
    const double lo_eps = double(eps) - 1e-4;
    for (int k = 0; k < 3; ++k) {
      const float2 a = px[(k + 1) % 3], b = px[(k + 2) % 3];
      // w_k = ((a.x - X)(b.y - Y) - (b.x - X)(a.y - Y)) inv = (u0 + u1 Y + v X) inv
      const double u0 = (double(a.x) * b.y - double(b.x) * a.y) * inv;
      const double u1 = (double(b.x) - double(a.x)) * inv;
      const double v = (double(a.y) - double(b.y)) * inv;
      Bound& e = bounds_[k];
      if (v > 1e-12 || v < -1e-12) {
        e.kind = v > 0 ? 1 : -1;  // X >= (lo_eps - u) / v, or <= for v < 0
        e.a = (lo_eps - u0) / v;
        e.b = -u1 / v;
      } else {
        e.kind = 0;  // w_k does not change along a row: the row passes or misses whole
        e.a = u0 - (lo_eps - 1e-3);
        e.b = u1;
      }
    }
  }
  // Narrows [*x0, *x1] to row y's span (empty: *x1 < *x0).
  void Row(int y, int* x0, int* x1) const {
    const double py = y + 0.5;
    double lo = -1e9, hi = 1e9;
    for (const Bound& e : bounds_) {
      const double t = e.a + e.b * py;
      if (e.kind > 0) lo = std::max(lo, t);
      else if (e.kind < 0) hi = std::min(hi, t);
      else if (t < 0.0) hi = -1e9;
    }
    if (!(hi >= lo)) { *x1 = *x0 - 1; return; }
    *x0 = std::max(*x0, Floor(lo - 0.5) - 1);
    *x1 = std::min(*x1, -Floor(-(hi - 0.5)) + 1);
  }

 private:
  static int Floor(double v) {  // v in [-1e9 - 1, 1e9 + 1]
    const int i = int(v);
    return i - (v < double(i) ? 1 : 0);
  }
  struct Bound {
    int kind;
    double a, b;
  };
  Bound bounds_[3];
};

// Rasterises every field of `fields` into out[f] in one walk over the triangles (the same
// barycentrics for all), in triangle order, so each image is what one field alone would give.
void RasterizeInto(const FineScaleMesh& mesh, span<const float2> corner_uvs,
                   span<const span<const float3>> fields, int size, FieldImage* out) {
  const size_t pixels = size_t(size) * size_t(size);
  const size_t nf = fields.size();
  for (size_t f = 0; f < nf; ++f) {
    out[f].size = size;
    out[f].direction.assign(pixels, float2{0.f, 0.f});
    out[f].magnitude.assign(pixels, 0.f);
    out[f].mapped.assign(pixels, 0);
  }
  constexpr size_t kMaxFields = 2;
  if (nf == 0 || nf > kMaxFields) return;
  const float fs = float(size);
  for (size_t t = 0; 3 * t + 2 < mesh.triangles.size() && 3 * t + 2 < corner_uvs.size(); ++t) {
    const uint32_t c[3] = {mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]};
    float2 px[3];
    for (int k = 0; k < 3; ++k)
      px[k] = float2{corner_uvs[3 * t + k].x * fs, corner_uvs[3 * t + k].y * fs};
    const float area = (px[1].x - px[0].x) * (px[2].y - px[0].y) - (px[2].x - px[0].x) * (px[1].y - px[0].y);
    if (!(std::abs(area) > 1e-12f)) continue;
    // Each field's corner vectors in this triangle's chart (unit direction times magnitude).
    float2 vec[kMaxFields][3];
    float mag[kMaxFields][3];
    bool draw[kMaxFields] = {};
    bool any = false;
    for (size_t f = 0; f < nf; ++f) {
      const span<const float3> field = fields[f];
      if (c[0] >= field.size() || c[1] >= field.size() || c[2] >= field.size()) continue;
      const float3 e1 = mesh.points[c[1]] - mesh.points[c[0]], e2 = mesh.points[c[2]] - mesh.points[c[0]];
      const float2 g1 = Sub2(px[1], px[0]), g2 = Sub2(px[2], px[0]);
      bool ok = true;
      for (int k = 0; k < 3; ++k) {
        float2 v;
        ok = ok && ToTexture(e1, e2, g1, g2, field[c[k]], &v);
        mag[f][k] = Length(field[c[k]]);
        const float2 u = Unit2(v);
        vec[f][k] = float2{u.x * mag[f][k], u.y * mag[f][k]};
      }
      draw[f] = ok;
      any = any || ok;
    }
    if (!any) continue;
    const float minx = std::min({px[0].x, px[1].x, px[2].x}), maxx = std::max({px[0].x, px[1].x, px[2].x});
    const float miny = std::min({px[0].y, px[1].y, px[2].y}), maxy = std::max({px[0].y, px[1].y, px[2].y});
    const int bx0 = std::max(0, int(std::floor(minx - 0.5f))), bx1 = std::min(size - 1, int(std::ceil(maxx)));
    const int y0 = std::max(0, int(std::floor(miny - 0.5f))), y1 = std::min(size - 1, int(std::ceil(maxy)));
    const float inv = 1.f / area, eps = -1e-5f;
    const RowSpans spans(px, inv, eps);
    for (int y = y0; y <= y1; ++y) {
      int x0 = bx0, x1 = bx1;
      spans.Row(y, &x0, &x1);
      int x = x0;
#if defined(__SSE2__)
      // Four pixels at a time: the scalar operations below in the same order in each lane
      // (IEEE products, sums, square roots and quotients), so the same bits.
      const __m128 fpy = _mm_set1_ps(y + 0.5f), veps = _mm_set1_ps(eps), vone = _mm_set1_ps(1.f);
      const __m128 vinv = _mm_set1_ps(inv), tiny = _mm_set1_ps(1e-30f);
      const __m128 a0y = _mm_sub_ps(_mm_set1_ps(px[0].y), fpy), a1y = _mm_sub_ps(_mm_set1_ps(px[1].y), fpy);
      const __m128 a2y = _mm_sub_ps(_mm_set1_ps(px[2].y), fpy);
      // The last group may reach past x1 (its lanes there are masked off: they rewrite what
      // is there) but never past the image.
      for (; x <= x1 && size_t(y) * size_t(size) + size_t(x) + 3 < pixels; x += 4) {
        const __m128 fpx = _mm_add_ps(_mm_cvtepi32_ps(_mm_add_epi32(_mm_set1_epi32(x), _mm_setr_epi32(0, 1, 2, 3))),
                                      _mm_set1_ps(0.5f));  // x + 0.5f, as below
        const __m128 a0x = _mm_sub_ps(_mm_set1_ps(px[0].x), fpx), a1x = _mm_sub_ps(_mm_set1_ps(px[1].x), fpx);
        const __m128 a2x = _mm_sub_ps(_mm_set1_ps(px[2].x), fpx);
        const __m128 w0 = _mm_mul_ps(_mm_sub_ps(_mm_mul_ps(a1x, a2y), _mm_mul_ps(a2x, a1y)), vinv);
        const __m128 w1 = _mm_mul_ps(_mm_sub_ps(_mm_mul_ps(a2x, a0y), _mm_mul_ps(a0x, a2y)), vinv);
        const __m128 w2 = _mm_sub_ps(_mm_sub_ps(vone, w0), w1);
        // !(w < eps) for all three (NaN draws, as the scalar test lets it through).
        const __m128i lane = _mm_add_epi32(_mm_set1_epi32(x), _mm_setr_epi32(0, 1, 2, 3));
        const __m128 valid = _mm_castsi128_ps(_mm_cmplt_epi32(lane, _mm_set1_epi32(x1 + 1)));
        const __m128 in = _mm_and_ps(
            valid, _mm_and_ps(_mm_and_ps(_mm_cmpnlt_ps(w0, veps), _mm_cmpnlt_ps(w1, veps)),
                              _mm_cmpnlt_ps(w2, veps)));
        const int bits = _mm_movemask_ps(in);
        if (bits == 0) continue;
        const size_t i = size_t(y) * size_t(size) + size_t(x);
        for (size_t f = 0; f < nf; ++f) {
          if (!draw[f]) continue;
          const float2* v = vec[f];
          const float* m = mag[f];
          auto lerp = [&](float c0, float c1, float c2) {
            return _mm_add_ps(_mm_add_ps(_mm_mul_ps(w0, _mm_set1_ps(c0)), _mm_mul_ps(w1, _mm_set1_ps(c1))),
                              _mm_mul_ps(w2, _mm_set1_ps(c2)));
          };
          const __m128 dx = lerp(v[0].x, v[1].x, v[2].x), dy = lerp(v[0].y, v[1].y, v[2].y);
          const __m128 mg = lerp(m[0], m[1], m[2]);
          const __m128 l = _mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)));
          const __m128 ok = _mm_cmpgt_ps(l, tiny);
          const __m128 ux = _mm_and_ps(ok, _mm_div_ps(dx, l)), uy = _mm_and_ps(ok, _mm_div_ps(dy, l));
          auto blend = [&](float* at, __m128 val, __m128 mask) {
            const __m128 old = _mm_loadu_ps(at);
            _mm_storeu_ps(at, _mm_or_ps(_mm_and_ps(mask, val), _mm_andnot_ps(mask, old)));
          };
          float* d = &out[f].direction[i].x;
          blend(d, _mm_unpacklo_ps(ux, uy), _mm_unpacklo_ps(in, in));
          blend(d + 4, _mm_unpackhi_ps(ux, uy), _mm_unpackhi_ps(in, in));
          blend(&out[f].magnitude[i], mg, in);
          for (int k = 0; k < 4; ++k)
            if (bits >> k & 1) out[f].mapped[i + size_t(k)] = 1;
        }
      }
#endif
      for (; x <= x1; ++x) {
        const float2 p{x + 0.5f, y + 0.5f};
        const float w0 = ((px[1].x - p.x) * (px[2].y - p.y) - (px[2].x - p.x) * (px[1].y - p.y)) * inv;
        const float w1 = ((px[2].x - p.x) * (px[0].y - p.y) - (px[0].x - p.x) * (px[2].y - p.y)) * inv;
        const float w2 = 1.f - w0 - w1;
        if (w0 < eps || w1 < eps || w2 < eps) continue;
        const size_t i = size_t(y) * size_t(size) + size_t(x);
        for (size_t f = 0; f < nf; ++f) {
          if (!draw[f]) continue;
          const float2* v = vec[f];
          const float* m = mag[f];
          out[f].direction[i] = Unit2(float2{w0 * v[0].x + w1 * v[1].x + w2 * v[2].x,
                                             w0 * v[0].y + w1 * v[1].y + w2 * v[2].y});
          out[f].magnitude[i] = w0 * m[0] + w1 * m[1] + w2 * m[2];
          out[f].mapped[i] = 1;
        }
      }
    }
  }
}

}  // namespace

FieldImage RasterizeField(const FineScaleMesh& mesh, span<const float2> corner_uvs,
                          span<const float3> field, int size) {
  FieldImage img;
  const span<const float3> one[1] = {field};
  RasterizeInto(mesh, corner_uvs, one, size, &img);
  return img;
}

void RasterizeFields(const FineScaleMesh& mesh, span<const float2> corner_uvs,
                     span<const float3> field1, span<const float3> field2, int size,
                     FieldImage out[2]) {
  const span<const float3> two[2] = {field1, field2};
  RasterizeInto(mesh, corner_uvs, two, size, out);
}

namespace {

// Segments bucketed on a coarse grid, for the crossing test. A segment is listed in every
// cell its bounding box touches, so two segments whose boxes overlap share a cell (the cell
// of any point of the overlap: floor is monotone), and a query over PQ's box sees every
// segment that can cross PQ. Each cell keeps its segments' geometry in blocks of
// kBlock (128 bytes), newest block first: a query reads a cell's few blocks, not one scattered
// record per segment.
class SegmentGrid {
 public:
  SegmentGrid(int size, int cell) : cell_(cell), cells_((size + cell - 1) / cell) {
    head_.assign(size_t(cells_) * size_t(cells_), -1);
  }
  void Add(const FurrowSegment& s) {
    ForCells(s.p, s.q, [&](size_t c) {
      int32_t b = head_[c];
      if (b < 0 || blocks_[size_t(b)].count == kBlock) {
        blocks_.push_back(Block{b, 0, {}});
        b = head_[c] = int32_t(blocks_.size() - 1);
      }
      Block& block = blocks_[size_t(b)];
      block.segments[block.count++] = s;
    });
  }
  template <class Fn>
  void Visit(float2 p, float2 q, const Fn& fn) const {
    ForCells(p, q, [&](size_t c) {
      for (int32_t b = head_[c]; b >= 0; b = blocks_[size_t(b)].next) {
        const Block& block = blocks_[size_t(b)];
        for (uint32_t k = 0; k < block.count; ++k) fn(block.segments[k]);
      }
    });
  }

 private:
  template <class Fn>
  void ForCells(float2 p, float2 q, const Fn& fn) const {
    auto cell = [&](float v) { return FloorIn(v / float(cell_), 0, cells_ - 1); };
    const int x0 = cell(std::min(p.x, q.x)), x1 = cell(std::max(p.x, q.x));
    const int y0 = cell(std::min(p.y, q.y)), y1 = cell(std::max(p.y, q.y));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) fn(size_t(y) * size_t(cells_) + size_t(x));
  }
  static constexpr uint32_t kBlock = 6;
  struct Block {
    int32_t next;
    uint32_t count;
    FurrowSegment segments[kBlock];
  };
  int cell_, cells_;
  std::vector<int32_t> head_;
  std::vector<Block> blocks_;
};

// Parameter t in [0, 1] along pq where it crosses ab, or -1.
float Crossing(float2 p, float2 q, float2 a, float2 b) {
  const float2 r = Sub2(q, p), s = Sub2(b, a), ap = Sub2(a, p);
  const float den = r.x * s.y - r.y * s.x;
  if (std::abs(den) < 1e-12f) return -1.f;  // parallel: never a crossing
  const float t = (ap.x * s.y - ap.y * s.x) / den, u = (ap.x * r.y - ap.y * r.x) / den;
  return t >= 0.f && t <= 1.f && u >= 0.f && u <= 1.f ? t : -1.f;
}

struct Carver {
  const FieldImage& field;
  const CarveOptions& options;
  CarveResult* out;
  int size;
  // Occupancy and the mapped area as bitmaps (bit x % 64 of word x / 64 of a row): 512 kB
  // each at 2048 x 2048, so both stay in cache while furrows wander over the image. Padding
  // bits past a row's end read occupied and unmapped.
  size_t words = 0;  // per row
  std::vector<uint64_t> occupied, mapped;
  SegmentGrid grid;
  // This field's segments (the crossing test reads the grid's own copies).
  std::vector<FurrowSegment> segments;
  std::mt19937_64 rng;
  std::uniform_real_distribution<float> unit{-1.f, 1.f};

  Carver(const FieldImage& f, const CarveOptions& o, CarveResult* r)
      : field(f), options(o), out(r), size(f.size), grid(f.size, 8), rng(o.seed) {
    words = (size_t(size) + 63) / 64;
    occupied.assign(words * size_t(size), ~uint64_t(0));
    mapped.assign(words * size_t(size), 0);
    for (size_t y = 0; y < size_t(size); ++y)
      for (size_t x = 0; x < size_t(size); ++x)
        if (f.mapped[y * size_t(size) + x]) {
          occupied[y * words + x / 64] &= ~(uint64_t(1) << (x % 64));
          mapped[y * words + x / 64] |= uint64_t(1) << (x % 64);
        }
  }
  // Every pixel of [x0, x1] x [y0, y1] is mapped (false when the box leaves the image).
  bool AllMapped(int x0, int y0, int x1, int y1) const {
    if (x0 < 0 || y0 < 0 || x1 >= size || y1 >= size) return false;
    for (int y = y0; y <= y1; ++y) {
      const uint64_t* row = &mapped[size_t(y) * words];
      for (int w = x0 / 64; w <= x1 / 64; ++w) {
        const int lo = std::max(x0, w * 64) - w * 64, hi = std::min(x1, w * 64 + 63) - w * 64;
        const uint64_t mask = (~uint64_t(0) >> (63 - hi)) & (~uint64_t(0) << lo);
        if ((row[w] & mask) != mask) return false;
      }
    }
    return true;
  }
  bool Occupied(size_t x, size_t y) const { return (occupied[y * words + x / 64] >> (x % 64)) & 1; }
  // Sets bits [x0, x1] of row y.
  void Occupy(size_t y, int x0, int x1) {
    uint64_t* row = &occupied[y * words];
    for (int w = x0 / 64; w <= x1 / 64; ++w) {
      const int lo = std::max(x0, w * 64) - w * 64, hi = std::min(x1, w * 64 + 63) - w * 64;
      row[w] |= (~uint64_t(0) >> (63 - hi)) & (~uint64_t(0) << lo);
    }
  }

  bool Inside(float2 p) const {
    if (!(p.x >= 0.f && p.y >= 0.f && p.x < float(size) && p.y < float(size))) return false;
    const size_t x = size_t(int(p.x));
    return (mapped[size_t(int(p.y)) * words + x / 64] >> (x % 64)) & 1;
  }
  size_t Pixel(float2 p) const { return size_t(int(p.y)) * size_t(size) + size_t(int(p.x)); }

  // Box-filtered coverage of a pixel centre at distance d from a line of width w.
  static float Coverage(float d, float w) {
    const float h = 0.5f * w;
    return std::clamp(std::min(d + 0.5f, h) - std::max(d - 0.5f, -h), 0.f, 1.f);
  }

  // Draws segment PQ: occupancy at every pixel centre within W_o of it, height with width
  // W_h. Each is drawn over the rows of the rectangle {a in [a_lo, L + R], |b| <= R} around PQ
  // (a along PQ from P, b across, R its reach: W_o for the occupancy, the height band W_h / 2 +
  // 1/2 for the height), which holds its capsule. With `prev` (the segment that ended at P, of
  // this furrow) no larger in W_o, W_h and depth, everything within reach of P is already
  // drawn at least as strongly (min / or of smaller values leaves it), so a_lo = 0; else
  // a_lo = -R. The same image either way. A capsule meets a row in one run of pixels (it is
  // convex): the occupancy tests pixels inward from the rectangle's ends and sets the run
  // between the first that pass; the height tests every pixel of the band's run.
  void Draw(float2 p, float2 q, const FurrowParams& fp, const FurrowParams* prev) {
    const float band = 0.5f * fp.width + 0.5f, band2 = band * band;
    const float occ2 = fp.spacing * fp.spacing;
    const float depth = 1.f - fp.intensity;
    float* h = out->height.data();
    const float2 dq = Sub2(q, p);
    const float l2 = Dot2(dq, dq), len = std::sqrt(l2), inv = l2 > 0.f ? 1.f / l2 : 0.f;
    const bool covered = prev && fp.spacing <= prev->spacing && fp.width <= prev->width &&
                         depth <= 1.f - prev->intensity;
    const float2 u = len > 1e-6f ? float2{dq.x / len, dq.y / len} : float2{1.f, 0.f};
    const float2 n{-u.y, u.x};
    auto d2_at = [&](int x, float cy) {
      const float cx = x + 0.5f - p.x;
      const float t = std::clamp((cx * dq.x + cy * dq.y) * inv, 0.f, 1.f);
      const float ex = cx - t * dq.x, ey = cy - t * dq.y;
      return ex * ex + ey * ey;
    };
    // Calls row(y, cy, x0, x1) for each row's pixel run of the rectangle with reach `reach`.
    auto rect_rows = [&](float reach, const auto& row) {
      const float a_lo = (covered && len > 1e-6f ? 0.f : -reach) - 1e-3f, a_hi = len + reach + 1e-3f;
      const float b_hi = reach + 1e-3f;
      const int y0 = FloorIn(std::min(p.y, q.y) - reach - 0.5f, 0, size);
      const int y1 = CeilIn(std::max(p.y, q.y) + reach, -1, size - 1);
      // x - p.x in [lo, hi] from both slabs, mn <= cx X + cyc cy <= mx: X between
      // (mn - k) / cx and (mx - k) / cx, k = cy cyc, by a reciprocal set up once (a coefficient
      // near 0 leaves its slab a test on cy). The bounds only need to hold the capsule, 1e-3
      // wide of it, and the a >= 0 cut of a covered start, where what is left out was drawn.
      struct Slab {
        float cyc, mn, mx, ic;
        bool along;  // |cx| > 1e-6
      };
      auto make_slab = [](float cx, float cyc, float mn, float mx) {
        const bool along = std::fabs(cx) > 1e-6f;
        const float ic = along ? 1.f / cx : 0.f;
        return ic < 0.f ? Slab{cyc, mx, mn, ic, along} : Slab{cyc, mn, mx, ic, along};
      };
      const Slab slabs[2] = {make_slab(u.x, u.y, a_lo, a_hi), make_slab(n.x, n.y, -b_hi, b_hi)};
      for (int y = y0; y <= y1; ++y) {
        const float cy = y + 0.5f - p.y;
        float lo = -1e30f, hi = 1e30f;
        for (const Slab& sl : slabs) {
          const float k = cy * sl.cyc;
          if (sl.along) {
            lo = std::max(lo, (sl.mn - k) * sl.ic);
            hi = std::min(hi, (sl.mx - k) * sl.ic);
          } else if (k < std::min(sl.mn, sl.mx) || k > std::max(sl.mn, sl.mx)) {
            hi = -1e30f;
          }
        }
        if (!(hi >= lo)) continue;
        const int x0 = CeilIn(p.x + lo - 0.5f, 0, size);
        const int x1 = FloorIn(p.x + hi - 0.5f, -1, size - 1);
        if (x0 <= x1) row(y, cy, x0, x1);
      }
    };
    rect_rows(fp.spacing, [&](int y, float cy, int x0, int x1) {
      while (x0 <= x1 && !(d2_at(x0, cy) <= occ2)) ++x0;
      while (x1 >= x0 && !(d2_at(x1, cy) <= occ2)) --x1;
      if (x0 <= x1) Occupy(size_t(y), x0, x1);
    });
    if (!(depth > 0.f)) return;
    rect_rows(band, [&](int y, float cy, int x0, int x1) {
      float* hr = h + size_t(y) * size_t(size);
      for (int x = x0; x <= x1; ++x) {
        const float d2 = d2_at(x, cy);
        if (d2 < band2) {
          const float cov = Coverage(std::sqrt(d2), fp.width);
          if (cov > 0.f) hr[x] = std::min(hr[x], 1.f - depth * cov);
        }
      }
    });
  }

  // One side of a furrow from `start` along sign * d (000 §5.2 steps 1-7).
  FurrowSide Grow(uint32_t id, float2 start, float sign, FurrowParams* last) {
    FurrowSide side;
    float2 p = start, prev{0.f, 0.f};
    long n = std::numeric_limits<long>::max();
    for (;;) {
      const size_t pix = Pixel(p);
      float2 d = field.direction[pix];  // step 1 (the pixel's interpolated direction)
      const float m = field.magnitude[pix];
      if (Dot2(d, d) == 0.f) { side.end = FurrowEnd::kNoField; break; }
      if (side.segments == 0) d = float2{sign * d.x, sign * d.y};
      else if (Dot2(d, prev) < 0.f) d = float2{-d.x, -d.y};  // keep going the same way
      const FurrowParams fp = FurrowParamsFor(options.parameters, m, options.k_scale);
      n = std::min(n, long(fp.segments));  // step 2
      const float theta = fp.max_angle * unit(rng);  // step 3
      const float cs = std::cos(theta), sn = std::sin(theta);
      d = float2{cs * d.x - sn * d.y, sn * d.x + cs * d.y};
      float2 q{p.x + fp.length * d.x, p.y + fp.length * d.y};  // step 4
      // Where the next step reads and this segment's height band writes, asked for early
      // (the border walk and the crossing test come first): cache misses, not arithmetic,
      // are most of the carving's time.
      if (q.x >= 0.f && q.y >= 0.f && q.x < float(size) && q.y < float(size)) {
        const size_t next = Pixel(q);
        __builtin_prefetch(&field.direction[next]);
        __builtin_prefetch(&field.magnitude[next]);
        const float band = 0.5f * fp.width + 0.5f;
        const int x = int(0.5f * (p.x + q.x));
        const int ya = std::max(0, int(std::min(p.y, q.y) - band)), yb = std::min(size - 1, int(std::max(p.y, q.y) + band));
        for (int y = ya; y <= yb; ++y) __builtin_prefetch(&out->height[size_t(y) * size_t(size) + size_t(x)], 1);
      }
      FurrowEnd end = FurrowEnd::kBudget;
      // The border: the last sample inside the mapped area, 1/4 pixel steps. Skipped when
      // every pixel of PQ's box, a pixel wider, is mapped (then every sample is inside).
      const int steps = CeilIn(fp.length * 4.f, 1, 1 << 24);
      const bool all_mapped = AllMapped(FloorIn(std::min(p.x, q.x) - 1.f, -1, size), FloorIn(std::min(p.y, q.y) - 1.f, -1, size),
                                        FloorIn(std::max(p.x, q.x) + 1.f, -1, size), FloorIn(std::max(p.y, q.y) + 1.f, -1, size));
      for (int k = 1; k <= steps && !all_mapped; ++k) {
        const float t = float(k) / float(steps);
        const float2 s{p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
        if (!Inside(s)) {
          const float tb = float(k - 1) / float(steps);
          q = float2{p.x + tb * (q.x - p.x), p.y + tb * (q.y - p.y)};
          end = FurrowEnd::kBorder;
          break;
        }
      }
      // The nearest crossing of another furrow's centre line.
      float best = 2.f;
      const float bx0 = std::min(p.x, q.x), bx1 = std::max(p.x, q.x);
      const float by0 = std::min(p.y, q.y), by1 = std::max(p.y, q.y);
      grid.Visit(p, q, [&](const FurrowSegment& g) {
        if (g.furrow == id) return;
        // Bounding boxes first (most candidates in a cell are nowhere near PQ).
        if (std::max(g.p.x, g.q.x) < bx0 || std::min(g.p.x, g.q.x) > bx1 ||
            std::max(g.p.y, g.q.y) < by0 || std::min(g.p.y, g.q.y) > by1)
          return;
        const float t = Crossing(p, q, g.p, g.q);
        if (t >= 0.f && t < best) best = t;
      });
      if (best <= 1.f) {
        q = float2{p.x + best * (q.x - p.x), p.y + best * (q.y - p.y)};
        end = FurrowEnd::kCrossing;
      }
      if (end != FurrowEnd::kBudget) n = 0;
      Draw(p, q, fp, side.segments ? last : start_params_);  // steps 5-6
      *last = fp;
      if (side.segments == 0 && sign > 0.f) first_params_ = fp;
      segments.push_back({p, q, id});
      grid.Add(segments.back());
      ++side.segments;
      side.end = end;
      prev = d;
      if (n == 0) break;  // step 7
      p = q;
      --n;
      if (!Inside(p)) { side.end = FurrowEnd::kBorder; break; }
    }
    side.end_point = side.segments ? segments.back().q : start;
    return side;
  }

  void Start(float2 start) {
    const uint32_t id = uint32_t(out->furrows.size() + furrow_count_);
    Furrow f;
    f.start = start;
    f.start_magnitude = field.magnitude[Pixel(start)];
    f.first_segment = uint32_t(segments.size());
    FurrowParams last;
    start_params_ = nullptr;  // nothing drawn around the start yet
    f.sides[0] = Grow(id, start, 1.f, &last);
    // The -d side starts where the +d side's first segment started (its parameters, when it
    // drew one, cover the start).
    start_params_ = f.sides[0].segments ? &first_params_ : nullptr;
    f.sides[1] = Grow(id, start, -1.f, &last);
    f.segment_count = uint32_t(segments.size()) - f.first_segment;
    if (options.record) out->furrows.push_back(f);
    else ++furrow_count_;
  }
  size_t furrow_count_ = 0;
  const FurrowParams* start_params_ = nullptr;
  FurrowParams first_params_;

  void Run() {
    const size_t pixels = size_t(size) * size_t(size);
    out->size = size;
    out->height.assign(pixels, 1.f);
    out->furrows.clear();
    out->segments.clear();
    size_t mapped_pixels = 0;
    for (uint8_t m : field.mapped) mapped_pixels += m;
    if (mapped_pixels == 0) return;
    // Random starts (pixel centres) until max_failures picks in a row are occupied.
    std::uniform_int_distribution<size_t> pick(0, pixels - 1);
    uint32_t failures = 0;
    while (failures < options.max_failures) {
      const size_t i = pick(rng);
      if (Occupied(i % size_t(size), i / size_t(size))) { ++failures; continue; }
      failures = 0;
      Start(float2{float(i % size_t(size)) + 0.5f, float(i / size_t(size)) + 0.5f});
      ++out->random_starts;
    }
    if (options.progress) options.progress(0.5f);
    // Then every pixel still free.
    for (int y = 0; y < size; ++y) {
      const uint64_t* row = &occupied[size_t(y) * words];
      for (size_t w = 0; w < words; ++w) {
        // The free bits of this word from `from` on, read again after each start (a furrow
        // may occupy pixels ahead of the scan).
        for (uint32_t from = 0; from < 64;) {
          const uint64_t free = ~row[w] & (~uint64_t(0) << from);
          if (!free) break;
          const uint32_t bit = uint32_t(__builtin_ctzll(free));
          Start(float2{float(w * 64 + bit) + 0.5f, y + 0.5f});
          ++out->scan_starts;
          from = bit + 1;
        }
      }
      if (options.progress && (y & 63) == 63) options.progress(0.5f + 0.5f * float(y + 1) / float(size));
    }
    if (options.record) out->segments = std::move(segments);
  }
};

}  // namespace

void CarveFurrows(const FieldImage& field, const CarveOptions& options, CarveResult* out) {
  *out = CarveResult();
  if (field.size <= 0) return;
  Carver c(field, options, out);
  c.Run();
}

bool InterpolateSpecFields(const FineScaleSpec& spec, const FineScaleMesh& mesh,
                           const std::vector<uint32_t> anchor_points[2], std::vector<float3> out[2],
                           Diagnostics* diag) {
  std::vector<float3> vectors[2];
  std::vector<float> weights[2];
  FieldAnchors anchors[2];
  for (int f = 0; f < 2; ++f) {
    for (const DirectionAnchor& a : spec.fields[f].anchors) {
      vectors[f].push_back(a.vector);
      weights[f].push_back(a.weight);
    }
    anchors[f] = {anchor_points[f], vectors[f], weights[f]};
  }
  return InterpolateDirectionFields(mesh, anchors, spec.interpolation, "fine_scale", out, diag);
}

void AddHeightNoise(float k_noise, uint64_t seed, std::vector<float>* height) {
  if (!(k_noise > 0.f)) return;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (float& h : *height) h = std::max(0.f, h - k_noise * unit(rng));
}

namespace {

// lround(v) for finite v >= 0 (half away from zero): v - trunc(v) is exact in float.
inline int RoundNonNegative(float v) {
  const int r = int(v);
  return r + (v - float(r) >= 0.5f ? 1 : 0);
}

// One texel of the bump normal map from its four neighbours' heights (the normal of
// (-k dx, k dy, 1), normalised as NormalizeOr does, each component to [0, 255]). A NaN or
// infinite slope (heights that are not finite) gives the flat normal (0, 0, 1).
inline void BumpTexel(float left, float right, float up, float down, float k_bump, uint8_t* o) {
  const float dx = 0.5f * (right - left), dy = 0.5f * (down - up);
  const float nx = -k_bump * dx, ny = k_bump * dy, nz = 1.f;
  const float len2 = nx * nx + ny * ny + nz * nz;
  float3 n{0.f, 0.f, 1.f};
  if (len2 > 1e-30f && len2 < std::numeric_limits<float>::infinity()) {
    const float s = 1.f / std::sqrt(len2);
    n = float3{nx * s, ny * s, nz * s};
  }
  o[0] = uint8_t(RoundNonNegative(127.5f * (n.x + 1.f)));
  o[1] = uint8_t(RoundNonNegative(127.5f * (n.y + 1.f)));
  o[2] = uint8_t(RoundNonNegative(127.5f * (n.z + 1.f)));
}

}  // namespace

std::vector<uint8_t> BumpNormalMap(span<const float> height, int size, float k_bump, int threads) {
  std::vector<uint8_t> out(size_t(size) * size_t(size) * 3);
  // Central differences, clamped at the border (the edge texel stands in for its missing
  // neighbour).
  auto rows = [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      const float* up = &height[size_t(std::max(y - 1, 0)) * size_t(size)];
      const float* row = &height[size_t(y) * size_t(size)];
      const float* down = &height[size_t(std::min(y + 1, size - 1)) * size_t(size)];
      uint8_t* o = &out[3 * size_t(y) * size_t(size)];
      auto texel = [&](int x) {
        const int l = x > 0 ? x - 1 : 0, r = x + 1 < size ? x + 1 : size - 1;
        BumpTexel(row[l], row[r], up[x], down[x], k_bump, o + 3 * size_t(x));
      };
      texel(0);
      int x = 1;
#if defined(__SSE2__)
      // Four texels at a time: BumpTexel's operations in each lane (the same bits).
      const __m128 half = _mm_set1_ps(0.5f), nk = _mm_set1_ps(-k_bump), k = _mm_set1_ps(k_bump);
      const __m128 one = _mm_set1_ps(1.f), tiny = _mm_set1_ps(1e-30f), inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
      const __m128 scale = _mm_set1_ps(127.5f);
      for (; x + 4 < size; x += 4) {
        const __m128 dx = _mm_mul_ps(half, _mm_sub_ps(_mm_loadu_ps(row + x + 1), _mm_loadu_ps(row + x - 1)));
        const __m128 dy = _mm_mul_ps(half, _mm_sub_ps(_mm_loadu_ps(down + x), _mm_loadu_ps(up + x)));
        const __m128 nx = _mm_mul_ps(nk, dx), ny = _mm_mul_ps(k, dy);
        const __m128 len2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, nx), _mm_mul_ps(ny, ny)), _mm_mul_ps(one, one));
        const __m128 ok = _mm_and_ps(_mm_cmpgt_ps(len2, tiny), _mm_cmplt_ps(len2, inf));
        const __m128 sc = _mm_div_ps(one, _mm_sqrt_ps(len2));
        // Not ok: (0, 0, 1).
        const __m128 c[3] = {_mm_and_ps(ok, _mm_mul_ps(nx, sc)), _mm_and_ps(ok, _mm_mul_ps(ny, sc)),
                             _mm_or_ps(_mm_and_ps(ok, _mm_mul_ps(one, sc)), _mm_andnot_ps(ok, one))};
        alignas(16) int32_t b[3][4];
        for (int j = 0; j < 3; ++j) {
          const __m128 v = _mm_mul_ps(scale, _mm_add_ps(c[j], one));  // >= 0
          const __m128i r = _mm_cvttps_epi32(v);
          // r + (v - r >= 0.5): the mask is -1 where it holds.
          const __m128 up_mask = _mm_cmpge_ps(_mm_sub_ps(v, _mm_cvtepi32_ps(r)), half);
          _mm_store_si128(reinterpret_cast<__m128i*>(b[j]), _mm_sub_epi32(r, _mm_castps_si128(up_mask)));
        }
        uint8_t* t = o + 3 * size_t(x);
        for (int l = 0; l < 4; ++l) {
          t[3 * l] = uint8_t(b[0][l]);
          t[3 * l + 1] = uint8_t(b[1][l]);
          t[3 * l + 2] = uint8_t(b[2][l]);
        }
      }
#endif
      for (; x + 1 < size; ++x)
        BumpTexel(row[x - 1], row[x + 1], up[x], down[x], k_bump, o + 3 * size_t(x));
      if (size > 1) texel(size - 1);
    }
  };
  if (threads >= 2 && size >= 64) {
    std::thread t(rows, 0, size / 2);
    rows(size / 2, size);
    t.join();
  } else {
    rows(0, size);
  }
  return out;
}

bool MakeFineScaleMaps(const FineScaleSpec& spec, const FineScaleMesh& mesh,
                       const std::vector<uint32_t> anchor_points[2],
                       const FineScaleTextureOptions& options, FineScaleMaps* out,
                       Diagnostics* diag) {
  if (options.size < 1 || options.size > kMaxFineScaleSize) {
    diag->Error("--size", "must be in [1, " + std::to_string(kMaxFineScaleSize) + "], not " +
                              std::to_string(options.size));
    return false;
  }
  std::vector<float2> uvs;
  if (!MakeTextureSpace(mesh, spec.projection, spec.minimize_distortion, "fine_scale", &uvs, diag))
    return false;
  std::vector<float3> fields[2];
  if (!InterpolateSpecFields(spec, mesh, anchor_points, fields, diag)) return false;
  FieldImage images[2];
  RasterizeFields(mesh, uvs, fields[0], fields[1], options.size, images);
  out->size = options.size;
  CarveResult results[2];
  float done[2] = {0.f, 0.f};
  auto carve = [&](int f) {
    CarveOptions o;
    o.parameters = spec.parameters;
    o.k_scale = spec.k_scale;
    o.seed = options.seed * 2 + uint64_t(f);  // one stream per field: any thread count
    if (options.progress) {
      if (options.threads >= 2) {
        if (f == 0) o.progress = [&](float x) { options.progress(0.95f * x); };
      } else {
        o.progress = [&, f](float x) { done[f] = x; options.progress(0.95f * 0.5f * (done[0] + done[1])); };
      }
    }
    CarveFurrows(images[f], o, &results[f]);
  };
  if (options.threads >= 2) {
    std::thread t(carve, 1);
    carve(0);
    t.join();
  } else {
    carve(0);
    carve(1);
  }
  for (int f = 0; f < 2; ++f) out->height[f] = std::move(results[f].height);
  out->merged.resize(out->height[0].size());
  for (size_t i = 0; i < out->merged.size(); ++i)
    out->merged[i] = std::min(out->height[0][i], out->height[1][i]);  // 003 step 8
  AddHeightNoise(spec.k_noise, options.seed * 2 + 7, &out->merged);   // step 9
  out->normal = BumpNormalMap(out->merged, out->size, spec.k_bump, options.threads);
  if (options.progress) options.progress(1.f);
  return true;
}

}  // namespace mimetic
