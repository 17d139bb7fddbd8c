// fuzz/fuzz_arkit_take.cpp: the take readers (io/arkit_take.h) on arbitrary bytes, as CSV and as
// JSON; a take that parses is imported through a two-shape map (ImportArkitTake) and every key
// checked to lie in [0, 1] with increasing times.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/arkit_take.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::vector<mimetic::ArkitShapeActivations> map = {
      {"jawOpen", false, {{"m", 0.6f}}}, {"mouthClose", false, {{"m", 0.7f}, {"n", 1.f}}}};
  for (int json = 0; json < 2; ++json) {
    mimetic::ArkitTake take;
    mimetic::Diagnostics diag;
    const bool ok = json ? mimetic::ParseArkitTakeJson(text, "fuzz", &take, &diag)
                         : mimetic::ParseArkitCsv(text, "fuzz", 30.0, &take, &diag);
    (void)diag.Format();
    if (!ok) continue;
    mimetic::ArkitImport out;
    if (!mimetic::ImportArkitTake(take, map, {"m", "n"}, "fuzz", &out, &diag)) continue;
    for (const auto& c : out.clip.channels)
      for (size_t k = 0; k < c.keys.size(); ++k)
        if (!(c.keys[k].v >= 0.f && c.keys[k].v <= 1.f) ||
            (k > 0 && !(c.keys[k].t > c.keys[k - 1].t)))
          std::abort();
  }
  return 0;
}
