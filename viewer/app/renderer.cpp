// viewer/app/renderer.cpp: see renderer.h. Shading: docs/model.md §12 (viewer/core/skin_shading.h
// is the reference of the fragment shader's expression).
//
// Fine scale (docs/model.md §22-23, docs/viewer.md "Fine scale"): the two height maps are two
// R16 textures, the evaluator's per-vertex amplitudes (a1, a2) one more attribute; the fragment
// shader bump-maps H = depth sum_k a_k (h_k - 1) as mimetic render does (tools/render/render.cpp),
// with the surface's uv derivatives P_u, P_v taken from the screen-space derivatives of the
// camera-space position and the uv instead of per triangle.
#include "viewer/app/renderer.h"

#include <algorithm>
#include <string>

#include <GL/glcorearb.h>
#include <glm/gtc/type_ptr.hpp>

namespace mimetic::viewer {
namespace {

const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
layout(location = 3) in vec2 a_uv;
layout(location = 4) in vec2 a_amplitude;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_normal;   // camera space
out vec3 v_position; // camera space
out vec3 v_color;
out vec2 v_uv;
out vec2 v_amplitude;
void main() {
  vec4 p = u_view * vec4(a_position, 1.0);
  v_position = p.xyz;
  v_uv = a_uv;
  v_amplitude = a_amplitude;
  v_normal = mat3(u_view) * a_normal;
  v_color = a_color;
  gl_Position = u_projection * p;
}
)";

// c: the albedo b - m a_m - h a_h (SkinAlbedo) or the overlay colour; Blinn-Phong with
// ambient 0.3 and light 0.7 (003 §5.3), two-sided, a faint white highlight (ShadeSkin).
const char* kMeshFragment = R"(#version 330 core
in vec3 v_normal;
in vec3 v_position;
in vec3 v_color;
in vec2 v_uv;
in vec2 v_amplitude;
uniform vec3 u_albedo;
uniform vec3 u_light;  // unit, toward the light, camera space
uniform float u_ambient;
uniform float u_diffuse;
uniform float u_specular;
uniform float u_exponent;
uniform int u_overlay;
uniform int u_flat;     // 1: a plain colour (wireframe)
uniform vec3 u_flat_color;
uniform int u_fine;     // 1: bump-map the two fine-scale height maps
uniform sampler2D u_height1;
uniform sampler2D u_height2;
uniform vec2 u_texel;   // one texel of the maps in uv
uniform float u_fine_depth;
out vec4 frag;
// dh/du, dh/dv of one map by central differences over one texel (the CPU renderer's).
vec2 Slope(sampler2D m) {
  float hu = texture(m, v_uv + vec2(u_texel.x, 0.0)).r - texture(m, v_uv - vec2(u_texel.x, 0.0)).r;
  float hv = texture(m, v_uv + vec2(0.0, u_texel.y)).r - texture(m, v_uv - vec2(0.0, u_texel.y)).r;
  return vec2(hu / (2.0 * u_texel.x), hv / (2.0 * u_texel.y));
}
void main() {
  if (u_flat == 1) { frag = vec4(u_flat_color, 1.0); return; }
  // A back face is the skin seen from inside (the head's inside through the open mouth):
  // shaded dark, as a cavity, like `mimetic render` (RenderOptions::shade_inside).
  vec3 c = !gl_FrontFacing ? vec3(0.23, 0.09, 0.08) : u_overlay == 1 ? v_color : u_albedo;
  vec3 n = normalize(v_normal);
  if (u_fine == 1) {
    // P_u, P_v from dp/dx = P_u du/dx + P_v dv/dx and the same in y (a 2x2 solve).
    vec3 dpx = dFdx(v_position), dpy = dFdy(v_position);
    vec2 tx = dFdx(v_uv), ty = dFdy(v_uv);
    float det = tx.x * ty.y - tx.y * ty.x;
    vec2 g = (v_amplitude.x * Slope(u_height1) + v_amplitude.y * Slope(u_height2)) * u_fine_depth;
    // No slope (a flat map, depth 0, amplitude 0) leaves the normal as it is, bit for bit, also
    // where texture space is a sliver (the inner lip rolls) and P_u x P_v is huge.
    if (abs(det) > 1e-20 && (g.x != 0.0 || g.y != 0.0)) {
      vec3 pu = (dpx * ty.y - dpy * tx.y) / det;
      vec3 pv = (dpy * tx.x - dpx * ty.x) / det;
      // (P_u + H_u n) x (P_v + H_v n) to first order, turned outward, divided by |P_u x P_v|.
      vec3 base = cross(pu, pv);
      float area = length(base);
      float sgn = dot(base, n) < 0.0 ? -1.0 : 1.0;
      if (area > 0.0 && !isinf(area))
        n = normalize(n + (cross(n, pv) * g.x + cross(pu, n) * g.y) * (sgn / area));
    }
  }
  vec3 v = normalize(-v_position);
  if (dot(n, v) < 0.0) n = -n;
  float d = max(0.0, dot(n, u_light));
  vec3 h = normalize(u_light + v);
  float s = d > 0.0 ? u_specular * pow(max(0.0, dot(n, h)), u_exponent) : 0.0;
  frag = vec4(clamp((u_ambient + u_diffuse * d) * c + vec3(s), 0.0, 1.0), 1.0);
}
)";

const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_color;
uniform mat4 u_view_projection;
out vec3 v_color;
void main() { v_color = a_color; gl_Position = u_view_projection * vec4(a_position, 1.0); gl_PointSize = 3.0; }
)";

const char* kLineFragment = R"(#version 330 core
in vec3 v_color;
out vec4 frag;
void main() { frag = vec4(v_color, 1.0); }
)";

// True when the shader (program = false) compiled or the program linked; else `error` gets
// `what` and the GL info log.
bool Succeeded(unsigned object, bool program, const char* what, std::string* error) {
  GLint ok = 0;
  if (program) glGetProgramiv(object, GL_LINK_STATUS, &ok);
  else glGetShaderiv(object, GL_COMPILE_STATUS, &ok);
  if (ok) return true;
  char log[2048] = "";
  if (program) glGetProgramInfoLog(object, sizeof log, nullptr, log);
  else glGetShaderInfoLog(object, sizeof log, nullptr, log);
  *error = std::string(what) + ": " + log;
  return false;
}

unsigned Compile(GLenum kind, const char* source, std::string* error) {
  const unsigned shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  if (Succeeded(shader, false, "shader does not compile", error)) return shader;
  glDeleteShader(shader);
  return 0;
}

unsigned Link(const char* vs, const char* fs, std::string* error) {
  const unsigned v = Compile(GL_VERTEX_SHADER, vs, error);
  if (!v) return 0;
  const unsigned f = Compile(GL_FRAGMENT_SHADER, fs, error);
  if (!f) return glDeleteShader(v), 0;
  const unsigned program = glCreateProgram();
  glAttachShader(program, v);
  glAttachShader(program, f);
  glLinkProgram(program);
  glDeleteShader(v);
  glDeleteShader(f);
  if (Succeeded(program, true, "shader program does not link", error)) return program;
  glDeleteProgram(program);
  return 0;
}

void Attribute(unsigned vbo, unsigned location, int size = 3) {
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, 0, nullptr);
}

}  // namespace

bool Renderer::Init(std::string* error) {
  mesh_program_ = Link(kMeshVertex, kMeshFragment, error);
  if (!mesh_program_) return false;
  line_program_ = Link(kLineVertex, kLineFragment, error);
  if (!line_program_) return false;
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &position_vbo_);
  glGenBuffers(1, &normal_vbo_);
  glGenBuffers(1, &color_vbo_);
  glGenBuffers(1, &uv_vbo_);
  glGenBuffers(1, &amplitude_vbo_);
  glGenBuffers(1, &index_ebo_);
  glGenTextures(2, height_textures_);
  glBindVertexArray(vao_);
  Attribute(position_vbo_, 0);
  Attribute(normal_vbo_, 1);
  Attribute(color_vbo_, 2);
  Attribute(uv_vbo_, 3, 2);
  Attribute(amplitude_vbo_, 4, 2);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_ebo_);
  glGenVertexArrays(1, &static_vao_);
  glGenBuffers(3, static_vbo_);
  glGenBuffers(1, &static_ebo_);
  glBindVertexArray(static_vao_);
  Attribute(static_vbo_[0], 0);
  Attribute(static_vbo_[1], 1);
  Attribute(static_vbo_[2], 2);
  glVertexAttrib2f(3, 0.f, 0.f);  // no uvs, amplitude 0: never bump-mapped
  glVertexAttrib2f(4, 0.f, 0.f);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, static_ebo_);
  glGenVertexArrays(1, &gizmo_vao_);
  glGenBuffers(1, &gizmo_vbo_);
  glGenBuffers(1, &gizmo_color_vbo_);
  glBindVertexArray(gizmo_vao_);
  Attribute(gizmo_vbo_, 0);
  Attribute(gizmo_color_vbo_, 1);
  glBindVertexArray(0);
  return true;
}

void Renderer::Shutdown() {
  const unsigned buffers[] = {position_vbo_, normal_vbo_, color_vbo_, uv_vbo_, amplitude_vbo_,
                              index_ebo_, gizmo_vbo_, gizmo_color_vbo_};
  glDeleteBuffers(8, buffers);
  glDeleteTextures(2, height_textures_);
  glDeleteBuffers(3, static_vbo_);
  glDeleteBuffers(1, &static_ebo_);
  const unsigned arrays[] = {vao_, gizmo_vao_, static_vao_};
  glDeleteVertexArrays(3, arrays);
  glDeleteProgram(mesh_program_);
  glDeleteProgram(line_program_);
  if (fbo_) {
    glDeleteFramebuffers(1, &fbo_);
    glDeleteRenderbuffers(1, &color_rb_);
    glDeleteRenderbuffers(1, &depth_rb_);
  }
}

void Renderer::SetMesh(const std::vector<uint32_t>& indices, uint32_t vertex_count,
                       const std::vector<float2>& uvs) {
  glBindVertexArray(vao_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_ebo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * 4), indices.data(), GL_STATIC_DRAW);
  const GLsizeiptr bytes = GLsizeiptr(vertex_count) * 12;
  for (unsigned vbo : {position_vbo_, normal_vbo_, color_vbo_}) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, bytes, nullptr, GL_DYNAMIC_DRAW);
  }
  // Texture coordinates (zeros without: the fine-scale maps are then never drawn, Session::
  // fine_active) and amplitudes 1 until a frame brings the evaluator's.
  std::vector<float2> uv = uvs;
  uv.resize(vertex_count, float2{0.f, 0.f});
  glBindBuffer(GL_ARRAY_BUFFER, uv_vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertex_count) * 8, uv.data(), GL_STATIC_DRAW);
  const std::vector<float> ones(2 * size_t(vertex_count), 1.f);
  glBindBuffer(GL_ARRAY_BUFFER, amplitude_vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertex_count) * 8, ones.data(), GL_DYNAMIC_DRAW);
  glBindVertexArray(0);
  index_count_ = indices.size();
  vertex_count_ = vertex_count;
}

void Renderer::SetFineMaps(const Gray16Image& height1, const Gray16Image& height2) {
  const Gray16Image* maps[2] = {&height1, &height2};
  for (int k = 0; k < 2; ++k) {
    glBindTexture(GL_TEXTURE_2D, height_textures_[k]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R16, maps[k]->width, maps[k]->height, 0, GL_RED,
                 GL_UNSIGNED_SHORT, maps[k]->pixels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    // u is the azimuth of a cylindrical unwrap on the sample head (it wraps); v does not.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  glBindTexture(GL_TEXTURE_2D, 0);
  fine_texel_[0] = 1.f / float(std::max(1, height1.width));
  fine_texel_[1] = 1.f / float(std::max(1, height1.height));
  has_fine_maps_ = true;
}

void Renderer::UploadFineAmplitudes(const std::vector<float>& amplitudes) {
  if (amplitudes.size() < 2 * vertex_count_) return;
  glBindBuffer(GL_ARRAY_BUFFER, amplitude_vbo_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(vertex_count_) * 8, amplitudes.data());
}

void Renderer::UploadFrame(const std::vector<float3>& positions, const std::vector<float3>& normals) {
  if (positions.size() < vertex_count_ || normals.size() < vertex_count_) return;
  const GLsizeiptr bytes = GLsizeiptr(vertex_count_) * 12;
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, positions.data());
  glBindBuffer(GL_ARRAY_BUFFER, normal_vbo_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, normals.data());
}

void Renderer::UploadColors(const std::vector<float3>& colors) {
  if (colors.size() < vertex_count_) return;
  glBindBuffer(GL_ARRAY_BUFFER, color_vbo_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(vertex_count_) * 12, colors.data());
}

void Renderer::SetStaticMesh(const MeshData& mesh, const std::vector<float3>& colors) {
  const size_t n = mesh.vertex_count();
  static_index_count_ = 0;
  if (n == 0 || mesh.normals.size() != n || colors.size() != n) return;
  glBindVertexArray(static_vao_);
  const std::vector<float3>* data[3] = {&mesh.positions, &mesh.normals, &colors};
  for (int k = 0; k < 3; ++k) {
    glBindBuffer(GL_ARRAY_BUFFER, static_vbo_[k]);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(n * 12), data[k]->data(), GL_STATIC_DRAW);
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, static_ebo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * 4), mesh.indices.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
  static_index_count_ = mesh.indices.size();
}

void Renderer::SetGizmos(const std::vector<float3>& lines, const std::vector<float3>& line_colors,
                         const std::vector<float3>& points, const std::vector<float3>& point_colors) {
  std::vector<float3> all = lines, colors = line_colors;
  all.insert(all.end(), points.begin(), points.end());
  colors.insert(colors.end(), point_colors.begin(), point_colors.end());
  colors.resize(all.size(), float3{1.f, 1.f, 0.f});
  glBindBuffer(GL_ARRAY_BUFFER, gizmo_vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(all.size() * 12), all.data(), GL_DYNAMIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, gizmo_color_vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(colors.size() * 12), colors.data(), GL_DYNAMIC_DRAW);
  gizmo_lines_ = lines.size();
  gizmo_points_ = points.size();
}

void Renderer::Draw(const DrawParams& p) {
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glClearColor(0.18f, 0.19f, 0.21f, 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (index_count_ == 0) return;
  glUseProgram(mesh_program_);
  auto loc = [&](const char* name) { return glGetUniformLocation(mesh_program_, name); };
  glUniformMatrix4fv(loc("u_view"), 1, GL_FALSE, glm::value_ptr(p.view));
  glUniformMatrix4fv(loc("u_projection"), 1, GL_FALSE, glm::value_ptr(p.projection));
  glUniform3f(loc("u_albedo"), p.albedo.x, p.albedo.y, p.albedo.z);
  glUniform3f(loc("u_light"), p.light_camera.x, p.light_camera.y, p.light_camera.z);
  glUniform1f(loc("u_ambient"), p.ambient);
  glUniform1f(loc("u_diffuse"), p.light);
  glUniform1f(loc("u_specular"), p.specular);
  glUniform1f(loc("u_exponent"), p.exponent);
  glUniform1i(loc("u_overlay"), p.overlay ? 1 : 0);
  const bool fine = p.fine && has_fine_maps_;
  glUniform1i(loc("u_fine"), fine ? 1 : 0);
  if (fine) {
    for (int k = 0; k < 2; ++k) {
      glActiveTexture(GLenum(GL_TEXTURE0 + k));
      glBindTexture(GL_TEXTURE_2D, height_textures_[k]);
    }
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(loc("u_height1"), 0);
    glUniform1i(loc("u_height2"), 1);
    glUniform2f(loc("u_texel"), fine_texel_[0], fine_texel_[1]);
    glUniform1f(loc("u_fine_depth"), p.fine_depth);
  }
  glBindVertexArray(vao_);
  if (p.surface) {
    glUniform1i(loc("u_flat"), 0);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.f, 1.f);
    glDrawElements(GL_TRIANGLES, GLsizei(index_count_), GL_UNSIGNED_INT, nullptr);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }
  if (p.surface && static_index_count_ > 0) {  // unposed, in its own colours, never bumped
    glBindVertexArray(static_vao_);
    glUniform1i(loc("u_flat"), 0);
    glUniform1i(loc("u_overlay"), 1);
    glUniform1i(loc("u_fine"), 0);
    glDrawElements(GL_TRIANGLES, GLsizei(static_index_count_), GL_UNSIGNED_INT, nullptr);
    glUniform1i(loc("u_overlay"), p.overlay ? 1 : 0);
    glUniform1i(loc("u_fine"), fine ? 1 : 0);
    glBindVertexArray(vao_);
  }
  if (p.wireframe) {
    glUniform1i(loc("u_flat"), 1);
    glUniform3f(loc("u_flat_color"), 0.1f, 0.1f, 0.12f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, GLsizei(index_count_), GL_UNSIGNED_INT, nullptr);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  if (gizmo_lines_ + gizmo_points_ > 0) {
    glUseProgram(line_program_);
    const glm::mat4 vp = p.projection * p.view;
    glUniformMatrix4fv(glGetUniformLocation(line_program_, "u_view_projection"), 1, GL_FALSE,
                       glm::value_ptr(vp));
    glBindVertexArray(gizmo_vao_);
    glEnable(GL_PROGRAM_POINT_SIZE);
    // The region's points on the skin first, then the lines over everything: a muscle's
    // attachment lies under the skin, on the bone.
    glDepthFunc(GL_LEQUAL);
    glDrawArrays(GL_POINTS, GLsizei(gizmo_lines_), GLsizei(gizmo_points_));
    glDepthFunc(GL_ALWAYS);
    glDrawArrays(GL_LINES, 0, GLsizei(gizmo_lines_));
    glDepthFunc(GL_LESS);
  }
  glBindVertexArray(0);
  glUseProgram(0);
}

bool Renderer::BindOffscreen(int width, int height) {
  if (!fbo_ || width != fbo_width_ || height != fbo_height_) {
    if (fbo_) {
      glDeleteFramebuffers(1, &fbo_);
      glDeleteRenderbuffers(1, &color_rb_);
      glDeleteRenderbuffers(1, &depth_rb_);
    }
    glGenFramebuffers(1, &fbo_);
    glGenRenderbuffers(1, &color_rb_);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, color_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
    fbo_width_ = width;
    fbo_height_ = height;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width, height);
  return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

void Renderer::UnbindOffscreen() { glBindFramebuffer(GL_FRAMEBUFFER, 0); }

Image Renderer::ReadPixels(int width, int height) {
  Image image;
  image.width = width;
  image.height = height;
  std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  image.rgb.resize(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y) {
    const uint8_t* src = rgba.data() + size_t(height - 1 - y) * size_t(width) * 4;  // GL: bottom up
    uint8_t* dst = image.rgb.data() + size_t(y) * size_t(width) * 3;
    for (int x = 0; x < width; ++x) {
      dst[3 * x] = src[4 * x];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 2];
    }
  }
  return image;
}

}  // namespace mimetic::viewer
