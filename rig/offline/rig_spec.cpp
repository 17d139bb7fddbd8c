#include "rig/offline/rig_spec.h"

namespace mimetic {

WrinkleMuscleGeometry WrinkleGeometryOf(const MuscleSpec& m) {
  WrinkleMuscleGeometry g;
  if (m.type == MuscleType::kLinear) {
    g.kind = WrinkleMuscleKind::kLinear;
    g.attachment = m.linear.attachment;
    g.insertion = m.linear.insertion;
    g.zone_angle = m.linear.zone_angle;
    g.radius = m.linear.falloff_end;  // 001's R is Waters' Rf
  } else {
    g.kind = WrinkleMuscleKind::kSheet;
    for (int k = 0; k < 2; ++k) {
      g.attachment_line[k] = m.sheet.attachment[k];
      g.insertion_line[k] = m.sheet.insertion[k];
    }
    g.length = m.sheet.length;
    g.width = m.sheet.width;
  }
  return g;
}

}  // namespace mimetic
