// fuzz/fuzz_mesh_gltf.cpp: the mesh reader (ImportMeshBytes, .gltf) on arbitrary bytes. Buffer URIs
// resolve in a directory that does not exist.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mimetic::MeshData mesh;
  mimetic::Diagnostics diag;
  mimetic::ImportMeshBytes(std::string(reinterpret_cast<const char*>(data), size), ".gltf",
                           "/nonexistent-fuzz-dir", "", &mesh, &diag);
  (void)diag.Format();
  return 0;
}
