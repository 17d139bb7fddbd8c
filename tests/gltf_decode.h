// tests/gltf_decode.h: reading a baked .glb back with tinygltf for the bake tests: an
// accessor's float values with a sparse accessor expanded (glTF 2.0 §3.6.2.3), written here
// independently of io/gltf_bake.cpp.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace mimetic::test {

inline bool LoadGlb(const std::string& bytes, tinygltf::Model* model, std::string* err) {
  tinygltf::TinyGLTF loader;
  std::string warn;
  return loader.LoadBinaryFromMemory(model, err, &warn,
                                     reinterpret_cast<const unsigned char*>(bytes.data()),
                                     unsigned(bytes.size()));
}

inline const unsigned char* ViewBytes(const tinygltf::Model& m, int view, size_t offset) {
  const tinygltf::BufferView& bv = m.bufferViews.at(size_t(view));
  return m.buffers.at(size_t(bv.buffer)).data.data() + bv.byteOffset + offset;
}

inline size_t Components(int type) {
  return type == TINYGLTF_TYPE_SCALAR ? 1 : type == TINYGLTF_TYPE_VEC2 ? 2
         : type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
}

// Float accessor -> count * components floats (tightly packed views only, as the bake writes).
inline std::vector<float> ReadFloats(const tinygltf::Model& m, int accessor) {
  const tinygltf::Accessor& a = m.accessors.at(size_t(accessor));
  const size_t n = Components(a.type);
  std::vector<float> out(a.count * n, 0.f);
  if (a.bufferView >= 0)
    std::memcpy(out.data(), ViewBytes(m, a.bufferView, a.byteOffset), out.size() * 4);
  if (a.sparse.isSparse) {
    const unsigned char* idx =
        ViewBytes(m, a.sparse.indices.bufferView, size_t(a.sparse.indices.byteOffset));
    const unsigned char* val =
        ViewBytes(m, a.sparse.values.bufferView, size_t(a.sparse.values.byteOffset));
    for (int i = 0; i < a.sparse.count; ++i) {
      uint32_t v = 0;
      if (a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        uint16_t s;
        std::memcpy(&s, idx + 2 * size_t(i), 2);
        v = s;
      } else if (a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        v = idx[i];
      } else {
        std::memcpy(&v, idx + 4 * size_t(i), 4);
      }
      std::memcpy(&out.at(size_t(v) * n), val + 4 * n * size_t(i), 4 * n);
    }
  }
  return out;
}

}  // namespace mimetic::test
