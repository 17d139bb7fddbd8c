// fuzz/fuzz_mesh_obj.cpp: the OBJ readers on arbitrary bytes: ImportMeshBytes (the first object)
// and ImportOtherObjBytes (the objects after it, each with its face numbers made its own).
// Buffer URIs resolve in a directory that does not exist.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  mimetic::MeshData mesh;
  mimetic::Diagnostics diag;
  mimetic::ImportMeshBytes(bytes, ".obj", "/nonexistent-fuzz-dir", "", &mesh, &diag);
  (void)diag.Format();
  std::vector<mimetic::NamedMeshData> others;
  mimetic::Diagnostics other_diag;
  std::string first_name;
  mimetic::ImportOtherObjBytes(bytes, "/nonexistent-fuzz-dir", &others, &other_diag, &first_name);
  (void)other_diag.Format();
  return 0;
}
