// fuzz/fuzz_landmarks.cpp: the landmark file reader (ParseLandmarks) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/landmarks_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mimetic::Landmarks lm;
  mimetic::Diagnostics diag;
  mimetic::ParseLandmarks(std::string(reinterpret_cast<const char*>(data), size), "fuzz", &lm,
                          &diag);
  (void)diag.Format();
  return 0;
}
