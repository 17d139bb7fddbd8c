// tools/render/render.cpp: z-buffered software rasterizer with Blinn-Phong skin shading
// (docs/model.md §12). Deliberately simple: one pass over the triangles into a supersampled
// colour/depth buffer, box-filtered down to the output size.
#include "tools/render/render.h"

#include <algorithm>
#include <cmath>

#include "core/file_util.h"
#include "geometry/normals.h"

namespace mimetic {
namespace {

float3 Normalized(float3 v) { return NormalizeOr(v, float3{0.f, 0.f, 1.f}); }

struct Camera {
  float3 eye, right, up, back;  // back = unit vector from the target toward the eye
  float tan_x = 1.f, tan_y = 1.f;
};

Camera FitCamera(const MeshData& mesh, const RenderOptions& o, int w, int h) {
  float3 lo{0.f, 0.f, 0.f}, hi{0.f, 0.f, 0.f};
  bool any = false;
  for (const float3& p : mesh.positions) {
    if (!IsFinite(p)) continue;
    if (!any) {
      lo = hi = p;
      any = true;
    }
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const float3 centre = (lo + hi) * 0.5f;
  float radius = 0.5f * Length(hi - lo);
  if (!(radius > 0.f)) radius = 1.f;

  const float yaw = o.yaw_deg * kPi / 180.f, pitch = o.pitch_deg * kPi / 180.f;
  Camera cam;
  cam.back = Normalized({std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                         std::cos(yaw) * std::cos(pitch)});
  cam.right = NormalizeOr(Cross(float3{0.f, 1.f, 0.f}, cam.back), float3{1.f, 0.f, 0.f});
  cam.up = Cross(cam.back, cam.right);
  float fov = o.fov_deg;
  if (!(fov > 1.f && fov < 170.f)) fov = 30.f;
  cam.tan_y = std::tan(0.5f * fov * kPi / 180.f);
  cam.tan_x = cam.tan_y * static_cast<float>(w) / static_cast<float>(h);
  float fill = o.fill;
  if (!(fill > 0.01f && fill <= 10.f)) fill = 0.9f;
  const float t = std::min(cam.tan_x, cam.tan_y);
  const float dist = radius / std::sin(std::atan(fill * t));
  cam.eye = centre + cam.back * dist;
  return cam;
}

uint8_t ToByte(float v) {
  const float c = ClampOrLow(v, 0.f, 1.f);
  return static_cast<uint8_t>(std::lround(c * 255.f));
}

}  // namespace

float3 ShadeColor(float3 n, float3 albedo, const RenderOptions& o) {
  const float3 l = Normalized(o.light_dir);
  const float3 h = Normalized(l + float3{0.f, 0.f, 1.f});
  const float ndl = std::max(0.f, Dot(n, l));
  const float ndh = std::max(0.f, Dot(n, h));
  const float spec = ndl > 0.f ? o.specular * std::pow(ndh, o.shininess) : 0.f;
  const float k = o.ambient + o.diffuse * ndl;
  return {ClampOrLow(albedo.x * k + spec, 0.f, 1.f), ClampOrLow(albedo.y * k + spec, 0.f, 1.f),
          ClampOrLow(albedo.z * k + spec, 0.f, 1.f)};
}

Image RenderMesh(const MeshData& mesh, const RenderOptions& o) {
  Image img;
  img.width = std::clamp(o.width, 1, 8192);
  img.height = std::clamp(o.height, 1, 8192);
  const int ss = std::clamp(o.supersample, 1, 4);
  const int W = img.width * ss, H = img.height * ss;
  std::vector<float3> color(static_cast<size_t>(W) * H, o.background);
  std::vector<float> depth(static_cast<size_t>(W) * H, INFINITY);

  const size_t nv = mesh.positions.size();
  const Camera cam = FitCamera(mesh, o, W, H);
  const std::vector<float3> normals =
      mesh.normals.size() == nv ? mesh.normals : ComputeVertexNormals(mesh);  // fallback +z
  const bool use_colors = o.vertex_colors && o.vertex_colors->size() == nv;

  // Project every vertex once: screen x, y in supersampled pixels, view depth, camera-space
  // normal.
  struct Projected {
    float x, y, depth;
    float3 n;
    bool ok;
  };
  std::vector<Projected> pv(nv);
  for (size_t i = 0; i < nv; ++i) {
    const float3 d = mesh.positions[i] - cam.eye;
    const float depth_i = -Dot(d, cam.back);
    const float cx = Dot(d, cam.right), cy = Dot(d, cam.up);
    Projected& p = pv[i];
    p.ok = IsFinite(mesh.positions[i]) && depth_i > 1e-6f;
    p.depth = depth_i;
    p.x = p.ok ? (0.5f + 0.5f * cx / (depth_i * cam.tan_x)) * W : 0.f;
    p.y = p.ok ? (0.5f - 0.5f * cy / (depth_i * cam.tan_y)) * H : 0.f;
    const float3 n = normals[i];
    p.n = {Dot(n, cam.right), Dot(n, cam.up), Dot(n, cam.back)};
  }

  const float wire_px = 0.6f * ss;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t ia = mesh.indices[t], ib = mesh.indices[t + 1], ic = mesh.indices[t + 2];
    if (ia >= nv || ib >= nv || ic >= nv) continue;
    const Projected &a = pv[ia], &b = pv[ib], &c = pv[ic];
    if (!a.ok || !b.ok || !c.ok) continue;
    // Signed area in screen space (y down): negative for counter-clockwise (front) faces.
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(std::fabs(area) > 1e-12f)) continue;
    const bool back_facing = area > 0.f;
    if (back_facing && !o.two_sided) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(W - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(H - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
    if (x0 > x1 || y0 > y1) continue;
    const float inv_area = 1.f / area;
    const float len_a = std::hypot(c.x - b.x, c.y - b.y);  // edge opposite a
    const float len_b = std::hypot(a.x - c.x, a.y - c.y);
    const float len_c = std::hypot(b.x - a.x, b.y - a.y);
    const float3 alb_a = use_colors ? (*o.vertex_colors)[ia] : o.base_color;
    const float3 alb_b = use_colors ? (*o.vertex_colors)[ib] : o.base_color;
    const float3 alb_c = use_colors ? (*o.vertex_colors)[ic] : o.base_color;
    for (int y = y0; y <= y1; ++y) {
      const float py = y + 0.5f;
      for (int x = x0; x <= x1; ++x) {
        const float px = x + 0.5f;
        // Barycentric weights from the edge functions (same sign as `area` inside).
        const float wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv_area;
        const float wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv_area;
        const float wc = 1.f - wa - wb;
        if (wa < 0.f || wb < 0.f || wc < 0.f) continue;
        // Perspective-correct weights.
        const float qa = wa / a.depth, qb = wb / b.depth, qc = wc / c.depth;
        const float q = qa + qb + qc;
        const float z = 1.f / q;
        const size_t k = static_cast<size_t>(y) * W + x;
        if (!(z < depth[k])) continue;
        depth[k] = z;
        float3 n = Normalized((a.n * qa + b.n * qb + c.n * qc) * z);
        if (back_facing) n = -n;
        const float3 albedo = (alb_a * qa + alb_b * qb + alb_c * qc) * z;
        float3 col = ShadeColor(n, albedo, o);
        if (o.wireframe) {
          const float two_area = std::fabs(area);
          const float da = wa * two_area / std::max(len_a, 1e-6f);
          const float db = wb * two_area / std::max(len_b, 1e-6f);
          const float dc = wc * two_area / std::max(len_c, 1e-6f);
          if (std::min({da, db, dc}) < wire_px) col = o.wire_color;
        }
        color[k] = col;
      }
    }
  }

  // Box filter down to the output size.
  img.rgb.resize(static_cast<size_t>(img.width) * img.height * 3);
  const float inv = 1.f / static_cast<float>(ss * ss);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      float3 sum{0.f, 0.f, 0.f};
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx)
          sum += color[static_cast<size_t>(y * ss + sy) * W + (x * ss + sx)];
      sum *= inv;
      uint8_t* out = &img.rgb[(static_cast<size_t>(y) * img.width + x) * 3];
      out[0] = ToByte(sum.x);
      out[1] = ToByte(sum.y);
      out[2] = ToByte(sum.z);
    }
  }
  return img;
}

}  // namespace mimetic
