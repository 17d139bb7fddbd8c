// fuzz/fuzz_rig.cpp: the rig file reader (ParseRigSpec) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/rig_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mimetic::RigSpec spec;
  mimetic::Diagnostics diag;
  mimetic::ParseRigSpec(std::string_view(reinterpret_cast<const char*>(data), size),
                        "/nonexistent-fuzz-dir", &spec, &diag);
  (void)diag.Format();
  return 0;
}
