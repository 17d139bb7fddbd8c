// tests/tools/render_test.cpp: the software rasterizer (tools/render/render.h).
//
// Expected colours are computed by hand from docs/model.md §12 (b = (0.97, 0.87, 0.67), ambient
// 0.3, light 0.7) and expected coverage from the camera fit documented in render.h.
#include <gtest/gtest.h>

#include <utility>
#include <stb/stb_image.h>

#include <cmath>
#include <cstring>
#include <string>

#include "core/file_util.h"
#include "geometry/mesh.h"
#include "io/image.h"
#include "io/mesh_io.h"
#include "test_support.h"
#include "tools/render/render.h"

namespace mimetic {
namespace {

// A square of side `s` in the plane z = `z`, centred on the origin, facing +Z.
void AddQuad(MeshData* m, float s, float z) {
  const uint32_t base = static_cast<uint32_t>(m->positions.size());
  const float h = 0.5f * s;
  m->positions.insert(m->positions.end(), {{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}});
  m->indices.insert(m->indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

RenderOptions Plain(int size) {
  RenderOptions o;
  o.width = o.height = size;
  o.supersample = 1;
  o.specular = 0.f;
  o.light_dir = {0.f, 0.6f, 0.8f};  // n.l = 0.8 for a normal toward the camera
  return o;
}

const uint8_t* Pixel(const Image& img, int x, int y) { return &img.rgb[(size_t(y) * img.width + x) * 3]; }

TEST(Render, CentrePixelHasTheHandComputedSkinColour) {
  MeshData quad;
  AddQuad(&quad, 1.f, 0.f);  // no normals: the renderer computes them
  const Image img = RenderMesh(quad, Plain(200));
  ASSERT_EQ(img.width, 200);
  ASSERT_EQ(img.rgb.size(), 200u * 200u * 3u);
  // c = b * (0.3 + 0.7 * 0.8) = b * 0.86 -> (0.8342, 0.7482, 0.5762) * 255.
  const uint8_t* c = Pixel(img, 100, 100);
  EXPECT_NEAR(c[0], 212.7, 0.6);
  EXPECT_NEAR(c[1], 190.8, 0.6);
  EXPECT_NEAR(c[2], 146.9, 0.6);
}

// A square turned away from the camera is the skin seen from inside: shaded with the flipped
// normal (toward the camera, n.l = 0.8) and the inside colour; with shade_inside off, as skin.
TEST(Render, BackFacesAreShadedAsTheInside) {
  MeshData quad;
  AddQuad(&quad, 1.f, 0.f);
  for (size_t t = 0; t < quad.indices.size(); t += 3) std::swap(quad.indices[t + 1], quad.indices[t + 2]);
  RenderOptions o = Plain(200);
  const Image inside = RenderMesh(quad, o);
  const float3 want = ShadeColor({0.f, 0.f, 1.f}, o.inside_color, o);
  const uint8_t* c = Pixel(inside, 100, 100);
  EXPECT_NEAR(c[0], 255.f * want.x, 0.6f);
  EXPECT_NEAR(c[1], 255.f * want.y, 0.6f);
  EXPECT_NEAR(c[2], 255.f * want.z, 0.6f);
  EXPECT_NEAR(want.x, 0.23f * 0.86f, 1e-6f);  // (0.3 + 0.7 * 0.8) of the albedo
  o.shade_inside = false;
  const Image skin = RenderMesh(quad, o);
  EXPECT_NEAR(Pixel(skin, 100, 100)[0], 212.7, 0.6);  // as CentrePixelHasTheHandComputedSkinColour
}

TEST(Render, SpecularHighlightAddsWhite) {
  MeshData quad;
  AddQuad(&quad, 1.f, 0.f);
  RenderOptions o = Plain(100);
  o.specular = 0.1f;
  o.shininess = 8.f;
  const Image img = RenderMesh(quad, o);
  // h = normalize(l + (0,0,1)) = normalize(0, 0.6, 1.8); n.h = 1.8 / sqrt(3.6) = 0.948683;
  // spec = 0.1 * 0.948683^8 = 0.0655998.
  const double spec = 0.1 * std::pow(1.8 / std::sqrt(3.6), 8.0);
  const uint8_t* c = Pixel(img, 50, 50);
  EXPECT_NEAR(c[0], (0.97 * 0.86 + spec) * 255, 0.6);
  EXPECT_NEAR(c[2], (0.67 * 0.86 + spec) * 255, 0.6);
}

TEST(Render, CoverageMatchesTheCameraFitAndBackgroundIsGrey) {
  MeshData quad;
  AddQuad(&quad, 1.f, 0.f);
  const int size = 200;
  const Image img = RenderMesh(quad, Plain(size));
  // Camera fit (render.h): R = half the box diagonal = sqrt(0.5); distance
  // d = R / sin(atan(0.9 tan 15 deg)); the unit quad's half side projects to
  // 0.5 / (d tan 15 deg) of the half image.
  const double t = std::tan(15.0 * M_PI / 180.0);
  const double d = std::sqrt(0.5) / std::sin(std::atan(0.9 * t));
  const double half_px = 0.5 / (d * t) * (size / 2.0);
  const double expected = (2 * half_px) * (2 * half_px);
  size_t covered = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const uint8_t* p = Pixel(img, x, y);
      if (p[0] != 128 || p[1] != 128 || p[2] != 128) ++covered;
    }
  EXPECT_NEAR(double(covered), expected, 4 * 2 * half_px) << "perimeter tolerance";
  // Background: 0.5 grey -> 127.5 rounds to 128.
  for (auto [x, y] : {std::pair{0, 0}, {size - 1, 0}, {0, size - 1}, {size - 1, size - 1}}) {
    const uint8_t* p = Pixel(img, x, y);
    EXPECT_EQ(p[0], 128);
    EXPECT_EQ(p[1], 128);
    EXPECT_EQ(p[2], 128);
  }
  // The quad is centred: the pixels just inside and just outside its edge.
  const int edge = int(std::floor(size / 2.0 + half_px));
  EXPECT_NE(Pixel(img, edge - 2, size / 2)[0], 128);
  EXPECT_EQ(Pixel(img, edge + 2, size / 2)[0], 128);
}

TEST(Render, DepthBufferKeepsTheNearestSurface) {
  // Near small red quad drawn first, far large green quad drawn after it.
  MeshData m;
  AddQuad(&m, 0.5f, 0.2f);
  AddQuad(&m, 1.f, 0.f);
  std::vector<float3> colors = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0},
                                {0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  RenderOptions o = Plain(200);
  o.vertex_colors = &colors;
  const Image img = RenderMesh(m, o);
  const uint8_t* c = Pixel(img, 100, 100);
  EXPECT_NEAR(c[0], 0.86 * 255, 0.6);  // red albedo * 0.86
  EXPECT_EQ(c[1], 0);
  // Between the two quads' edges: the green one.
  const uint8_t* g = Pixel(img, 100 + 52, 100);
  EXPECT_EQ(g[0], 0);
  EXPECT_NEAR(g[1], 0.86 * 255, 0.6);
}

TEST(Render, YawTurnsTheCameraTowardPlusX) {
  // A quad facing +X is invisible edge-on from the front and fully lit from yaw 90.
  MeshData m;
  m.positions = {{0, -0.5f, -0.5f}, {0, -0.5f, 0.5f}, {0, 0.5f, 0.5f}, {0, 0.5f, -0.5f}};
  m.indices = {0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +X (a front face there)
  RenderOptions o = Plain(100);
  o.yaw_deg = 90.f;
  const Image img = RenderMesh(m, o);
  const uint8_t* c = Pixel(img, 50, 50);
  EXPECT_NEAR(c[0], 212.7, 0.6);
}

TEST(Render, WireframeDrawsEdges) {
  MeshData quad;
  AddQuad(&quad, 1.f, 0.f);
  RenderOptions o = Plain(200);
  o.wireframe = true;
  const Image img = RenderMesh(quad, o);
  // The shared diagonal of the two triangles, x + y = 200 in pixels (y down), passes
  // through the centre of pixel (99, 100) at (99.5, 100.5).
  const uint8_t* c = Pixel(img, 99, 100);
  EXPECT_EQ(c[0], std::lround(0.15 * 255));
  // Away from every edge the skin colour remains.
  const uint8_t* s = Pixel(img, 80, 100);
  EXPECT_NEAR(s[0], 212.7, 0.6);
}

TEST(Render, EmptyAndBrokenMeshesGiveABackgroundImage) {
  MeshData empty;
  Image img = RenderMesh(empty, Plain(16));
  ASSERT_EQ(img.rgb.size(), 16u * 16u * 3u);
  for (uint8_t v : img.rgb) ASSERT_EQ(v, 128);
  MeshData broken;
  broken.positions = {{0, 0, 0}, {1, 0, 0}};
  broken.indices = {0, 1, 7};  // out of range: skipped
  img = RenderMesh(broken, Plain(16));
  for (uint8_t v : img.rgb) ASSERT_EQ(v, 128);
}

// Saves `img` with SavePng and reads it back with stb's decoder (a second implementation):
// the same size and bytes.
void ExpectPngRoundTrip(const Image& img, const std::string& path) {
  Diagnostics diag;
  ASSERT_TRUE(SavePng(path, img, &diag)) << diag.Format();
  std::string bytes;
  ASSERT_TRUE(ReadFile(path, &bytes, &diag));
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                                            int(bytes.size()), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, img.width);
  EXPECT_EQ(h, img.height);
  if (w == img.width && h == img.height) {
    EXPECT_EQ(std::memcmp(px, img.rgb.data(), img.rgb.size()), 0);
  }
  stbi_image_free(px);
}

TEST(Render, SavePngRoundTripsThePixels) {
  MeshData quad;
  AddQuad(&quad, 1.f, 0.f);
  const Image img = RenderMesh(quad, Plain(64));
  const std::string path = test::TempDir() + "/quad.png";
  ExpectPngRoundTrip(img, path);
  // Noise at an odd size (every PNG filter and no run of equal bytes).
  Image noise;
  noise.width = 67;
  noise.height = 5;
  uint32_t state = 12345u;
  for (int i = 0; i < noise.width * noise.height * 3; ++i) {
    state = state * 1664525u + 1013904223u;
    noise.rgb.push_back(uint8_t(state >> 24));
  }
  ExpectPngRoundTrip(noise, path);
  // Bad images and unwritable paths are reported, not thrown.
  Image bad;
  bad.width = 4;
  bad.height = 4;
  Diagnostics d2;
  EXPECT_FALSE(SavePng(test::TempDir() + "/bad.png", bad, &d2));
  EXPECT_TRUE(d2.Contains("width*height*3"));
  Diagnostics d3;
  EXPECT_FALSE(SavePng("/nonexistent-dir/x.png", img, &d3));
  EXPECT_TRUE(d3.HasErrors());
}

// Reads a PNG written by the tool as RGB.
Image LoadPng(const std::string& path) {
  Image img;
  std::string bytes;
  Diagnostics diag;
  if (!ReadFile(path, &bytes, &diag)) return img;
  int n = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                                            int(bytes.size()), &img.width, &img.height, &n, 3);
  if (!px) return Image{};
  img.rgb.assign(px, px + size_t(img.width) * img.height * 3);
  stbi_image_free(px);
  return img;
}

TEST(RenderCli, ZoomKeepsTheFocusWindowOfALargerRender) {
  // Two quads at different depths so the image is not uniform.
  MeshData m;
  AddQuad(&m, 1.f, 0.f);
  AddQuad(&m, 0.3f, 0.2f);
  for (float3& p : m.positions) p.x += 0.1f * p.y;  // shear: no symmetry to hide an offset
  const std::string dir = test::TempDir();
  Diagnostics diag;
  ASSERT_TRUE(ExportMesh(dir + "/quads.obj", m, &diag)) << diag.Format();
  test::ToolResult r = test::RunTool({"render", dir + "/quads.obj", "--size", "120", "--out", dir + "/full.png"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::RunTool({"render", dir + "/quads.obj", "--size", "40", "--zoom", "3", "--focus", "0.25,0.6",
                     "--out", dir + "/zoom.png"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image full = LoadPng(dir + "/full.png"), zoom = LoadPng(dir + "/zoom.png");
  ASSERT_EQ(full.width, 120);
  ASSERT_EQ(zoom.width, 40);
  ASSERT_EQ(zoom.height, 40);
  // The 40 x 40 window centred on (0.25 * 120, 0.6 * 120) = (30, 72): x from 10, y from 52.
  for (int y = 0; y < 40; ++y)
    ASSERT_EQ(std::memcmp(Pixel(zoom, 0, y), Pixel(full, 10, 52 + y), 40 * 3), 0) << "row " << y;
  // A focus at the corner keeps the window inside the view.
  r = test::RunTool({"render", dir + "/quads.obj", "--size", "40", "--zoom", "3", "--focus", "1,1",
                     "--out", dir + "/corner.png"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image corner = LoadPng(dir + "/corner.png");
  ASSERT_EQ(corner.width, 40);
  for (int y = 0; y < 40; ++y)
    ASSERT_EQ(std::memcmp(Pixel(corner, 0, y), Pixel(full, 80, 80 + y), 40 * 3), 0) << "row " << y;
  // Bad values are usage errors (exit 2) that say what was expected.
  r = test::RunTool({"render", dir + "/quads.obj", "--zoom", "0.5", "--out", dir + "/x.png"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("[1, 8]"), std::string::npos) << r.output;
  r = test::RunTool({"render", dir + "/quads.obj", "--focus", "2,0", "--out", dir + "/x.png"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("fractions in [0, 1]"), std::string::npos) << r.output;
  r = test::RunTool({"render", dir + "/quads.obj", "--focus", "0.5", "--out", dir + "/x.png"});
  EXPECT_EQ(r.exit_code, 2);
}


TEST(Render, FineScaleHeightRampTiltsTheNormalByItsSlope) {
  // A 2 x 2 quad facing +Z with uv = ((x + 1) / 2, (1 - y) / 2) (v down, glTF); height map
  // 1 h = u (16-bit ramp), map 2 flat white; amplitudes (a1, 1). H = depth a1 (u - 1), so
  // dH/dx = depth a1 / 2 and the normal is normalize(-depth a1 / 2, 0, 1) (Blinn, 003 eq. 4.2).
  MeshData m;
  AddQuad(&m, 2.f, 0.f);
  for (const float3& p : m.positions) m.uvs.push_back({(p.x + 1.f) / 2.f, (1.f - p.y) / 2.f});
  Gray16Image ramp, flat;
  ramp.width = ramp.height = flat.width = flat.height = 256;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      ramp.pixels.push_back(uint16_t(std::lround(65535.0 * (x + 0.5) / 256.0)));
      flat.pixels.push_back(65535);
    }
  const float a1 = 0.5f, depth = 1.2f;
  std::vector<float> amps;
  for (size_t v = 0; v < m.positions.size(); ++v) amps.insert(amps.end(), {a1, 1.f});
  FineScaleShading fine;
  fine.height[0] = &ramp;
  fine.height[1] = &flat;
  fine.amplitudes = &amps;
  fine.depth = depth;
  RenderOptions o = Plain(64);
  o.light_dir = {-0.6f, 0.f, 0.8f};  // from the left: a normal tilted left is brighter
  o.fine = &fine;
  const Image img = RenderMesh(m, o);
  const float3 n = NormalizeOr(float3{-depth * a1 / 2.f, 0.f, 1.f}, {});
  const float3 c = ShadeColor(n, o.base_color, o);
  const uint8_t* px = Pixel(img, 32, 32);
  EXPECT_NEAR(px[0], c.x * 255.f, 2.f);
  EXPECT_NEAR(px[1], c.y * 255.f, 2.f);
  // Without the maps: the flat normal's colour (darker under this light).
  o.fine = nullptr;
  const float3 c0 = ShadeColor({0.f, 0.f, 1.f}, o.base_color, o);
  EXPECT_NEAR(Pixel(RenderMesh(m, o), 32, 32)[0], c0.x * 255.f, 1.5f);
  EXPECT_GT(c.x, c0.x + 0.02f);
}

}  // namespace
}  // namespace mimetic
