// fuzz/fuzz_expression.cpp: the expression file reader (ParseExpression) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/expression_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mimetic::Expression e;
  mimetic::Diagnostics diag;
  mimetic::ParseExpression(std::string(reinterpret_cast<const char*>(data), size), "fuzz", &e,
                           &diag);
  (void)diag.Format();
  return 0;
}
