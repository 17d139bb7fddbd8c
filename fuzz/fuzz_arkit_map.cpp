// fuzz/fuzz_arkit_map.cpp: the ARKit map reader (ParseArkitMap) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/arkit_map.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<mimetic::ArkitShape> shapes;
  mimetic::Diagnostics diag;
  mimetic::ParseArkitMap(std::string(reinterpret_cast<const char*>(data), size), "fuzz", &shapes,
                         &diag);
  (void)diag.Format();
  return 0;
}
