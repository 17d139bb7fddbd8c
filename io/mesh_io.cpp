// io/mesh_io.cpp: ImportMesh / ExportMesh (glTF 2.0 via tinygltf, OBJ via OpenMesh).
//
// glTF: the whole file is read here (so a missing file reads "cannot open"), parsed by tinygltf
// from memory, and every accessor is bounds-checked against its bufferView and buffer before a
// byte is read (tinygltf does not do that). Images are never decoded.
//
// OBJ: OpenMesh's OBJ reader does the parsing, into RawObjImporter (a BaseImporter that keeps
// the raw vertex list, the raw face vertex lists and the per-corner texcoords instead of
// building a half-edge mesh). OpenMesh's reader still silently skips what it cannot parse: a
// `v` line it cannot read (also `nan`, `1e999`), a face with fewer than 3 distinct vertices,
// repeated vertices inside a face (removed), texcoords out of range. So a light validating scan
// (ScanObj) walks the same lines first: it reports those problems with line numbers, and after
// OpenMesh has read the file the two are compared face by face, so nothing is dropped unseen.
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <functional>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "core/file_util.h"
#include "io/json_reader.h"
#include "io/mesh_io.h"

namespace mimetic {
namespace {


std::string LowerExtension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string FormatG(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

std::string Join(const std::string& a, const std::string& b) {
  return a.empty() ? b : a + ": " + b;
}

// Checks positions, normals and uvs for non-finite values (capped per attribute).
bool CheckFinite(const MeshData& mesh, Diagnostics* diag) {
  CappedErrors pos(diag, "", "vertices with non-finite positions");
  CappedErrors nrm(diag, "", "vertices with non-finite normals");
  CappedErrors uv(diag, "", "vertices with non-finite texture coordinates");
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const float3 p = mesh.positions[i];
    if (!IsFinite(p)) {
      pos.Add("vertex " + std::to_string(i),
              "position is not finite (" + FormatG(p.x) + ", " + FormatG(p.y) + ", " +
                  FormatG(p.z) + "; expected finite numbers)");
    }
  }
  for (size_t i = 0; i < mesh.normals.size(); ++i) {
    const float3 n = mesh.normals[i];
    if (!IsFinite(n)) {
      nrm.Add("vertex " + std::to_string(i),
              "normal is not finite (" + FormatG(n.x) + ", " + FormatG(n.y) + ", " +
                  FormatG(n.z) + "; expected finite numbers)");
    }
  }
  for (size_t i = 0; i < mesh.uvs.size(); ++i) {
    const float2 t = mesh.uvs[i];
    if (!std::isfinite(t.x) || !std::isfinite(t.y)) {
      uv.Add("vertex " + std::to_string(i),
             "texture coordinate is not finite (" + FormatG(t.x) + ", " + FormatG(t.y) +
                 "; expected finite numbers)");
    }
  }
  return pos.count() + nrm.count() + uv.count() == 0;
}

// ------------------------------------------------------------------------------------------
// glTF

const char* TypeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "unknown";
  }
}

const char* ModeName(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS: return "POINTS";
    case TINYGLTF_MODE_LINE: return "LINES";
    case TINYGLTF_MODE_LINE_LOOP: return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP: return "LINE_STRIP";
    case TINYGLTF_MODE_TRIANGLES: return "TRIANGLES";
    case TINYGLTF_MODE_TRIANGLE_STRIP: return "TRIANGLE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_FAN: return "TRIANGLE_FAN";
    default: return "unknown";
  }
}

size_t ComponentSize(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

// A bounds-checked view of an accessor's elements.
struct AccessorView {
  const unsigned char* base = nullptr;  // first element
  size_t stride = 0;
  size_t count = 0;
  int component_type = 0;
  int components = 0;
  bool normalized = false;

  float Float(size_t i, int c) const {
    const unsigned char* p = base + i * stride + static_cast<size_t>(c) * ComponentSize(component_type);
    switch (component_type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0] / 255.f;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return v / 65535.f;
      }
      default: return 0.f;
    }
  }
  uint32_t Index(size_t i) const {
    const unsigned char* p = base + i * stride;
    switch (component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      default: return 0;
    }
  }
};

// Validates accessor `index` (type, component type, bufferView, buffer, byte ranges) and
// fills `view`. `what_for` names the use ("POSITION", "indices") for messages.
bool ViewAccessor(const tinygltf::Model& model, int index, const std::string& where,
                  const std::string& what_for, int expected_type,
                  const std::vector<int>& allowed_components, bool allow_normalized,
                  AccessorView* view, Diagnostics* diag) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) {
    diag->Error(where, what_for + " refers to accessor " + std::to_string(index) +
                           ", but the file has " + std::to_string(model.accessors.size()) +
                           " accessors");
    return false;
  }
  const tinygltf::Accessor& acc = model.accessors[static_cast<size_t>(index)];
  const std::string aname = what_for + " (accessor " + std::to_string(index) + ")";
  if (acc.sparse.isSparse) {
    diag->Error(where, aname + " is sparse; sparse accessors are not supported (expected a "
                               "plain bufferView accessor)");
    return false;
  }
  if (acc.type != expected_type) {
    diag->Error(where, aname + " has type " + TypeName(acc.type) + " (expected " +
                           TypeName(expected_type) + ")");
    return false;
  }
  const bool component_ok =
      std::find(allowed_components.begin(), allowed_components.end(), acc.componentType) !=
          allowed_components.end() &&
      (acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
       expected_type == TINYGLTF_TYPE_SCALAR || (allow_normalized && acc.normalized));
  if (!component_ok) {
    std::string expected;
    if (expected_type == TINYGLTF_TYPE_SCALAR) {
      expected = "unsigned byte, unsigned short or unsigned int";
    } else if (allow_normalized) {
      expected = "float, or normalized unsigned byte/short";
    } else {
      expected = "float";
    }
    diag->Error(where, aname + " has component type " + std::to_string(acc.componentType) +
                           (acc.normalized ? " (normalized)" : "") + " (expected " + expected +
                           ")");
    return false;
  }
  if (acc.bufferView < 0 || static_cast<size_t>(acc.bufferView) >= model.bufferViews.size()) {
    diag->Error(where, aname + " refers to bufferView " + std::to_string(acc.bufferView) +
                           ", but the file has " + std::to_string(model.bufferViews.size()) +
                           " bufferViews (accessors without a bufferView are not supported)");
    return false;
  }
  const tinygltf::BufferView& bv = model.bufferViews[static_cast<size_t>(acc.bufferView)];
  const std::string bvname = "bufferView " + std::to_string(acc.bufferView);
  if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model.buffers.size()) {
    diag->Error(where, bvname + " (used by " + aname + ") refers to buffer " +
                           std::to_string(bv.buffer) + ", but the file has " +
                           std::to_string(model.buffers.size()) + " buffers");
    return false;
  }
  const size_t buffer_size = model.buffers[static_cast<size_t>(bv.buffer)].data.size();
  if (bv.byteOffset > buffer_size || bv.byteLength > buffer_size - bv.byteOffset) {
    diag->Error(where, bvname + " (used by " + aname + ") spans bytes [" +
                           std::to_string(bv.byteOffset) + ", " +
                           std::to_string(bv.byteOffset) + " + " + std::to_string(bv.byteLength) +
                           ") of buffer " + std::to_string(bv.buffer) + ", which has only " +
                           std::to_string(buffer_size) + " bytes");
    return false;
  }
  const int components = expected_type == TINYGLTF_TYPE_SCALAR ? 1
                         : expected_type == TINYGLTF_TYPE_VEC2 ? 2
                                                               : 3;
  const size_t element = ComponentSize(acc.componentType) * static_cast<size_t>(components);
  const size_t stride = bv.byteStride != 0 ? bv.byteStride : element;
  if (stride < element || stride > 252) {
    diag->Error(where, bvname + " (used by " + aname + ") has byteStride " +
                           std::to_string(bv.byteStride) + " (expected 0 or " +
                           std::to_string(element) + "..252 for this accessor)");
    return false;
  }
  if (acc.count > 0) {
    const size_t available =
        acc.byteOffset <= bv.byteLength ? bv.byteLength - acc.byteOffset : 0;
    // count > available catches absurd counts before the multiplication could overflow.
    const bool fits = acc.byteOffset <= bv.byteLength && acc.count <= available &&
                      (acc.count - 1) * stride + element <= available;
    if (!fits) {
      diag->Error(where, aname + " (count " + std::to_string(acc.count) + ", byteOffset " +
                             std::to_string(acc.byteOffset) + ", stride " +
                             std::to_string(stride) + ") reads past the end of " + bvname +
                             ", which has " + std::to_string(bv.byteLength) +
                             " bytes (expected the accessor to lie within its bufferView)");
      return false;
    }
  }
  view->base = model.buffers[static_cast<size_t>(bv.buffer)].data.data() + bv.byteOffset +
               acc.byteOffset;
  view->stride = stride;
  view->count = acc.count;
  view->component_type = acc.componentType;
  view->components = components;
  view->normalized = acc.normalized;
  return true;
}

bool SkipImages(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;  // geometry only: images are never decoded
}

// ------------------------------------------------------------------------------------------
// glTF: the checks before tinygltf sees a byte (docs/errors.md "glTF").

// The JSON chunk of a .glb (or the whole .gltf text). False after recording why the GLB
// container is unusable.
bool GltfJsonText(const std::string& bytes, bool binary, std::string_view* json,
                  Diagnostics* diag) {
  if (!binary) {
    *json = bytes;
    return true;
  }
  auto u32 = [&](size_t at) {
    uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  if (bytes.size() < 20) {
    diag->Error("", "truncated GLB: " + std::to_string(bytes.size()) +
                        " bytes (expected a 12-byte header and a JSON chunk)");
    return false;
  }
  if (bytes.compare(0, 4, "glTF") != 0) {
    diag->Error("", "not a GLB file: the first 4 bytes are not 'glTF' (a .glb is binary glTF; "
                    "is this a .gltf text file or another format?)");
    return false;
  }
  if (u32(4) != 2) {
    diag->Error("", "GLB version " + std::to_string(u32(4)) + " (expected 2)");
    return false;
  }
  if (u32(8) < 20) {  // (found by fuzz_mesh_glb: u32(8) - 20 wrapped around)
    diag->Error("", "GLB header says the file is " + std::to_string(u32(8)) +
                        " bytes (expected at least 20: the header and a JSON chunk)");
    return false;
  }
  if (u32(8) > bytes.size()) {
    diag->Error("", "truncated GLB: the header says " + std::to_string(u32(8)) +
                        " bytes, the file has " + std::to_string(bytes.size()));
    return false;
  }
  const size_t json_length = u32(12);
  if (u32(16) != 0x4E4F534Au) {
    diag->Error("", "GLB: the first chunk is not JSON (expected chunk type 'JSON')");
    return false;
  }
  if (json_length > u32(8) - 20) {
    diag->Error("", "truncated GLB: the JSON chunk says " + std::to_string(json_length) +
                        " bytes, but only " + std::to_string(u32(8) - 20) + " follow it");
    return false;
  }
  *json = std::string_view(bytes.data() + 20, json_length);
  return true;
}

const char* const kCompressionExtensions[] = {"KHR_draco_mesh_compression",
                                              "EXT_meshopt_compression",
                                              "KHR_meshopt_compression"};

// Required extensions that do not change the geometry mimetic reads (materials, lights,
// image formats): accepted. Any other required extension is refused.
bool HarmlessExtension(const std::string& name) {
  static const char* const kPrefixes[] = {"KHR_materials_", "KHR_lights_", "KHR_texture_basisu",
                                          "EXT_texture_webp", "EXT_texture_avif",
                                          "KHR_xmp", "EXT_lights_"};
  for (const char* p : kPrefixes)
    if (name.compare(0, std::strlen(p), p) == 0) return true;
  return false;
}

// Structural checks on the glTF JSON that tinygltf does not make (or makes by crashing,
// wrapping around or reading out of bounds): required extensions, non-negative integers,
// references to existing accessors, bufferViews, buffers, meshes and nodes. Each message
// names the JSON path. False after recording every problem.
bool CheckGltfJson(std::string_view text, Diagnostics* diag) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.begin(), text.end());
  } catch (const std::exception& e) {
    diag->Error("", std::string("invalid glTF: the JSON does not parse: ") + e.what());
    return false;
  }
  if (!j.is_object()) {
    diag->Error("", "invalid glTF: the top level is not a JSON object");
    return false;
  }
  const size_t before = diag->ErrorCount();
  CappedErrors bad(diag, "", "glTF structure errors");
  if (j.contains("extensionsRequired")) {
    const auto& req = j["extensionsRequired"];
    if (!req.is_array()) {
      bad.Add("extensionsRequired", "expected an array of extension names");
    } else {
      for (size_t i = 0; i < req.size(); ++i) {
        const std::string at = "extensionsRequired[" + std::to_string(i) + "]";
        if (!req[i].is_string()) {
          bad.Add(at, "expected an extension name (string)");
          continue;
        }
        const std::string name = req[i].get<std::string>();
        bool compressed = false;
        for (const char* c : kCompressionExtensions) compressed = compressed || name == c;
        if (compressed) {
          bad.Add(at, "compressed glTF (" + name +
                          ") is not supported; decompress it first, e.g. with gltf-transform "
                          "(npm @gltf-transform/cli): gltf-transform copy in.glb out.glb");
        } else if (!HarmlessExtension(name)) {
          bad.Add(at, "the file requires extension " + name +
                          ", which mimetic does not support (supported: none that change "
                          "geometry; KHR_materials_*, KHR_lights_*, texture formats are "
                          "ignored)");
        }
      }
    }
  }
  auto count = [&](const char* key) -> size_t {
    const auto it = j.find(key);
    return it != j.end() && it->is_array() ? it->size() : 0;
  };
  const size_t n_acc = count("accessors"), n_bv = count("bufferViews"), n_buf = count("buffers"),
               n_mesh = count("meshes"), n_node = count("nodes");
  // An optional non-negative integer below `limit` (limit 0 = no upper bound).
  auto index = [&](const nlohmann::json& obj, const char* key, const std::string& path,
                   size_t limit, const char* what) {
    const auto it = obj.find(key);
    if (it == obj.end()) return;
    const std::string at = path + "." + key;
    if (!it->is_number_integer() && !it->is_number_unsigned()) {
      bad.Add(at, "expected a non-negative integer, got " + it->dump(-1).substr(0, 40));
      return;
    }
    if (it->is_number_integer() && !it->is_number_unsigned() && it->get<int64_t>() < 0) {
      bad.Add(at, std::to_string(it->get<int64_t>()) + " is negative (expected an integer >= 0)");
      return;
    }
    const uint64_t v = it->get<uint64_t>();
    if (what && v >= limit) {
      const std::string plural = std::string(what) == "mesh" ? "meshes" : std::string(what) + "s";
      bad.Add(at, std::string(what) + " " + std::to_string(v) + " does not exist (the file has " +
                      std::to_string(limit) + " " + plural + ")");
    } else if (!what && v > (uint64_t{1} << 40)) {
      bad.Add(at, std::to_string(v) + " is out of range (expected at most 2^40)");
    }
  };
  auto each = [&](const char* key, const std::function<void(const nlohmann::json&,
                                                            const std::string&)>& f) {
    const auto it = j.find(key);
    if (it == j.end() || !it->is_array()) return;
    for (size_t i = 0; i < it->size(); ++i)
      if ((*it)[i].is_object()) f((*it)[i], std::string(key) + "[" + std::to_string(i) + "]");
  };
  each("accessors", [&](const nlohmann::json& a, const std::string& at) {
    index(a, "bufferView", at, n_bv, "bufferView");
    index(a, "byteOffset", at, 0, nullptr);
    index(a, "count", at, 0, nullptr);
  });
  each("bufferViews", [&](const nlohmann::json& v, const std::string& at) {
    index(v, "buffer", at, n_buf, "buffer");
    index(v, "byteOffset", at, 0, nullptr);
    index(v, "byteLength", at, 0, nullptr);
    index(v, "byteStride", at, 0, nullptr);
  });
  each("buffers", [&](const nlohmann::json& b, const std::string& at) {
    index(b, "byteLength", at, 0, nullptr);
  });
  each("meshes", [&](const nlohmann::json& m, const std::string& at) {
    const auto prims = m.find("primitives");
    if (prims == m.end() || !prims->is_array()) return;
    for (size_t p = 0; p < prims->size(); ++p) {
      const auto& prim = (*prims)[p];
      if (!prim.is_object()) continue;
      const std::string pat = at + ".primitives[" + std::to_string(p) + "]";
      index(prim, "indices", pat, n_acc, "accessor");
      const auto attrs = prim.find("attributes");
      if (attrs != prim.end() && attrs->is_object())
        for (auto it = attrs->begin(); it != attrs->end(); ++it)
          index(*attrs, it.key().c_str(), pat + ".attributes", n_acc, "accessor");
    }
  });
  each("nodes", [&](const nlohmann::json& n, const std::string& at) {
    index(n, "mesh", at, n_mesh, "mesh");
    const auto children = n.find("children");
    if (children != n.end() && children->is_array())
      for (size_t c = 0; c < children->size(); ++c) {
        const auto& ch = (*children)[c];
        const std::string cat = at + ".children[" + std::to_string(c) + "]";
        if (!ch.is_number_unsigned() || ch.get<uint64_t>() >= n_node)
          bad.Add(cat, ch.dump(-1).substr(0, 40) + " is not a node (the file has " +
                           std::to_string(n_node) + " nodes)");
      }
  });
  each("scenes", [&](const nlohmann::json& s, const std::string& at) {
    const auto nodes = s.find("nodes");
    if (nodes != s.end() && nodes->is_array())
      for (size_t c = 0; c < nodes->size(); ++c) {
        const auto& nd = (*nodes)[c];
        if (!nd.is_number_unsigned() || nd.get<uint64_t>() >= n_node)
          bad.Add(at + ".nodes[" + std::to_string(c) + "]",
                  nd.dump(-1).substr(0, 40) + " is not a node (the file has " +
                      std::to_string(n_node) + " nodes)");
      }
  });
  return bad.count() == 0 && diag->ErrorCount() == before;
}

// tinygltf's file system: external buffer and image URIs go through ReadFile (regular files
// only, size-capped, never blocking on a FIFO); the first refusal is kept for the message.
struct GltfFs {
  std::string first_error;
};

bool FsFileExists(const std::string&, void*) {
  // Always "exists": tinygltf then reads the URI beside the glTF file (never the current
  // directory, its fallback) and ReadWholeFile says exactly what is wrong with it.
  return true;
}
std::string FsExpandFilePath(const std::string& path, void*) { return path; }
bool FsReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* user) {
  Diagnostics d;
  std::string bytes;
  if (!ReadFile(path, &bytes, &d, kMaxMeshFileBytes, "glTF buffer or image")) {
    const std::string what = d.items().empty() ? "cannot read" : d.items()[0].what;
    if (err) *err = what;
    auto* fs = static_cast<GltfFs*>(user);
    if (fs && fs->first_error.empty()) fs->first_error = "'" + path + "' " + what;
    return false;
  }
  out->assign(bytes.begin(), bytes.end());
  return true;
}
bool FsWriteWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&,
                      void*) {
  if (err) *err = "mimetic never writes through tinygltf's file system";
  return false;
}

// The node that places mesh `mesh_index` in the scene and its world matrix (column-major,
// as glTF). False when no node of the scene (or, without scenes, of the file) uses it.
using Mat4 = std::array<double, 16>;

Mat4 Multiply(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int rr = 0; rr < 4; ++rr) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
      r[c * 4 + rr] = s;
    }
  return r;
}

Mat4 NodeMatrix(const tinygltf::Node& n) {
  Mat4 m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (n.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m[i] = n.matrix[i];
    return m;
  }
  double tx = 0, ty = 0, tz = 0, qx = 0, qy = 0, qz = 0, qw = 1, sx = 1, sy = 1, sz = 1;
  if (n.translation.size() == 3) tx = n.translation[0], ty = n.translation[1], tz = n.translation[2];
  if (n.rotation.size() == 4) qx = n.rotation[0], qy = n.rotation[1], qz = n.rotation[2], qw = n.rotation[3];
  if (n.scale.size() == 3) sx = n.scale[0], sy = n.scale[1], sz = n.scale[2];
  const double r[9] = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw), 2 * (qx * qz - qy * qw),
                       2 * (qx * qy - qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw),
                       2 * (qx * qz + qy * qw), 2 * (qy * qz - qx * qw), 1 - 2 * (qx * qx + qy * qy)};
  const double s[3] = {sx, sy, sz};
  for (int c = 0; c < 3; ++c)
    for (int rr = 0; rr < 3; ++rr) m[c * 4 + rr] = r[c * 3 + rr] * s[c];
  m[12] = tx, m[13] = ty, m[14] = tz;
  return m;
}

struct MeshPlacement {
  int node = -1;             // first node (depth first, scene order) that uses the mesh
  Mat4 world{};
  size_t instances = 0;      // nodes that use it
  bool instances_differ = false;
};

MeshPlacement FindPlacement(const tinygltf::Model& model, size_t mesh_index) {
  MeshPlacement out;
  std::vector<int> roots;
  const int scene = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
  if (scene >= 0 && static_cast<size_t>(scene) < model.scenes.size()) {
    roots = model.scenes[static_cast<size_t>(scene)].nodes;
  } else {
    std::vector<char> is_child(model.nodes.size(), 0);
    for (const auto& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && static_cast<size_t>(c) < model.nodes.size()) is_child[c] = 1;
    for (size_t i = 0; i < model.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
  }
  std::vector<char> visited(model.nodes.size(), 0);  // a cycle or a shared child: once
  std::vector<std::pair<int, Mat4>> stack;
  const Mat4 identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, identity});
  while (!stack.empty()) {
    const auto [n, parent] = stack.back();
    stack.pop_back();
    if (n < 0 || static_cast<size_t>(n) >= model.nodes.size() || visited[n]) continue;
    visited[n] = 1;
    const tinygltf::Node& node = model.nodes[static_cast<size_t>(n)];
    const Mat4 world = Multiply(parent, NodeMatrix(node));
    if (node.mesh >= 0 && static_cast<size_t>(node.mesh) == mesh_index) {
      if (out.instances++ == 0) {
        out.node = n;
        out.world = world;
      } else {
        for (int i = 0; i < 16; ++i)
          if (std::fabs(world[i] - out.world[i]) > 1e-9 * (1 + std::fabs(world[i])))
            out.instances_differ = true;
      }
    }
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
      stack.push_back({*c, world});
  }
  return out;
}

// Applies the placing node's transform (docs/errors.md, "glTF"): positions become the scene
// positions in the mesh's own unit, M p / s, where s is the transform's uniform scale (a
// uniform scale is how a glTF file states its unit; mimetic writes one). Rotation, translation
// and mirroring are applied (a mirror flips the triangle winding back); a non-uniform scale
// or shear is refused. False after recording why.
bool ApplyPlacement(const tinygltf::Model& model, size_t mesh_index, const std::string& where,
                    MeshData* out, Diagnostics* diag) {
  const MeshPlacement pl = FindPlacement(model, mesh_index);
  if (pl.node < 0) return true;  // not in the scene: its own space
  const std::string node_name =
      "node " + std::to_string(pl.node) +
      (model.nodes[pl.node].name.empty() ? "" : " ('" + model.nodes[pl.node].name + "')");
  if (pl.instances > 1 && pl.instances_differ)
    diag->Warning(where, "is used by " + std::to_string(pl.instances) +
                             " nodes with different transforms; the first, " + node_name +
                             ", is applied");
  const Mat4& m = pl.world;
  for (double v : m)
    if (!std::isfinite(v)) {
      diag->Error(where, node_name + " has a non-finite transform (expected finite numbers)");
      return false;
    }
  const double det = m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
                     m[8] * (m[1] * m[6] - m[5] * m[2]);
  if (!(std::fabs(det) > 1e-30) || m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1) {
    diag->Error(where, node_name + " has a degenerate or projective transform (determinant " +
                           FormatG(det) + "; expected rotation, translation and scale)");
    return false;
  }
  // A pure uniform scale (the unit node mimetic writes) gives s exactly, so q is exactly I.
  const bool diagonal_uniform = m[1] == 0 && m[2] == 0 && m[4] == 0 && m[6] == 0 && m[8] == 0 &&
                                m[9] == 0 && m[0] == m[5] && m[5] == m[10];
  const double s = diagonal_uniform ? std::fabs(m[0]) : std::cbrt(std::fabs(det));
  double q[9];
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) q[c * 3 + r] = m[c * 4 + r] / s;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double dot = 0;
      for (int r = 0; r < 3; ++r) dot += q[a * 3 + r] * q[b * 3 + r];
      if (std::fabs(dot - (a == b ? 1.0 : 0.0)) > 1e-4) {
        diag->Error(where, node_name + " places the mesh with a non-uniform scale or shear; "
                               "mimetic applies rotation, translation and a uniform scale only "
                               "(apply the transform in the exporting tool, e.g. Blender's "
                               "Apply > Scale)");
        return false;
      }
    }
  const bool identity_rotation = q[0] == 1 && q[4] == 1 && q[8] == 1 && q[1] == 0 && q[2] == 0 &&
                                 q[3] == 0 && q[5] == 0 && q[6] == 0 && q[7] == 0;
  if (identity_rotation && m[12] == 0 && m[13] == 0 && m[14] == 0) return true;  // unit only
  for (float3& p : out->positions) {
    const double x = p.x, y = p.y, z = p.z;
    p = {float(q[0] * x + q[3] * y + q[6] * z + m[12] / s),
         float(q[1] * x + q[4] * y + q[7] * z + m[13] / s),
         float(q[2] * x + q[5] * y + q[8] * z + m[14] / s)};
  }
  for (float3& n : out->normals) {
    const double x = n.x, y = n.y, z = n.z;
    n = {float(q[0] * x + q[3] * y + q[6] * z), float(q[1] * x + q[4] * y + q[7] * z),
         float(q[2] * x + q[5] * y + q[8] * z)};
  }
  if (det < 0)  // a mirror: glTF flips the winding, so the front faces stay in front
    for (size_t t = 0; t + 2 < out->indices.size(); t += 3) std::swap(out->indices[t + 1], out->indices[t + 2]);
  return true;
}

// `names` (when given) receives every mesh's name once the file has loaded; `index` (>= 0)
// chooses the mesh by its number instead of `mesh_name`.
bool ImportGltf(const std::string& base_dir, const std::string& bytes, bool binary,
                const std::string& mesh_name, MeshData* out, Diagnostics* diag,
                std::vector<std::string>* names = nullptr, int index = -1) {
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) {
    diag->Error("", "file is larger than 4 GiB (tinygltf cannot read it)");
    return false;
  }
  // tinygltf's JSON parser recurses: the JSON reader's guard (size, nesting) first, then the
  // structure tinygltf does not check.
  std::string_view json;
  if (!GltfJsonText(bytes, binary, &json, diag)) return false;
  const std::string shape = json_reader::CheckJsonText(json);
  if (!shape.empty()) {
    diag->Error("", std::string("glTF ") + (binary ? "JSON chunk" : "JSON") + ": " + shape);
    return false;
  }
  if (!CheckGltfJson(json, diag)) return false;
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&SkipImages, nullptr);
  GltfFs fs_state;
  loader.SetFsCallbacks(
      tinygltf::FsCallbacks{&FsFileExists, &FsExpandFilePath, &FsReadWholeFile, &FsWriteWholeFile,
                            &fs_state});
  std::string err, warn;
  bool ok = false;
  try {
    if (binary) {
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn,
                                       reinterpret_cast<const unsigned char*>(bytes.data()),
                                       static_cast<unsigned int>(bytes.size()), base_dir);
    } else {
      ok = loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                      static_cast<unsigned int>(bytes.size()), base_dir);
    }
  } catch (const std::exception& e) {
    ok = false;
    err += e.what();
  } catch (...) {
    ok = false;
    err += "unknown exception from tinygltf";
  }
  if (!ok && !fs_state.first_error.empty()) {
    diag->Error("", "glTF buffer " + fs_state.first_error);
    return false;
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    diag->Error("", "invalid glTF: " + (err.empty() ? std::string("tinygltf failed") : err));
    return false;
  }
  if (model.meshes.empty()) {
    diag->Error("", "the file has no meshes (expected at least one mesh)");
    return false;
  }
  if (names) {
    names->clear();
    for (const tinygltf::Mesh& m : model.meshes) names->push_back(m.name);
  }
  size_t mesh_index = 0;
  if (index >= 0) {
    if (size_t(index) >= model.meshes.size()) {
      diag->Error("", "no mesh #" + std::to_string(index) + " (the file has " +
                          std::to_string(model.meshes.size()) + ")");
      return false;
    }
    mesh_index = size_t(index);
  } else if (!mesh_name.empty()) {
    mesh_index = model.meshes.size();
    for (size_t i = 0; i < model.meshes.size(); ++i) {
      if (model.meshes[i].name == mesh_name) {
        mesh_index = i;
        break;
      }
    }
    if (mesh_index == model.meshes.size()) {
      std::string names;
      for (size_t i = 0; i < model.meshes.size(); ++i) {
        if (i) names += ", ";
        names += model.meshes[i].name.empty() ? "#" + std::to_string(i) + " (unnamed)"
                                              : "'" + model.meshes[i].name + "'";
      }
      diag->Error("", "no mesh named '" + mesh_name + "' (available: " + names + ")");
      return false;
    }
  }
  const tinygltf::Mesh& mesh = model.meshes[mesh_index];
  const std::string mesh_where =
      "mesh " +
      (mesh.name.empty() ? "#" + std::to_string(mesh_index) : "'" + mesh.name + "'");
  const bool single = mesh.primitives.size() == 1;

  const size_t errors_before = diag->ErrorCount();
  bool all_normals = true, all_uvs = true;
  std::vector<std::vector<float3>> prim_normals(mesh.primitives.size());
  std::vector<std::vector<float2>> prim_uvs(mesh.primitives.size());
  CappedErrors range_errors(diag, mesh_where, "indices out of range");
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string where = mesh_where + " primitive " + std::to_string(p);
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
      diag->Error(where, std::string("mode ") + std::to_string(prim.mode) + " (" +
                             ModeName(prim.mode) + ") is not supported (expected 4, TRIANGLES)");
      continue;
    }
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) {
      diag->Error(where, "has no POSITION attribute (expected POSITION, VEC3 float)");
      continue;
    }
    AccessorView pos, nrm, uv, idx;
    if (!ViewAccessor(model, pos_it->second, where, "POSITION", TINYGLTF_TYPE_VEC3,
                      {TINYGLTF_COMPONENT_TYPE_FLOAT}, false, &pos, diag)) {
      continue;
    }
    bool prim_ok = true;
    const auto nrm_it = prim.attributes.find("NORMAL");
    const bool has_normals = nrm_it != prim.attributes.end();
    if (has_normals) {
      if (!ViewAccessor(model, nrm_it->second, where, "NORMAL", TINYGLTF_TYPE_VEC3,
                        {TINYGLTF_COMPONENT_TYPE_FLOAT}, false, &nrm, diag)) {
        prim_ok = false;
      } else if (nrm.count != pos.count) {
        diag->Error(where, "accessor count mismatch: NORMAL has " + std::to_string(nrm.count) +
                               " elements, POSITION has " + std::to_string(pos.count) +
                               " (expected equal counts)");
        prim_ok = false;
      }
    }
    const auto uv_it = prim.attributes.find("TEXCOORD_0");
    const bool has_uvs = uv_it != prim.attributes.end();
    if (has_uvs) {
      if (!ViewAccessor(model, uv_it->second, where, "TEXCOORD_0", TINYGLTF_TYPE_VEC2,
                        {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                        true, &uv, diag)) {
        prim_ok = false;
      } else if (uv.count != pos.count) {
        diag->Error(where, "accessor count mismatch: TEXCOORD_0 has " +
                               std::to_string(uv.count) + " elements, POSITION has " +
                               std::to_string(pos.count) + " (expected equal counts)");
        prim_ok = false;
      }
    }
    const bool indexed = prim.indices >= 0;
    if (indexed) {
      if (!ViewAccessor(model, prim.indices, where, "indices", TINYGLTF_TYPE_SCALAR,
                        {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                        false, &idx, diag)) {
        prim_ok = false;
      }
    }
    if (!prim_ok) continue;
    const size_t index_count = indexed ? idx.count : pos.count;
    if (index_count % 3 != 0) {
      diag->Error(where, std::string(indexed ? "index" : "vertex (non-indexed)") + " count " +
                             std::to_string(index_count) +
                             " is not a multiple of 3 (expected whole triangles)");
      continue;
    }
    if (pos.count > std::numeric_limits<uint32_t>::max() - out->positions.size()) {
      diag->Error(where, "too many vertices (expected fewer than 2^32 in total)");
      continue;
    }
    const uint32_t base = static_cast<uint32_t>(out->positions.size());
    const size_t first_triangle = out->indices.size() / 3;
    for (size_t i = 0; i < pos.count; ++i) {
      out->positions.push_back({pos.Float(i, 0), pos.Float(i, 1), pos.Float(i, 2)});
    }
    if (has_normals) {
      prim_normals[p].reserve(pos.count);
      for (size_t i = 0; i < nrm.count; ++i) {
        prim_normals[p].push_back({nrm.Float(i, 0), nrm.Float(i, 1), nrm.Float(i, 2)});
      }
    } else {
      all_normals = false;
    }
    if (has_uvs) {
      prim_uvs[p].reserve(pos.count);
      for (size_t i = 0; i < uv.count; ++i) prim_uvs[p].push_back({uv.Float(i, 0), uv.Float(i, 1)});
    } else {
      all_uvs = false;
    }
    for (size_t i = 0; i < index_count; ++i) {
      const uint32_t v = indexed ? idx.Index(i) : static_cast<uint32_t>(i);
      if (v >= pos.count) {
        const std::string tri = "triangle " + std::to_string(first_triangle + i / 3);
        range_errors.Add(single ? tri : Join(where, tri),
                         "index " + std::to_string(v) + " out of range (" +
                             (single ? "mesh" : "primitive") + " has " +
                             std::to_string(pos.count) + " vertices)");
        out->indices.push_back(0);
        continue;
      }
      out->indices.push_back(base + v);
    }
  }
  if (diag->ErrorCount() > errors_before) return false;

  // Normals / uvs are kept only when every primitive has them (MeshData: empty or #V).
  if (all_normals) {
    for (auto& n : prim_normals) out->normals.insert(out->normals.end(), n.begin(), n.end());
  } else if (std::any_of(prim_normals.begin(), prim_normals.end(),
                         [](const auto& n) { return !n.empty(); })) {
    diag->Warning(mesh_where, "some primitives have no NORMAL; normals dropped for the mesh");
  }
  if (all_uvs) {
    for (auto& t : prim_uvs) out->uvs.insert(out->uvs.end(), t.begin(), t.end());
  } else if (std::any_of(prim_uvs.begin(), prim_uvs.end(),
                         [](const auto& t) { return !t.empty(); })) {
    diag->Warning(mesh_where,
                  "some primitives have no TEXCOORD_0; texture coordinates dropped for the mesh");
  }
  if (!ApplyPlacement(model, mesh_index, mesh_where, out, diag)) return false;
  if (!CheckFinite(*out, diag)) return false;
  // What is not read is said, not dropped silently.
  size_t targets = 0;
  for (const auto& prim : mesh.primitives) targets = std::max(targets, prim.targets.size());
  if (targets > 0)
    diag->Warning(mesh_where, "has " + std::to_string(targets) +
                                  " morph targets; ignored (the base shape is read, no weights "
                                  "applied)");
  if (!model.skins.empty())
    diag->Warning("", "the file has " + std::to_string(model.skins.size()) +
                          " skin(s); ignored (positions are the mesh's bind pose, no joints "
                          "applied)");
  if (out->triangle_count() == 0) {
    diag->Error(mesh_where, "has no triangles (expected at least one TRIANGLES primitive "
                            "with 3 or more vertices)");
    return false;
  }
  return true;
}

// ------------------------------------------------------------------------------------------
// OBJ

// Receives what OpenMesh's OBJ reader parses, without building any connectivity.
class RawObjImporter : public OpenMesh::IO::BaseImporter {
 public:
  std::vector<float3> positions;
  std::vector<std::vector<int>> faces;          // raw vertex handles, as OpenMesh passed them
  std::vector<std::vector<float2>> face_uvs;    // per face corner (empty when none)

  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
    positions.push_back({p[0], p[1], p[2]});
    return OpenMesh::VertexHandle(static_cast<int>(positions.size()) - 1);
  }
  OpenMesh::VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3f(0, 0, 0)); }
  OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override {
    return OpenMesh::HalfedgeHandle();
  }
  OpenMesh::FaceHandle add_face(const VHandles& vhs) override {
    std::vector<int> f;
    f.reserve(vhs.size());
    for (const auto& vh : vhs) f.push_back(vh.idx());
    faces.push_back(std::move(f));
    face_uvs.emplace_back();
    return OpenMesh::FaceHandle(static_cast<int>(faces.size()) - 1);
  }
  OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override {
    return OpenMesh::FaceHandle();
  }
  void add_face_texcoords(OpenMesh::FaceHandle fh, OpenMesh::VertexHandle,
                          const std::vector<OpenMesh::Vec2f>& tcs) override {
    if (!fh.is_valid() || static_cast<size_t>(fh.idx()) >= face_uvs.size()) return;
    auto& dst = face_uvs[static_cast<size_t>(fh.idx())];
    dst.clear();
    for (const auto& t : tcs) dst.push_back({t[0], t[1]});
  }
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                          const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(OpenMesh::FaceHandle, int) override {}
  void set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& p) override {
    if (vh.is_valid() && static_cast<size_t>(vh.idx()) < positions.size())
      positions[static_cast<size_t>(vh.idx())] = {p[0], p[1], p[2]};
  }
  void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
  void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  size_t n_vertices() const override { return positions.size(); }
  size_t n_faces() const override { return faces.size(); }
  size_t n_edges() const override { return 0; }
};

struct ObjCorner {
  int64_t raw_v = 0, raw_vt = 0;  // as written (1-based, or negative = relative)
  int64_t v = -1;                 // 0-based position index (resolved; checked later)
  int64_t vt = -1;                // 0-based texcoord index when has_vt
  bool has_vt = false;
};
struct ObjFace {
  size_t line = 0;
  bool unreadable = false;  // a corner could not be parsed (already reported)
  std::vector<ObjCorner> corners;
};
struct ObjScan {
  size_t v_count = 0, vt_count = 0;
  std::vector<double> vt_v;  // each `vt` line's v, as double (flipped exactly: 1 - v)
  std::vector<ObjFace> faces;
  bool uses_vt = false;
};

std::vector<std::string> SplitWs(const std::string& s, size_t from) {
  std::vector<std::string> out;
  size_t i = from;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    size_t j = i;
    while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

bool ParseFloat(const std::string& tok, float* v) {
  char* end = nullptr;
  *v = std::strtof(tok.c_str(), &end);
  return end == tok.c_str() + tok.size() && !tok.empty();
}

bool ParseInt(const std::string& tok, int64_t* v) {
  if (tok.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long long x = std::strtoll(tok.c_str(), &end, 10);
  if (end != tok.c_str() + tok.size() || errno == ERANGE) return false;
  *v = x;
  return true;
}

// The validating scan (see the file comment). Returns false after recording problems.
bool ScanObj(const std::string& bytes, ObjScan* scan,
             Diagnostics* diag) {
  const size_t errors_before = diag->ErrorCount();
  CappedErrors bad_v(diag, "", "bad 'v' lines");
  CappedErrors bad_vt(diag, "", "bad 'vt' lines");
  CappedErrors bad_f(diag, "", "bad faces");
  bool warned_lines = false;
  size_t line_no = 0;
  size_t pos = 0;
  while (pos < bytes.size()) {
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    size_t start = 0;
    while (start < line.size() && std::isspace(static_cast<unsigned char>(line[start]))) ++start;
    line.erase(0, start);  // OpenMesh trims lines too
    if (line.empty() || line[0] == '#') continue;
    size_t kw_end = 0;
    while (kw_end < line.size() && !std::isspace(static_cast<unsigned char>(line[kw_end]))) ++kw_end;
    const std::string kw = line.substr(0, kw_end);
    const std::string at = "line " + std::to_string(line_no);
    if (kw == "v") {
      const auto tok = SplitWs(line, kw_end);
      float x[3];
      const size_t k = scan->v_count++;
      const std::string where = at + ": vertex " + std::to_string(k);
      if (tok.size() < 3 || !ParseFloat(tok[0], &x[0]) || !ParseFloat(tok[1], &x[1]) ||
          !ParseFloat(tok[2], &x[2])) {
        bad_v.Add(where, "cannot read the position (expected three numbers after 'v')");
      } else if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) {
        bad_v.Add(where, "position is not finite (" + tok[0] + " " + tok[1] + " " + tok[2] +
                             "; expected finite numbers)");
      }
    } else if (kw == "vt") {
      const auto tok = SplitWs(line, kw_end);
      float t[2];
      const size_t k = scan->vt_count++;
      const std::string where = at + ": texcoord " + std::to_string(k);
      scan->vt_v.push_back(tok.size() >= 2 ? std::strtod(tok[1].c_str(), nullptr) : 0.0);
      if (tok.size() < 2 || !ParseFloat(tok[0], &t[0]) || !ParseFloat(tok[1], &t[1])) {
        bad_vt.Add(where, "cannot read the texture coordinate (expected two numbers after "
                          "'vt')");
      } else if (!std::isfinite(t[0]) || !std::isfinite(t[1])) {
        bad_vt.Add(where, "texture coordinate is not finite (" + tok[0] + " " + tok[1] +
                              "; expected finite numbers)");
      }
    } else if (kw == "f") {
      // Indices are resolved here (negative ones are relative to the lines read so far, as
      // in OpenMesh) and range-checked after the scan, when the totals are known: OpenMesh
      // reads all `v` and `vt` lines before any face, so forward references are legal.
      const size_t f = scan->faces.size();
      ObjFace face;
      face.line = line_no;
      for (const std::string& tok : SplitWs(line, kw_end)) {
        const size_t s1 = tok.find('/');
        const std::string vs = tok.substr(0, s1);
        std::string ts;
        if (s1 != std::string::npos) {
          const size_t s2 = tok.find('/', s1 + 1);
          ts = tok.substr(s1 + 1, s2 == std::string::npos ? std::string::npos : s2 - s1 - 1);
        }
        ObjCorner c;
        if (!ParseInt(vs, &c.raw_v) || (!ts.empty() && !ParseInt(ts, &c.raw_vt))) {
          bad_f.Add(at + ": face " + std::to_string(f),
                    "cannot read corner '" + tok +
                        "' (expected v, v/vt, v//vn or v/vt/vn with integer indices)");
          face.unreadable = true;
          continue;
        }
        c.v = c.raw_v > 0 ? c.raw_v - 1 : static_cast<int64_t>(scan->v_count) + c.raw_v;
        if (!ts.empty()) {
          c.has_vt = true;
          c.vt = c.raw_vt > 0 ? c.raw_vt - 1 : static_cast<int64_t>(scan->vt_count) + c.raw_vt;
        }
        face.corners.push_back(c);
      }
      scan->faces.push_back(std::move(face));
    } else if (kw == "l" || kw == "p" || kw == "curv" || kw == "surf") {
      if (!warned_lines) {
        diag->Warning(at, "'" + kw + "' elements are ignored (only faces are imported)");
        warned_lines = true;
      }
    }
  }
  const int64_t nv = static_cast<int64_t>(scan->v_count);
  const int64_t nt = static_cast<int64_t>(scan->vt_count);
  for (const ObjFace& face : scan->faces) {
    for (const ObjCorner& c : face.corners) scan->uses_vt = scan->uses_vt || c.has_vt;
  }
  auto describe = [](const std::string& what, int64_t raw, int64_t total) {
    const std::string n = std::to_string(total);
    const std::string plural = what == "vertex" ? "vertices" : what + "s";
    if (raw == 0) {
      return "references " + what + " 0, but OBJ indices start at 1 (the file has " + n + " " +
             plural + ")";
    }
    if (raw < 0) {
      return "references " + what + " " + std::to_string(raw) + ", which is before the first " +
             what + " (relative index)";
    }
    return "references " + what + " " + std::to_string(raw) + ", but the file has " + n + " " +
           plural + " (OBJ indices run from 1 to " + n + ")";
  };
  for (size_t f = 0; f < scan->faces.size(); ++f) {
    const ObjFace& face = scan->faces[f];
    const std::string where =
        "line " + std::to_string(face.line) + ": face " + std::to_string(f);
    bool ok = !face.unreadable;
    if (face.corners.size() < 3 && !face.unreadable) {
      bad_f.Add(where, "has " + std::to_string(face.corners.size()) +
                           " corners (expected at least 3)");
      ok = false;
    }
    for (size_t k = 0; k < face.corners.size(); ++k) {
      const ObjCorner& c = face.corners[k];
      if (c.v < 0 || c.v >= nv || c.raw_v == 0) {
        bad_f.Add(where, describe("vertex", c.raw_v, nv));
        ok = false;
      }
      if (c.has_vt && (c.vt < 0 || c.vt >= nt || c.raw_vt == 0)) {
        bad_f.Add(where, describe("texcoord", c.raw_vt, nt));
        ok = false;
      }
      if (scan->uses_vt && !c.has_vt) {
        bad_f.Add(where, "corner " + std::to_string(k) +
                             " has no texcoord, but other corners have (expected v/vt on "
                             "every corner or on none)");
        ok = false;
      }
    }
    for (size_t a = 0; ok && a < face.corners.size(); ++a) {
      for (size_t b = a + 1; b < face.corners.size(); ++b) {
        if (face.corners[a].v == face.corners[b].v) {
          bad_f.Add(where, "uses vertex " + std::to_string(face.corners[a].v + 1) +
                               " twice (expected distinct vertices; OpenMesh would silently "
                               "alter this face)");
          ok = false;
          break;
        }
      }
    }
  }
  if (scan->faces.empty() && bad_v.count() + bad_vt.count() == 0) {
    diag->Error("", "no faces (expected at least one 'f' line; the mesh is empty)");
  }
  return diag->ErrorCount() == errors_before;  // every kind records its first error at once
}

bool ImportObj(const std::string& bytes, MeshData* out,
               Diagnostics* diag) {
  ObjScan scan;
  if (!ScanObj(bytes, &scan, diag)) return false;

  // OpenMesh opens an `mtllib` file by name (a FIFO there would block it, a huge file be read
  // whole); materials are never used, so those lines are blanked before OpenMesh sees them.
  std::string text = bytes;
  bool warned_mtllib = false;
  size_t line_no = 1;
  for (size_t i = 0; i < text.size(); ++i) {
    if (i == 0 || text[i - 1] == '\n') {
      if (i > 0) ++line_no;
      size_t k = i;
      while (k < text.size() && (text[k] == ' ' || text[k] == '\t')) ++k;
      if (text.compare(k, 6, "mtllib") == 0 &&
          (k + 6 == text.size() || std::isspace(static_cast<unsigned char>(text[k + 6])))) {
        if (!warned_mtllib) {
          diag->Warning("line " + std::to_string(line_no),
                        "'mtllib' ignored (materials are not read)");
          warned_mtllib = true;
        }
        text[k] = '#';
      }
    }
  }
  RawObjImporter importer;
  OpenMesh::IO::Options options = OpenMesh::IO::Options::FaceTexCoord;
  std::istringstream stream(text);
  bool read_ok = false;
  try {
    // OpenMesh's reader modules are singletons with per-read state (path, materials).
    static std::mutex openmesh_mutex;
    std::lock_guard<std::mutex> lock(openmesh_mutex);
    read_ok = OpenMesh::IO::IOManager().read(stream, "obj", importer, options);
  } catch (...) {
    read_ok = false;
  }
  if (!read_ok) {
    diag->Error("", "OpenMesh's OBJ reader failed (see its messages on stderr)");
    return false;
  }
  // Cross-check OpenMesh against the scan: every vertex and face, nothing altered.
  if (importer.positions.size() != scan.v_count) {
    diag->Error("", "OpenMesh read " + std::to_string(importer.positions.size()) +
                          " vertices, but the file has " + std::to_string(scan.v_count) +
                          " 'v' lines (unsupported OBJ syntax?)");
    return false;
  }
  if (importer.faces.size() != scan.faces.size()) {
    diag->Error("", "OpenMesh read " + std::to_string(importer.faces.size()) +
                          " faces, but the file has " + std::to_string(scan.faces.size()) +
                          " 'f' lines (unsupported OBJ syntax?)");
    return false;
  }
  for (size_t f = 0; f < scan.faces.size(); ++f) {
    const ObjFace& face = scan.faces[f];
    bool same = importer.faces[f].size() == face.corners.size();
    for (size_t c = 0; same && c < face.corners.size(); ++c) {
      same = importer.faces[f][c] == face.corners[c].v;
    }
    if (same && scan.uses_vt) same = importer.face_uvs[f].size() == face.corners.size();
    if (!same) {
      diag->Error("line " + std::to_string(face.line) + ": face " + std::to_string(f),
                  "OpenMesh read this face differently from the file (unsupported OBJ "
                  "syntax?)");
      return false;
    }
  }

  // Vertex layout: vertices 0..#v-1 are the file's `v` entries in file order (each with the
  // texcoord of its first use), so OBJ vertex k (1-based) is vertex k-1 here and, after
  // welding, point k-1 when no positions coincide. Each further distinct (v, vt) pair is a
  // seam duplicate, appended in order of first use.
  out->positions = importer.positions;
  if (scan.uses_vt) out->uvs.assign(out->positions.size(), float2{});
  std::vector<int64_t> first_vt(out->positions.size(), -1);
  std::unordered_map<uint64_t, uint32_t> split;
  std::vector<uint32_t> corner_vertex;
  for (size_t f = 0; f < scan.faces.size(); ++f) {
    const ObjFace& face = scan.faces[f];
    corner_vertex.clear();
    for (size_t c = 0; c < face.corners.size(); ++c) {
      const ObjCorner& k = face.corners[c];
      uint32_t vid = static_cast<uint32_t>(k.v);
      if (scan.uses_vt) {
        // OBJ's v runs up from the bottom of the image, glTF's (and MeshData's) down from the top.
        // In double, from the file's text: 1 - v is exact for every v the writer wrote.
        const float2 uv = {importer.face_uvs[f][c].x,
                           static_cast<float>(1.0 - scan.vt_v[static_cast<size_t>(k.vt)])};
        if (first_vt[k.v] < 0) {
          first_vt[k.v] = k.vt;
          out->uvs[vid] = uv;
        } else if (first_vt[k.v] != k.vt) {
          const uint64_t key = (static_cast<uint64_t>(k.v) << 32) | static_cast<uint64_t>(k.vt);
          const auto it = split.find(key);
          if (it != split.end()) {
            vid = it->second;
          } else {
            vid = static_cast<uint32_t>(out->positions.size());
            out->positions.push_back(out->positions[k.v]);
            out->uvs.push_back(uv);
            split.emplace(key, vid);
          }
        }
      }
      corner_vertex.push_back(vid);
    }
    for (size_t c = 1; c + 1 < corner_vertex.size(); ++c) {  // fan triangulation
      out->indices.push_back(corner_vertex[0]);
      out->indices.push_back(corner_vertex[c]);
      out->indices.push_back(corner_vertex[c + 1]);
    }
  }
  return CheckFinite(*out, diag);
}

// ------------------------------------------------------------------------------------------
// Export

bool CheckExportable(const MeshData& mesh, Diagnostics* diag) {
  bool ok = true;
  if (mesh.positions.empty() || mesh.indices.empty()) {
    diag->Error("", "nothing to write: the mesh has " + std::to_string(mesh.vertex_count()) +
                          " vertices and " + std::to_string(mesh.triangle_count()) +
                          " triangles (expected at least one triangle)");
    ok = false;
  }
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
    diag->Error("", "mesh has " + std::to_string(mesh.normals.size()) + " normals for " +
                          std::to_string(mesh.positions.size()) + " vertices (expected 0 or " +
                          std::to_string(mesh.positions.size()) + ")");
    ok = false;
  }
  if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()) {
    diag->Error("", "mesh has " + std::to_string(mesh.uvs.size()) + " uvs for " +
                          std::to_string(mesh.positions.size()) + " vertices (expected 0 or " +
                          std::to_string(mesh.positions.size()) + ")");
    ok = false;
  }
  if (mesh.indices.size() % 3 != 0) {
    diag->Error("", "index count " + std::to_string(mesh.indices.size()) +
                          " is not a multiple of 3 (expected whole triangles)");
    ok = false;
  }
  CappedErrors range(diag, "", "indices out of range");
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size()) {
      range.Add("triangle " + std::to_string(i / 3),
                "index " + std::to_string(mesh.indices[i]) + " out of range (mesh has " +
                    std::to_string(mesh.positions.size()) + " vertices)");
    }
  }
  if (range.count()) ok = false;
  if (!CheckFinite(mesh, diag)) ok = false;
  return ok;
}

// One OBJ object: `header` (a comment, or `o NAME`) then its elements; `base` is the number
// of vertices written before it (OBJ indices are global and 1-based).
std::string ObjText(const MeshData& mesh, const std::string& header = "", size_t base = 0) {
  std::string s;
  s.reserve(mesh.positions.size() * 80 + mesh.indices.size() * 12);
  char buf[160];
  if (header.empty()) {
    std::snprintf(buf, sizeof(buf), "# mimetic: %zu vertices, %zu triangles\n",
                  mesh.vertex_count(), mesh.triangle_count());
    s += buf;
  } else {
    s += header;
  }
  for (const float3& p : mesh.positions) {
    std::snprintf(buf, sizeof(buf), "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
    s += buf;
  }
  for (const float2& t : mesh.uvs) {
    // OBJ's v runs up: 1 - v, in double and with 17 digits so that reading it back (1 - v
    // again, in double) gives the same float.
    std::snprintf(buf, sizeof(buf), "vt %.9g %.17g\n", t.x, 1.0 - static_cast<double>(t.y));
    s += buf;
  }
  for (const float3& n : mesh.normals) {
    std::snprintf(buf, sizeof(buf), "vn %.9g %.9g %.9g\n", n.x, n.y, n.z);
    s += buf;
  }
  const bool vt = !mesh.uvs.empty(), vn = !mesh.normals.empty();
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    s += 'f';
    for (int c = 0; c < 3; ++c) {
      const unsigned i = static_cast<unsigned>(mesh.indices[3 * t + c] + base + 1);
      if (vt && vn) std::snprintf(buf, sizeof(buf), " %u/%u/%u", i, i, i);
      else if (vt) std::snprintf(buf, sizeof(buf), " %u/%u", i, i);
      else if (vn) std::snprintf(buf, sizeof(buf), " %u//%u", i, i);
      else std::snprintf(buf, sizeof(buf), " %u", i);
      s += buf;
    }
    s += '\n';
  }
  return s;
}

bool GlbBytes(const std::vector<NamedMesh>& meshes, double metres_per_unit, std::string* out,
              Diagnostics* diag) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "mimetic";
  tinygltf::Buffer buffer;
  auto append = [&](const void* data, size_t bytes, int target) {
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = buffer.data.size();
    bv.byteLength = bytes;
    bv.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.data.insert(buffer.data.end(), p, p + bytes);
    model.bufferViews.push_back(bv);
    return static_cast<int>(model.bufferViews.size()) - 1;
  };
  auto accessor = [&](int view, int component, size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = 0;
    a.componentType = component;
    a.count = count;
    a.type = type;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size()) - 1;
  };
  for (const NamedMesh& named : meshes) {
  const MeshData& mesh = *named.mesh;
  const size_t nv = mesh.positions.size();
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  const int pos = accessor(append(mesh.positions.data(), nv * sizeof(float3),
                                  TINYGLTF_TARGET_ARRAY_BUFFER),
                           TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
  float3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const float3& p : mesh.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  model.accessors[pos].minValues = {lo.x, lo.y, lo.z};
  model.accessors[pos].maxValues = {hi.x, hi.y, hi.z};
  prim.attributes["POSITION"] = pos;
  if (!mesh.normals.empty()) {
    prim.attributes["NORMAL"] =
        accessor(append(mesh.normals.data(), nv * sizeof(float3), TINYGLTF_TARGET_ARRAY_BUFFER),
                 TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
  }
  if (!mesh.uvs.empty()) {
    static_assert(sizeof(float2) == 8, "float2 must be tightly packed");
    prim.attributes["TEXCOORD_0"] =
        accessor(append(mesh.uvs.data(), nv * sizeof(float2), TINYGLTF_TARGET_ARRAY_BUFFER),
                 TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC2);
  }
  prim.indices = accessor(append(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t),
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                          TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, mesh.indices.size(),
                          TINYGLTF_TYPE_SCALAR);
  tinygltf::Mesh gmesh;
  gmesh.name = named.name;
  gmesh.primitives.push_back(prim);
  model.meshes.push_back(gmesh);
  }
  model.buffers.push_back(std::move(buffer));
  tinygltf::Scene scene;
  for (size_t k = 0; k < meshes.size(); ++k) {
    tinygltf::Node node;
    node.mesh = static_cast<int>(k);
    if (metres_per_unit != 1.0) {
      // glTF's unit is the metre: the positions stay in mesh units, the node scales them.
      node.name = k == 0 ? "mimetic_units" : "mimetic_units_" + meshes[k].name;
      node.scale = {metres_per_unit, metres_per_unit, metres_per_unit};
    }
    model.nodes.push_back(node);
    scene.nodes.push_back(static_cast<int>(k));
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  std::ostringstream ss;
  bool ok = false;
  try {
    tinygltf::TinyGLTF writer;
    ok = writer.WriteGltfSceneToStream(&model, ss, false, true);
  } catch (...) {
    ok = false;
  }
  if (!ok) {
    diag->Error("", "tinygltf could not serialise the mesh");
    return false;
  }
  *out = ss.str();
  return true;
}

}  // namespace

bool ImportMesh(const std::string& path, const std::string& mesh_name, MeshData* out,
                Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "ImportMesh: no output mesh given");
    return false;
  }
  *out = MeshData{};
  out->source = path;
  const std::string ext = LowerExtension(path);
  if (ext != ".gltf" && ext != ".glb" && ext != ".obj") {
    diag->Error("", "unknown mesh file extension '" + ext + "' (expected .gltf, .glb or .obj)");
    return false;
  }
  std::string bytes;
  Diagnostics read;
  if (!ReadFile(path, &bytes, &read, kMaxMeshFileBytes, ext.substr(1) + " mesh file")) {
    for (const Diagnostic& d : read.items()) diag->Error("", d.what);  // callers name the file
    return false;
  }
  const bool ok = ImportMeshBytes(bytes, ext, DirectoryOf(path), mesh_name, out, diag);
  out->source = path;
  return ok;
}

namespace {

// One `o NAME` line of an OBJ: where it starts, its name, and the v / vt / vn lines before it.
struct ObjObjectStart {
  size_t at;
  std::string name;
  size_t before[3];
};

// The object starts of an OBJ text, stopping after `limit` of them (the v / vt / vn counts are
// counted up to the last one returned).
std::vector<ObjObjectStart> ObjObjectStarts(const std::string& bytes, size_t limit) {
  std::vector<ObjObjectStart> starts;
  size_t counts[3] = {0, 0, 0};
  for (size_t at = 0; at < bytes.size() && starts.size() < limit;) {
    size_t nl = bytes.find('\n', at);
    if (nl == std::string::npos) nl = bytes.size();
    if (bytes.compare(at, 2, "o ") == 0 || bytes.compare(at, 2, "o\t") == 0) {
      std::string name = bytes.substr(at + 2, nl - at - 2);
      while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
      starts.push_back({at, name, {counts[0], counts[1], counts[2]}});
    } else if (bytes.compare(at, 2, "v ") == 0 || bytes.compare(at, 2, "v\t") == 0) {
      ++counts[0];
    } else if (bytes.compare(at, 3, "vt ") == 0 || bytes.compare(at, 3, "vt\t") == 0) {
      ++counts[1];
    } else if (bytes.compare(at, 3, "vn ") == 0 || bytes.compare(at, 3, "vn\t") == 0) {
      ++counts[2];
    }
    at = nl + 1;
  }
  return starts;
}

}  // namespace

bool ImportMeshBytes(const std::string& bytes, const std::string& extension,
                     const std::string& base_dir, const std::string& mesh_name, MeshData* out,
                     Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "ImportMesh: no output mesh given");
    return false;
  }
  *out = MeshData{};
  try {
    std::string ext = extension;
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".gltf" && ext != ".glb" && ext != ".obj") {
      diag->Error("", "unknown mesh file extension '" + ext +
                            "' (expected .gltf, .glb or .obj)");
      return false;
    }
    if (bytes.empty()) {
      diag->Error("", "file is empty (expected a " + ext.substr(1) + " mesh)");
      return false;
    }
    if (ext == ".obj" && bytes.find('\0') != std::string::npos) {
      diag->Error("", std::string("binary data (NUL bytes) in an OBJ file; expected text") +
                          (bytes.compare(0, 4, "glTF") == 0 ? " (this is a GLB file: rename it .glb)"
                                                            : ""));
      return false;
    }
    if (ext == ".gltf" && bytes.compare(0, 4, "glTF") == 0) {
      diag->Error("", "binary glTF in a .gltf file (expected JSON text; rename it .glb)");
      return false;
    }
    // An OBJ with several objects (`o` lines): the first object alone, as a glTF's first mesh
    // (mimetic writes a rig's companion meshes, the sample head's eyes, as further objects).
    size_t second_object = std::string::npos;
    if (ext == ".obj") {
      const std::vector<ObjObjectStart> starts = ObjObjectStarts(bytes, 2);
      if (starts.size() == 2) second_object = starts[1].at;
    }
    bool ok = ext == ".obj"
                  ? (second_object == std::string::npos
                         ? ImportObj(bytes, out, diag)
                         : ImportObj(bytes.substr(0, second_object), out, diag))
                  : ImportGltf(base_dir, bytes, ext == ".glb", mesh_name, out, diag);
    if (ok && ext == ".obj" && !mesh_name.empty()) {
      diag->Warning("", "mesh name '" + mesh_name + "' ignored: OBJ files hold one mesh");
    }
    if (!ok) *out = MeshData{};
    return ok;
  } catch (const std::exception& e) {
    diag->Error("", std::string("internal error while importing: ") + e.what());
  } catch (...) {
    diag->Error("", "internal error while importing");
  }
  *out = MeshData{};
  return false;
}

namespace {

// The face lines of one OBJ object with their positive indices made local to it: `offsets`
// holds the v, vt and vn lines before the object (OBJ numbers every vertex of the file from
// 1). Relative (negative) indices stay. False, naming the line, for an index that reaches a
// vertex before the object or is not a number.
bool RebaseObjFaces(const std::string& text, const size_t offsets[3], const std::string& object,
                    std::string* out, Diagnostics* diag) {
  out->clear();
  out->reserve(text.size());
  size_t line_no = 0;
  for (size_t at = 0; at < text.size();) {
    size_t nl = text.find('\n', at);
    if (nl == std::string::npos) nl = text.size();
    const std::string line = text.substr(at, nl - at);
    ++line_no;
    at = nl + 1;
    if (line.size() < 2 || line[0] != 'f' || (line[1] != ' ' && line[1] != '\t')) {
      *out += line;
      *out += '\n';
      continue;
    }
    std::string rebased = "f";
    size_t i = 1;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i >= line.size()) break;
      rebased += ' ';
      int component = 0;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') {
        if (line[i] == '/') {
          rebased += '/';
          ++component;
          ++i;
          continue;
        }
        size_t end = i;
        if (line[end] == '-' || line[end] == '+') ++end;
        while (end < line.size() && line[end] >= '0' && line[end] <= '9') ++end;
        const std::string number = line.substr(i, end - i);
        if (component > 2 || number.empty() || number == "-" || number == "+" ||
            end - i > 12) {
          diag->Error("object " + object + ", line " + std::to_string(line_no),
                      "face index '" + line.substr(i, std::min<size_t>(end - i + 1, 20)) +
                          "' is not a vertex number");
          return false;
        }
        long long v = std::stoll(number);
        if (v > 0) {
          v -= static_cast<long long>(offsets[component]);
          if (v < 1) {
            diag->Error("object " + object + ", line " + std::to_string(line_no),
                        "face refers to a vertex before the object (OBJ objects after the "
                        "first must use their own vertices)");
            return false;
          }
        }
        rebased += std::to_string(v);
        i = end;
      }
    }
    *out += rebased;
    *out += '\n';
  }
  return true;
}

// ImportOtherMeshes for an OBJ file: read it, then ImportOtherObjBytes.
bool ImportOtherObjObjects(const std::string& path, std::vector<NamedMeshData>* out,
                           Diagnostics* diag, std::string* chosen_name) {
  std::string bytes;
  Diagnostics read;
  if (!ReadFile(path, &bytes, &read, kMaxMeshFileBytes, "obj mesh file")) {
    for (const Diagnostic& d : read.items()) diag->Error("", d.what);
    return false;
  }
  if (!ImportOtherObjBytes(bytes, DirectoryOf(path), out, diag, chosen_name)) return false;
  for (NamedMeshData& m : *out) m.mesh.source = path;
  return true;
}

}  // namespace

bool ImportOtherObjBytes(const std::string& bytes, const std::string& base_dir,
                         std::vector<NamedMeshData>* out, Diagnostics* diag,
                         std::string* chosen_name) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "ImportOtherObjBytes: no output given");
    return false;
  }
  out->clear();
  try {
    // ImportMeshBytes reads everything before the second `o` line as the first mesh; the
    // others start there.
    const std::vector<ObjObjectStart> starts = ObjObjectStarts(bytes, ~size_t{0});
    if (chosen_name) *chosen_name = starts.empty() ? std::string("mesh") : starts[0].name;
    for (size_t k = 1; k < starts.size(); ++k) {
      const size_t end = k + 1 < starts.size() ? starts[k + 1].at : bytes.size();
      NamedMeshData named;
      named.name = starts[k].name.empty() ? "mesh_" + std::to_string(k) : starts[k].name;
      std::string text;
      Diagnostics one;
      if (!RebaseObjFaces(bytes.substr(starts[k].at, end - starts[k].at), starts[k].before,
                          named.name, &text, &one) ||
          !ImportMeshBytes(text, ".obj", base_dir, "", &named.mesh, &one)) {
        diag->Append(one, "mesh " + named.name);
        out->clear();
        return false;
      }
      out->push_back(std::move(named));
    }
    return true;
  } catch (const std::exception& e) {
    diag->Error("", std::string("internal error while importing: ") + e.what());
  } catch (...) {
    diag->Error("", "internal error while importing");
  }
  out->clear();
  return false;
}

bool ImportOtherMeshes(const std::string& path, const std::string& mesh_name,
                       std::vector<NamedMeshData>* out, Diagnostics* diag,
                       std::string* chosen_name) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "ImportOtherMeshes: no output given");
    return false;
  }
  out->clear();
  const std::string ext = LowerExtension(path);
  if (ext == ".obj") return ImportOtherObjObjects(path, out, diag, chosen_name);
  if (ext != ".gltf" && ext != ".glb") {
    diag->Error("", "unknown mesh file extension '" + ext + "' (expected .gltf, .glb or .obj)");
    return false;
  }
  std::string bytes;
  Diagnostics read;
  if (!ReadFile(path, &bytes, &read, kMaxMeshFileBytes, ext.substr(1) + " mesh file")) {
    for (const Diagnostic& d : read.items()) diag->Error("", d.what);
    return false;
  }
  try {
    std::vector<std::string> names;
    MeshData first;
    if (!ImportGltf(DirectoryOf(path), bytes, ext == ".glb", mesh_name, &first, diag, &names))
      return false;
    size_t skip = 0;
    for (size_t i = 0; i < names.size() && !mesh_name.empty(); ++i)
      if (names[i] == mesh_name) {
        skip = i;
        break;
      }
    if (chosen_name && skip < names.size()) *chosen_name = names[skip];
    for (size_t i = 0; i < names.size(); ++i) {
      if (i == skip) continue;
      NamedMeshData named;
      named.name = names[i].empty() ? "mesh_" + std::to_string(i) : names[i];
      Diagnostics one;
      if (!ImportGltf(DirectoryOf(path), bytes, ext == ".glb", "", &named.mesh, &one, nullptr,
                      int(i))) {
        diag->Append(one, "mesh " + named.name);
        out->clear();
        return false;
      }
      named.mesh.source = path;
      out->push_back(std::move(named));
    }
  } catch (const std::exception& e) {
    diag->Error("", std::string("internal error while importing: ") + e.what());
    out->clear();
    return false;
  }
  return true;
}

double MetresPerUnit(const std::string& units) {
  if (units == "mm") return 0.001;
  if (units == "cm") return 0.01;
  if (units == "dm") return 0.1;
  if (units == "m") return 1.0;
  if (units == "in") return 0.0254;
  return 0.0;
}

bool ExportMesh(const std::string& path, const MeshData& mesh, Diagnostics* diag,
                double metres_per_unit) {
  return ExportMeshes(path, {{"mesh", &mesh}}, diag, metres_per_unit);
}

bool ExportMeshes(const std::string& path, const std::vector<NamedMesh>& meshes,
                  Diagnostics* diag, double metres_per_unit) {
  Diagnostics local;
  if (!diag) diag = &local;
  try {
    const std::string ext = LowerExtension(path);
    if (ext != ".obj" && ext != ".glb") {
      diag->Error("", "unknown export extension '" + ext + "' (expected .obj or .glb)");
      return false;
    }
    if (meshes.empty()) {
      diag->Error("", "nothing to write: no meshes (expected at least one)");
      return false;
    }
    bool ok = true;
    std::set<std::string> names;
    for (size_t k = 0; k < meshes.size(); ++k) {
      const std::string where = "mesh " + std::to_string(k) + " '" + meshes[k].name + "'";
      if (!meshes[k].mesh) {
        diag->Error(where, "no mesh data");
        ok = false;
        continue;
      }
      if (meshes[k].name.empty() || !names.insert(meshes[k].name).second) {
        diag->Error(where, "mesh names must be distinct and not empty");
        ok = false;
      }
      Diagnostics one;
      if (!CheckExportable(*meshes[k].mesh, &one)) ok = false;
      diag->Append(one, meshes.size() == 1 ? "" : where);
    }
    if (!ok) return false;
    std::string bytes;
    if (ext == ".obj") {
      if (meshes.size() == 1) {
        bytes = ObjText(*meshes[0].mesh);
      } else {
        // One object per mesh (`o NAME`); ImportMesh reads the first object.
        size_t base = 0;
        for (const NamedMesh& m : meshes) {
          char head[200];
          std::snprintf(head, sizeof(head), "# mimetic: %zu vertices, %zu triangles\no %s\n",
                        m.mesh->vertex_count(), m.mesh->triangle_count(), m.name.c_str());
          bytes += ObjText(*m.mesh, head, base);
          base += m.mesh->vertex_count();
        }
      }
    } else if (!(metres_per_unit > 0 && std::isfinite(metres_per_unit))) {
      diag->Error("", "metres per mesh unit is " + FormatG(metres_per_unit) +
                          " (expected a finite number > 0)");
      return false;
    } else if (!GlbBytes(meshes, metres_per_unit, &bytes, diag)) {
      return false;
    }
    return WriteFileAtomic(path, bytes, diag);
  } catch (const std::exception& e) {
    diag->Error("", std::string("internal error while exporting: ") + e.what());
  } catch (...) {
    diag->Error("", "internal error while exporting");
  }
  return false;
}

}  // namespace mimetic
