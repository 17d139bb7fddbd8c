#include "content/procedural.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mimetic {

static float SurfaceZ(float x, float y, float width, float height, float bulge) {
  const float sx = 2.f * x / width, sy = 2.f * y / height;
  return bulge * (1.f - sx * sx) * (1.f - sy * sy);
}

MeshData MakeSurfaceMesh(uint32_t columns, uint32_t rows, float width, float height, float bulge) {
  MeshData mesh;
  mesh.source = "procedural surface";
  if (columns < 2 || rows < 2) return mesh;
  mesh.positions.reserve(size_t(columns) * rows);
  mesh.uvs.reserve(size_t(columns) * rows);
  for (uint32_t j = 0; j < rows; ++j) {
    const float v = float(j) / float(rows - 1);   // 0 at the top
    const float y = (0.5f - v) * height;
    for (uint32_t i = 0; i < columns; ++i) {
      const float u = float(i) / float(columns - 1);
      const float x = (u - 0.5f) * width;
      mesh.positions.push_back({x, y, SurfaceZ(x, y, width, height, bulge)});
      mesh.uvs.push_back({u, v});
    }
  }
  for (uint32_t j = 0; j + 1 < rows; ++j) {
    for (uint32_t i = 0; i + 1 < columns; ++i) {
      const uint32_t a = j * columns + i;          // top-left
      const uint32_t b = a + 1;                    // top-right
      const uint32_t c = a + columns;              // bottom-left
      const uint32_t d = c + 1;                    // bottom-right
      // Seen from +Z with y up, (c, b, a) and (c, d, b) are counter-clockwise.
      mesh.indices.insert(mesh.indices.end(), {c, b, a, c, d, b});
    }
  }
  return mesh;
}

RigSpec MakeSurfaceRigSpec(uint32_t count, float width, float height, float bulge, float coverage,
                           float strength) {
  RigSpec spec;
  spec.units = "mm";
  spec.thickness.kind = ThicknessSpec::Kind::kConstant;
  spec.thickness.value = 0.05f * std::min(width, height);
  // Muscles on a jittered lattice; each zone's area ~ coverage * width * height.
  const float area = coverage * width * height;
  const uint32_t grid = uint32_t(std::ceil(std::sqrt(double(count))));
  for (uint32_t m = 0; m < count; ++m) {
    const float cx = ((float(m % grid) + 0.5f) / float(grid) - 0.5f) * width;
    const float cy = ((float(m / grid) + 0.5f) / float(grid) - 0.5f) * height;
    const float angle = 0.7f * float(m);  // fibre directions vary
    const float dx = std::cos(angle), dy = std::sin(angle);
    MuscleSpec ms;
    char name[32];
    std::snprintf(name, sizeof(name), "muscle_%02u", m);
    ms.name = name;
    ms.strength = strength;
    if (m % 2 == 0) {
      // Linear: a sector of half-angle Omega and radius Rf has area Omega * Rf^2.
      ms.type = MuscleType::kLinear;
      const float omega = 0.6f;
      const float rf = std::sqrt(area / omega);
      const float3 v1{cx - 0.5f * rf * dx, cy - 0.5f * rf * dy,
                      SurfaceZ(cx, cy, width, height, bulge) - 0.1f * rf};
      ms.linear.attachment = v1;
      ms.linear.insertion = {v1.x + rf * dx, v1.y + rf * dy, v1.z};
      ms.linear.zone_angle = omega;
      ms.linear.falloff_start = 0.5f * rf;
      ms.linear.falloff_end = rf;
    } else {
      // Sheet: an AOI of Ls x Ws.
      ms.type = MuscleType::kSheet;
      const float ls = std::sqrt(area * 1.5f), ws = area / ls;
      const float3 ac{cx - 0.5f * ls * dx, cy - 0.5f * ls * dy, SurfaceZ(cx, cy, width, height, bulge)};
      const float3 side{-dy * 0.5f * ws, dx * 0.5f * ws, 0.f};
      const float3 ic{ac.x + ls * dx, ac.y + ls * dy, ac.z};
      ms.sheet.attachment[0] = ac - side;
      ms.sheet.attachment[1] = ac + side;
      ms.sheet.insertion[0] = ic - side;
      ms.sheet.insertion[1] = ic + side;
      ms.sheet.length = ls;
      ms.sheet.width = ws;
      ms.sheet.falloff_start = 0.4f * ls;
    }
    spec.muscles.push_back(ms);
  }
  return spec;
}

}  // namespace mimetic

namespace mimetic {

void AddEverySkinLayer(RigSpec* spec, float lambda_w, float curve_width) {
  spec->thickness.value = 3.f;
  spec->muscle_wrinkles.assign(spec->muscles.size(), MuscleWrinkleSpec{});
  for (size_t m = 0; m < spec->muscles.size(); ++m) {
    const MuscleSpec& muscle = spec->muscles[m];
    MuscleWrinkleSpec& w = *spec->muscle_wrinkles[m];
    w.lambda_w = lambda_w;
    w.count = 3;
    w.depth = 0.5f;
    w.shape = 0.5f;
    w.phi_c = muscle.type == MuscleType::kLinear ? 0.2f : 0.f;
    w.h_c = muscle.type == MuscleType::kSheet ? 0.1f * muscle.sheet.width : 0.f;
  }
  for (int k = 0; k < 3; ++k) {
    NamedCurveWrinkle c;
    c.name = "curve_" + std::to_string(k);
    c.spec.control[0] = {0.2f, 0.2f + 0.3f * float(k)};
    c.spec.control[1] = {0.4f, 0.25f + 0.3f * float(k)};
    c.spec.control[2] = {0.6f, 0.15f + 0.3f * float(k)};
    c.spec.control[3] = {0.8f, 0.2f + 0.3f * float(k)};
    c.spec.depth = 0.5f;
    c.spec.width = curve_width;
    c.spec.modulation = k == 1 ? CurveWrinkleModulation::kArea : CurveWrinkleModulation::kDirectional;
    c.spec.profile = CurveWrinkleProfile(k);
    c.spec.rest_amplitude = 0.2f;
    spec->curve_wrinkles.push_back(c);
  }
  spec->refinement.enabled = false;
}

}  // namespace mimetic
