// fuzz/fuzz_golden.cpp: the golden reader (io/golden_file.h) on arbitrary bytes; a golden that
// parses writes back to the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/golden_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  mimetic::Golden golden;
  mimetic::Diagnostics diag;
  if (!mimetic::ParseGolden(bytes, "fuzz", &golden, &diag)) return (void)diag.Format(), 0;
  if (mimetic::GoldenToBytes(golden) != bytes) std::abort();
  return 0;
}
