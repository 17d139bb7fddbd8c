// io/jaw_fields.h: the fields that shape the jaw's weights, which the rig file's jaw block and
// the template's jaw block share (docs/rig-format.md and docs/template-format.md, "jaw"): the
// range, the glide, the blends about the lip line, the corner and thickness fades, and the two
// ordered pairs `back` and `neck_deg`. One reader for both, so the two files cannot drift.
#pragma once

#include <string>

#include "io/json_reader.h"

namespace mimetic::json_reader {

// Reads those fields of `j` into `jaw` (a JawSpec or a TemplateJaw, which name and type them
// alike); a missing key keeps its default. The scalars' ranges are the schema's; an ordered
// pair out of its range or out of order is reported through `r` (at the pair's path), and the
// result is then false.
template <class Jaw>
bool ReadJawShape(const View& j, const Reader& r, Jaw* jaw) {
  bool ok = true;
  j.Read("range_deg", &jaw->range_deg);
  j.Read("translation", &jaw->translation);
  j.Read("lip_blend_deg", &jaw->lip_blend_deg);
  j.Read("cheek_blend_deg", &jaw->cheek_blend_deg);
  j.Read("cheek_drop_deg", &jaw->cheek_drop_deg);
  j.Read("corner_fade", &jaw->corner_fade);
  j.Read("thickness_fade", &jaw->thickness_fade);
  // An ordered pair [a, b] in [lo, hi] with a < b; `what` says what the numbers are.
  auto pair = [&](const char* key, float lo, float hi, const char* what, float* dst) {
    float2 v{dst[0], dst[1]};
    if (!j.Read(key, &v)) return;
    if (!(v.x >= lo && v.y <= hi && v.x < v.y)) {
      r.Error(j.Path(key), "is [" + FormatFloat(v.x) + ", " + FormatFloat(v.y) + "]; expected " +
                               what);
      ok = false;
    }
    dst[0] = v.x;
    dst[1] = v.y;
  };
  pair("back", -1.f, 1.f,
       "[b0, b1] in [-1, 1] with b0 < b1 (fractions of the hinge-to-mouth distance)", jaw->back);
  pair("neck_deg", 0.f, 180.f,
       "[n0, n1] in [0, 180] with n0 < n1 (degrees below the lip line about the hinge)",
       jaw->neck_deg);
  return ok;
}

}  // namespace mimetic::json_reader
