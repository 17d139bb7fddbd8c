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

// Bilinear sample of a 16-bit map at uv (pixel centres at (x + 0.5) / w), in [0, 1] (1 white);
// clamped at the border.
float SampleHeight(const Gray16Image& m, float u, float v) {
  const float x = u * m.width - 0.5f, y = v * m.height - 0.5f;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const float fx = x - x0, fy = y - y0;
  auto at = [&](int xx, int yy) {
    xx = std::clamp(xx, 0, m.width - 1);
    yy = std::clamp(yy, 0, m.height - 1);
    return m.pixels[size_t(yy) * size_t(m.width) + size_t(xx)] * (1.f / 65535.f);
  };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
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
  const FineScaleShading* fine = o.fine;
  if (fine && (mesh.uvs.size() != nv || (fine->amplitudes && fine->amplitudes->size() != 2 * nv)))
    fine = nullptr;
  if (fine)
    for (const Gray16Image* m : fine->height)
      if (m && (m->width <= 0 || m->pixels.size() != size_t(m->width) * size_t(m->height))) fine = nullptr;

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
    // Fine-scale bump: the triangle's uv derivatives P_u, P_v in camera space (e = P_u du +
    // P_v dv for its two edges) and a per-texel step for the height differences.
    float3 pu{}, pv_{};
    bool bump = false;
    if (fine) {
      auto cam3 = [&](uint32_t i) {
        const float3 d = mesh.positions[i] - cam.eye;
        return float3{Dot(d, cam.right), Dot(d, cam.up), Dot(d, cam.back)};
      };
      const float3 e1 = cam3(ib) - cam3(ia), e2 = cam3(ic) - cam3(ia);
      const float2 ua = mesh.uvs[ia], ub = mesh.uvs[ib], uc = mesh.uvs[ic];
      const float du1 = ub.x - ua.x, dv1 = ub.y - ua.y, du2 = uc.x - ua.x, dv2 = uc.y - ua.y;
      const float det = du1 * dv2 - du2 * dv1;
      if (std::fabs(det) > 1e-12f) {
        pu = (e1 * dv2 - e2 * dv1) * (1.f / det);
        pv_ = (e2 * du1 - e1 * du2) * (1.f / det);
        bump = true;
      }
    }
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
        if (bump) {
          // H(u, v) = depth sum_k a_k (h_k - 1), bump-mapped as 003 eq. 4.2.
          const float2 uv{(mesh.uvs[ia].x * qa + mesh.uvs[ib].x * qb + mesh.uvs[ic].x * qc) * z,
                          (mesh.uvs[ia].y * qa + mesh.uvs[ib].y * qb + mesh.uvs[ic].y * qc) * z};
          float amp[2] = {1.f, 1.f};
          if (fine->amplitudes) {
            const std::vector<float>& A = *fine->amplitudes;
            for (int k = 0; k < 2; ++k)
              amp[k] = (A[2 * ia + k] * qa + A[2 * ib + k] * qb + A[2 * ic + k] * qc) * z;
          }
          float hu = 0.f, hv = 0.f;
          for (int k = 0; k < 2; ++k) {
            const Gray16Image* m = fine->height[k];
            if (!m) continue;
            const float su = 1.f / float(m->width), sv = 1.f / float(m->height);
            hu += amp[k] * (SampleHeight(*m, uv.x + su, uv.y) - SampleHeight(*m, uv.x - su, uv.y)) / (2.f * su);
            hv += amp[k] * (SampleHeight(*m, uv.x, uv.y + sv) - SampleHeight(*m, uv.x, uv.y - sv)) / (2.f * sv);
          }
          hu *= fine->depth;
          hv *= fine->depth;
          // The displaced surface P + H n (n the outward shading normal): to first order
          // (P_u + H_u n) x (P_v + H_v n) = P_u x P_v + H_u (n x P_v) + H_v (P_u x n), turned
          // outward (the uv parameterisation may run against the winding: v points down).
          // The smooth normal keeps its length |P_u x P_v| (not the face's direction).
          const float3 base = Cross(pu, pv_);
          const float sign = Dot(base, n) < 0.f ? -1.f : 1.f;
          n = Normalized(n * Length(base) + (Cross(n, pv_) * hu + Cross(pu, n) * hv) * sign);
        }
        if (back_facing) n = -n;
        const float3 albedo = back_facing && o.shade_inside ? o.inside_color
                                                            : (alb_a * qa + alb_b * qb + alb_c * qc) * z;
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
