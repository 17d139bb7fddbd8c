// tools/render/render.h: a small software rasterizer for looking at meshes without OpenGL.
//
// Z-buffered triangles, perspective camera fitted to the mesh's bounding box, per-pixel
// interpolated normals and Blinn-Phong shading with the skin colour of docs/model.md §12
// (b = (0.97, 0.87, 0.67), ambient 0.3, light 0.7). Used by `mimetic render`, the docs images
// and tests; deterministic (same mesh and options give the same bytes).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/image.h"
#include "core/math.h"
#include "geometry/mesh.h"

namespace mimetic {

// Fine-scale wrinkle maps bump-mapped over the shading (docs/model.md §22-23): height map k
// (16-bit, white = no furrow) scaled per vertex by amplitude k, H = sum_k a_k (h_k - 1) depth,
// and the normal perturbed by Blinn's bump mapping (003 eq. 4.2) along the triangle's uv
// derivatives. Needs the mesh's uvs; ignored where the sizes do not match.
struct FineScaleShading {
  const Gray16Image* height[2] = {nullptr, nullptr};
  const std::vector<float>* amplitudes = nullptr;  // 2 per vertex (a1, a2), or null: 1, 1
  float depth = 0.1f;  // mesh units of a full furrow (h = 0) at amplitude 1
};

struct RenderOptions {
  int width = 800, height = 800;  // pixels, each clamped to [1, 8192]
  // The camera looks at the centre of the mesh's bounding box from +Z, rotated by `yaw_deg`
  // about +Y (positive yaw moves the camera toward +X) and then by `pitch_deg` (positive
  // looks down from above). Degrees.
  float yaw_deg = 0.f, pitch_deg = 0.f;
  // Vertical field of view. The camera sits at distance d = R / sin(atan(fill * tan(fov/2)))
  // from the bounding-box centre (R = half the box diagonal), so that the bounding sphere's
  // silhouette spans `fill` of the image height (of the width when that is smaller).
  float fov_deg = 30.f;
  float fill = 0.9f;
  int supersample = 2;  // samples per pixel side (box-filtered), clamped to [1, 4]
  bool wireframe = false;  // dark triangle edges over the shading
  // Per-vertex albedo (#V) instead of the skin base colour; ignored when its size is not #V.
  const std::vector<float3>* vertex_colors = nullptr;
  float3 base_color{0.97f, 0.87f, 0.67f};  // docs/model.md §12 b
  float ambient = 0.3f;                     // docs/model.md §12 (003 §5.3)
  float diffuse = 0.7f;                     // docs/model.md §12 light intensity
  float specular = 0.08f;                   // white Blinn-Phong highlight strength
  float shininess = 24.f;                   // Blinn-Phong exponent
  // Direction toward the light in camera space (+X right, +Y up, +Z toward the viewer);
  // normalised internally. The default is a key light from the upper left front.
  float3 light_dir{-0.35f, 0.45f, 1.f};
  float3 background{0.5f, 0.5f, 0.5f};  // neutral grey
  float3 wire_color{0.15f, 0.15f, 0.15f};
  bool two_sided = true;  // shade back faces with the flipped normal
  // Back faces are the skin seen from inside (through an open mouth, the head's inside behind
  // the lip rolls; through the eye openings or a scan's holes): shaded with this dark albedo,
  // as a cavity would look, instead of as skin. Off: the same albedo as the front.
  bool shade_inside = true;
  float3 inside_color{0.23f, 0.09f, 0.08f};
  const FineScaleShading* fine = nullptr;  // optional fine-scale bump maps
};

// Renders `mesh` (uses its normals when it has #V of them, else area-weighted vertex normals).
// An empty mesh, or one with out-of-range indices (those triangles are skipped), still gives
// an image of the requested size (background where nothing is drawn).
Image RenderMesh(const MeshData& mesh, const RenderOptions& options);

// The colour RenderMesh gives a surface point with unit normal `n` (camera space, toward the
// viewer is +Z), albedo `albedo`, seen along -Z: ambient*albedo + diffuse*max(0,n.l)*albedo +
// specular*max(0,n.h)^shininess, with h = normalize(l + (0,0,1)), clamped to [0,1]. Exposed
// so that tests and tools can state expectations.
float3 ShadeColor(float3 n, float3 albedo, const RenderOptions& options);

}  // namespace mimetic
