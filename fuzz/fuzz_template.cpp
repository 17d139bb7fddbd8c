// fuzz/fuzz_template.cpp: the muscle template reader (ParseMuscleTemplate) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/template_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mimetic::MuscleTemplate t;
  mimetic::Diagnostics diag;
  mimetic::ParseMuscleTemplate(std::string_view(reinterpret_cast<const char*>(data), size), &t,
                               &diag);
  (void)diag.Format();
  return 0;
}
