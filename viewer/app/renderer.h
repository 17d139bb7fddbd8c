// viewer/app/renderer.h: the OpenGL 3.3 core drawing of the viewer (mesh, wireframe, overlay
// colours, muscle gizmos) and the offscreen target of headless screenshots.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "geometry/mesh.h"
#include "core/image.h"
#include "core/math.h"

namespace mimetic::viewer {

struct DrawParams {
  glm::mat4 view{1.f}, projection{1.f};
  float3 albedo{0.97f, 0.87f, 0.67f};  // SkinAlbedo(melanin, hemoglobin)
  float3 light_camera{0.f, 0.f, 1.f};  // unit, toward the light, camera space
  float ambient = 0.3f, light = 0.7f, specular = 0.08f, exponent = 24.f;
  bool overlay = false;    // colour by the per-vertex overlay colours instead of the albedo
  bool wireframe = false;  // edges drawn over the surface
  bool surface = true;
  bool fine = false;        // bump-map the fine-scale maps (SetFineMaps, UploadFineAmplitudes)
  float fine_depth = 0.15f; // a full furrow's depth at amplitude 1, mesh units
};

class Renderer {
 public:
  // Compiles the shaders; false with `error` (the GL info log) when they do not compile.
  bool Init(std::string* error);
  void Shutdown();
  // A new mesh (index buffer and texture coordinates fixed per rig; `uvs` may be empty).
  void SetMesh(const std::vector<uint32_t>& indices, uint32_t vertex_count,
               const std::vector<float2>& uvs);
  // The two fine-scale height maps (16-bit, white = no furrow; the same size).
  void SetFineMaps(const Gray16Image& height1, const Gray16Image& height2);
  // Per frame with fine scale on: the amplitudes (a1, a2) per vertex.
  void UploadFineAmplitudes(const std::vector<float>& amplitudes);
  // Per frame: positions and normals (3 floats per vertex).
  void UploadFrame(const std::vector<float3>& positions, const std::vector<float3>& normals);
  void UploadColors(const std::vector<float3>& colors);
  // A mesh drawn unposed beside the skin, in its own colours (the sample head's eyeballs); an
  // empty one draws nothing.
  void SetStaticMesh(const MeshData& mesh, const std::vector<float3>& colors);
  // Gizmo lines (pairs of endpoints) and points, in mesh space, one colour each.
  void SetGizmos(const std::vector<float3>& lines, const std::vector<float3>& line_colors,
                 const std::vector<float3>& points, const std::vector<float3>& point_colors);
  void Draw(const DrawParams& params);

  // The offscreen target: (re)created at width x height; Bind makes it current.
  bool BindOffscreen(int width, int height);
  void UnbindOffscreen();
  // The bound framebuffer's pixels, rows top to bottom.
  static Image ReadPixels(int width, int height);

 private:
  unsigned mesh_program_ = 0, line_program_ = 0;
  unsigned vao_ = 0, position_vbo_ = 0, normal_vbo_ = 0, color_vbo_ = 0, index_ebo_ = 0;
  unsigned uv_vbo_ = 0, amplitude_vbo_ = 0, height_textures_[2] = {0, 0};
  bool has_fine_maps_ = false;
  float fine_texel_[2] = {1.f, 1.f};
  unsigned gizmo_vao_ = 0, gizmo_vbo_ = 0, gizmo_color_vbo_ = 0;
  unsigned static_vao_ = 0, static_vbo_[3] = {0, 0, 0}, static_ebo_ = 0;
  size_t static_index_count_ = 0;
  size_t index_count_ = 0, vertex_count_ = 0, gizmo_lines_ = 0, gizmo_points_ = 0;
  unsigned fbo_ = 0, color_rb_ = 0, depth_rb_ = 0;
  int fbo_width_ = 0, fbo_height_ = 0;
};

}  // namespace mimetic::viewer
