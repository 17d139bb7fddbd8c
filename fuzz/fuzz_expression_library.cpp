// fuzz/fuzz_expression_library.cpp: the expression library reader (ParseExpressionLibrary) on
// arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/expression_library.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<mimetic::Expression> lib;
  mimetic::Diagnostics diag;
  mimetic::ParseExpressionLibrary(std::string(reinterpret_cast<const char*>(data), size), "fuzz",
                                  &lib, &diag);
  (void)diag.Format();
  return 0;
}
