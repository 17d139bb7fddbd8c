#include "rig/offline/rig_builder.h"

#include <atomic>
#include <cmath>
#include <string>

#include <stb/stb_image.h>

#include "muscles/offline/muscle_builder.h"
#include "rig/offline/weld.h"

namespace mimetic {
namespace {

std::atomic<uint64_t> g_next_uid{1};

// Grayscale image sampled bilinearly in texture space (u right, v down from the top row).
struct GrayImage {
  int width = 0, height = 0;
  std::vector<float> values;  // [0, 1]
  float Sample(float u, float v) const {
    const float x = ClampOrLow(u, 0.f, 1.f) * float(width - 1);
    const float y = ClampOrLow(v, 0.f, 1.f) * float(height - 1);
    const int x0 = int(x), y0 = int(y);
    const int x1 = x0 + 1 < width ? x0 + 1 : x0, y1 = y0 + 1 < height ? y0 + 1 : y0;
    const float fx = x - float(x0), fy = y - float(y0);
    auto at = [&](int xi, int yi) { return values[size_t(yi) * width + xi]; };
    return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) +
           (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
  }
};

bool LoadGray(const std::string& path, GrayImage* out, Diagnostics* diag) {
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 1);
  if (!data) {
    const char* reason = stbi_failure_reason();
    diag->Error("thickness.path", "cannot read thickness image '" + path +
                                      "': " + (reason ? reason : "unknown error") +
                                      " (expected a PNG, JPEG, TGA or BMP image)");
    return false;
  }
  out->width = w;
  out->height = h;
  out->values.resize(size_t(w) * h);
  for (size_t i = 0; i < out->values.size(); ++i) out->values[i] = data[i] / 255.f;
  stbi_image_free(data);
  return true;
}

bool ResolveThickness(const ThicknessSpec& spec, const MeshData& mesh, const WeldedMesh& welded,
                      std::vector<float>* out, Diagnostics* diag) {
  const size_t points = welded.points.size();
  out->assign(points, 0.f);
  switch (spec.kind) {
    case ThicknessSpec::Kind::kConstant:
      out->assign(points, spec.value);
      return true;
    case ThicknessSpec::Kind::kPerVertex: {
      if (spec.per_vertex.size() != mesh.vertex_count()) {
        diag->Error("thickness.values",
                    "expected one value per mesh vertex (" + std::to_string(mesh.vertex_count()) +
                        "), got " + std::to_string(spec.per_vertex.size()));
        return false;
      }
      std::vector<uint32_t> count(points, 0);
      for (size_t v = 0; v < mesh.vertex_count(); ++v) {
        (*out)[welded.point_of_vertex[v]] += spec.per_vertex[v];
        ++count[welded.point_of_vertex[v]];
      }
      for (size_t p = 0; p < points; ++p) (*out)[p] /= float(count[p] ? count[p] : 1);
      return true;
    }
    case ThicknessSpec::Kind::kImage: {
      if (mesh.uvs.size() != mesh.vertex_count()) {
        diag->Error("thickness", "a thickness image needs texture coordinates, and mesh '" +
                                     mesh.source + "' has none");
        return false;
      }
      GrayImage image;
      if (!LoadGray(spec.image_path, &image, diag)) return false;
      std::vector<uint32_t> count(points, 0);
      for (size_t v = 0; v < mesh.vertex_count(); ++v) {
        const float g = image.Sample(mesh.uvs[v].x, mesh.uvs[v].y);
        (*out)[welded.point_of_vertex[v]] += spec.min + (spec.max - spec.min) * g;
        ++count[welded.point_of_vertex[v]];
      }
      for (size_t p = 0; p < points; ++p) (*out)[p] /= float(count[p] ? count[p] : 1);
      return true;
    }
  }
  return false;
}

}  // namespace

bool BuildRig(const RigSpec& spec, const MeshData& mesh, const BuildOptions& options, Rig* out,
              Diagnostics* diag) {
  WeldedMesh welded;
  Diagnostics weld_diag;
  const bool welded_ok = WeldMesh(mesh, options.weld_tolerance, &welded, &weld_diag);
  diag->Append(weld_diag, mesh.source);
  if (!welded_ok) return false;

  Rig rig;
  rig.uid = g_next_uid.fetch_add(1);
  rig.rest_points = welded.points;
  rig.triangles = welded.triangles;
  rig.vertex_points = welded.point_of_vertex;
  rig.vertex_indices = mesh.indices;
  rig.vertex_uvs = mesh.uvs;

  // Point -> triangle adjacency (CSR, ascending triangle order per point).
  const uint32_t points = rig.point_count();
  rig.point_triangle_offsets.assign(points + 1, 0);
  for (uint32_t idx : rig.triangles) ++rig.point_triangle_offsets[idx + 1];
  for (uint32_t p = 0; p < points; ++p)
    rig.point_triangle_offsets[p + 1] += rig.point_triangle_offsets[p];
  rig.point_triangles.resize(rig.triangles.size());
  std::vector<uint32_t> fill(rig.point_triangle_offsets.begin(), rig.point_triangle_offsets.end() - 1);
  for (uint32_t t = 0; t < rig.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) rig.point_triangles[fill[rig.triangles[3 * t + k]]++] = t;

  bool ok = ResolveThickness(spec.thickness, mesh, welded, &rig.point_thickness, diag);

  for (const MuscleSpec& m : spec.muscles) rig.muscle_names.push_back(m.name);
  rig.muscles = BuildMuscleTable(spec.muscles, rig.rest_points);
  for (uint32_t m = 0; m < rig.muscle_count(); ++m) {
    if (rig.muscles.CountInfluenced(m) == 0 && spec.muscles[m].strength > 0.f)
      diag->Warning("muscles[" + std::to_string(m) + "] (" + spec.muscles[m].name + ")",
                    "reaches no vertex of the mesh: check its position and fall-off radii "
                    "against the mesh's units and placement");
  }
  if (!ok) return false;
  *out = std::move(rig);
  return true;
}

bool LoadRig(const std::string& rig_path, LoadedRig* out, Diagnostics* diag,
             const BuildOptions& options) {
  Diagnostics local;
  LoadedRig loaded;
  if (!LoadRigSpec(rig_path, &loaded.spec, &local)) {
    diag->Append(local, rig_path);
    return false;
  }
  if (!ImportMesh(loaded.spec.mesh_path, loaded.spec.mesh_name, &loaded.mesh, &local)) {
    diag->Append(local, loaded.spec.mesh_path);
    return false;
  }
  diag->Append(local, loaded.spec.mesh_path);
  local.Clear();
  const bool ok = BuildRig(loaded.spec, loaded.mesh, options, &loaded.rig, &local);
  diag->Append(local, rig_path);
  if (!ok) return false;
  *out = std::move(loaded);
  return true;
}

}  // namespace mimetic
