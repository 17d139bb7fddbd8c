#include "fitting/eyes.h"

#include <Eigen/Dense>
#include <cmath>
#include <numeric>

namespace mimetic {

namespace {

uint32_t Root(std::vector<uint32_t>& parent, uint32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

}  // namespace

bool FitEyeballs(const MeshData& eyes, std::vector<EyeSphere>* out, std::string* error) {
  out->clear();
  const size_t n = eyes.positions.size();
  if (eyes.indices.size() < 3 || n == 0) {
    *error = "the eyes mesh has no triangles";
    return false;
  }
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (size_t t = 0; t + 2 < eyes.indices.size(); t += 3)
    for (int k = 1; k < 3; ++k) {
      const uint32_t a = Root(parent, eyes.indices[t]), b = Root(parent, eyes.indices[t + k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<bool> used(n, false);
  for (uint32_t i : eyes.indices) used[i] = true;
  std::vector<int> part_of_root(n, -1);
  std::vector<std::vector<uint32_t>> parts;
  for (uint32_t v = 0; v < n; ++v) {
    if (!used[v]) continue;
    const uint32_t r = Root(parent, v);
    if (part_of_root[r] < 0) part_of_root[r] = int(parts.size()), parts.emplace_back();
    parts[size_t(part_of_root[r])].push_back(v);
  }
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::vector<uint32_t>& part = parts[i];
    const std::string which = "part " + std::to_string(i + 1) + " of the eyes mesh (from vertex " +
                              std::to_string(part[0]) + ")";
    if (part.size() < 4) {
      *error = which + " has " + std::to_string(part.size()) +
               " vertices; expected a sphere of at least 4";
      return false;
    }
    for (uint32_t v : part)
      if (!IsFinite(eyes.positions[v])) {
        *error = which + ": vertex " + std::to_string(v) + " is not finite";
        return false;
      }
    // |x|^2 = 2 c.x + k, least squares about the part's mean (for conditioning).
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (uint32_t v : part) {
      const float3 p = eyes.positions[v];
      mean += Eigen::Vector3d(p.x, p.y, p.z);
    }
    mean /= double(part.size());
    Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
    Eigen::Vector4d atb = Eigen::Vector4d::Zero();
    for (uint32_t v : part) {
      const float3 p = eyes.positions[v];
      const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
      const Eigen::Vector4d row(2 * d.x(), 2 * d.y(), 2 * d.z(), 1.0);
      ata += row * row.transpose();
      atb += row * d.squaredNorm();
    }
    const Eigen::FullPivLU<Eigen::Matrix4d> lu(ata);
    const Eigen::Vector4d s = lu.solve(atb);
    const Eigen::Vector3d c = s.head<3>();
    const double r2 = s[3] + c.squaredNorm();
    if (lu.rank() < 4 || !s.allFinite() || !(r2 > 0.0)) {
      *error = which + ": its vertices do not span a sphere (they lie on a plane)";
      return false;
    }
    const Eigen::Vector3d centre = c + mean;
    out->push_back({float3{float(centre.x()), float(centre.y()), float(centre.z())},
                    float(std::sqrt(r2))});
  }
  return true;
}

EyesSpec MakeEyesSpec(const std::vector<EyeSphere>& spheres) {
  EyesSpec spec;
  spec.spheres = spheres;
  double sum = 0.0;
  for (const EyeSphere& s : spheres) sum += s.radius;
  const float mean = spheres.empty() ? 0.f : float(sum / double(spheres.size()));
  spec.band[0] = kEyeBandInner * mean;
  spec.band[1] = kEyeBandOuter * mean;
  return spec;
}

}  // namespace mimetic
