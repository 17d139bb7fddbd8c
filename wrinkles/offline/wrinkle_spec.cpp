// wrinkles/offline/wrinkle_spec.cpp: checks of authored wrinkle specs (see wrinkle_spec.h).
#include "wrinkles/offline/wrinkle_spec.h"

#include <cmath>
#include <sstream>

namespace mimetic {
namespace {

std::string Num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

bool Finite3(float3 v) { return IsFinite(v); }

}  // namespace

bool ValidateMuscleWrinkleSpec(const MuscleWrinkleSpec& spec, const WrinkleMuscleGeometry& muscle,
                               const std::string& where, Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  if (!(spec.lambda_w >= 0.f && spec.lambda_w < 1.f)) {
    diag->Error(where + ".lambda_w", "got " + Num(spec.lambda_w) + ", expected a number in [0, 1)");
  }
  if (spec.count < 1) {
    diag->Error(where + ".count", "got " + Num(spec.count) + ", expected an integer >= 1");
  }
  if (!(spec.depth >= 0.f) || !std::isfinite(spec.depth)) {
    diag->Error(where + ".depth", "got " + Num(spec.depth) + ", expected a finite number >= 0");
  }
  if (!std::isfinite(spec.shape)) {
    diag->Error(where + ".alpha", "got " + Num(spec.shape) + ", expected a finite number");
  }
  if (!(spec.gate >= 0.f && spec.gate <= 1.f)) {
    diag->Error(where + ".gate", "got " + Num(spec.gate) +
                                     ", expected an activation in [0, 1] (0: no gate)");
  }
  if (muscle.kind == WrinkleMuscleKind::kLinear) {
    if (!Finite3(muscle.attachment) || !Finite3(muscle.insertion) ||
        !(Length(muscle.insertion - muscle.attachment) > 0.f)) {
      diag->Error(where, "linear muscle axis: expected distinct finite attachment and insertion");
    }
    if (!(muscle.zone_angle > 0.f && muscle.zone_angle < kPi)) {
      diag->Error(where, "linear muscle zone angle " + Num(muscle.zone_angle) +
                             ": expected radians in (0, pi)");
    }
    if (!(muscle.radius > 0.f) || !std::isfinite(muscle.radius)) {
      diag->Error(where, "linear muscle radius " + Num(muscle.radius) + ": expected > 0");
    }
    if (!(spec.phi_c >= 0.f && spec.phi_c < muscle.zone_angle)) {
      diag->Error(where + ".phi_c", "got " + Num(spec.phi_c) +
                                        " radians, expected [0, zone angle " +
                                        Num(muscle.zone_angle) + ")");
    }
  } else {
    const float3 a = (muscle.attachment_line[0] + muscle.attachment_line[1]) * 0.5f;
    const float3 i = (muscle.insertion_line[0] + muscle.insertion_line[1]) * 0.5f;
    if (!Finite3(a) || !Finite3(i) || !(Length(i - a) > 0.f)) {
      diag->Error(where, "sheet muscle fiber: expected distinct finite attachment and insertion "
                         "line midpoints");
    }
    if (!(muscle.length > 0.f) || !std::isfinite(muscle.length)) {
      diag->Error(where, "sheet muscle length " + Num(muscle.length) + ": expected > 0");
    }
    if (!(muscle.width > 0.f) || !std::isfinite(muscle.width)) {
      diag->Error(where, "sheet muscle width " + Num(muscle.width) + ": expected > 0");
    }
    if (!(spec.h_c >= 0.f && spec.h_c < 0.5f * muscle.width)) {
      diag->Error(where + ".h_c", "got " + Num(spec.h_c) + ", expected [0, width/2 = " +
                                      Num(0.5 * muscle.width) + ")");
    }
  }
  return diag->ErrorCount() == before;
}

bool ValidateCurveWrinkleSpec(const CurveWrinkleSpec& spec, const std::string& where,
                              Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  for (int k = 0; k < 4; ++k) {
    if (!std::isfinite(spec.control[k].x) || !std::isfinite(spec.control[k].y)) {
      diag->Error(where + ".curve[" + std::to_string(k) + "]",
                  "expected 2 finite texture coordinates");
    }
  }
  if (!(spec.depth > 0.f) || !std::isfinite(spec.depth)) {
    diag->Error(where + ".depth", "got " + Num(spec.depth) + ", expected a finite number > 0");
  }
  if (!(spec.width > 0.f) || !std::isfinite(spec.width)) {
    diag->Error(where + ".width", "got " + Num(spec.width) + ", expected a finite number > 0");
  }
  if (!(spec.rest_amplitude >= 0.f && spec.rest_amplitude <= 1.f)) {
    diag->Error(where + (spec.modulation == CurveWrinkleModulation::kArea ? ".k_r" : ".r"),
                "got " + Num(spec.rest_amplitude) + ", expected a number in [0, 1]");
  }
  if (spec.modulation != CurveWrinkleModulation::kDirectional &&
      spec.modulation != CurveWrinkleModulation::kArea) {
    diag->Error(where + ".modulation", "expected \"directional\" or \"area\"");
  }
  if (spec.profile != CurveWrinkleProfile::kBando && spec.profile != CurveWrinkleProfile::kYangZhang &&
      spec.profile != CurveWrinkleProfile::kYangZhangExact) {
    diag->Error(where + ".profile", "expected \"bando\", \"yang_zhang\" or \"yang_zhang_exact\"");
  }
  return diag->ErrorCount() == before;
}

const char* CurveWrinkleProfileName(CurveWrinkleProfile profile) {
  switch (profile) {
    case CurveWrinkleProfile::kBando: return "bando";
    case CurveWrinkleProfile::kYangZhang: return "yang_zhang";
    case CurveWrinkleProfile::kYangZhangExact: return "yang_zhang_exact";
  }
  return "unknown";
}

const char* CurveWrinkleModulationName(CurveWrinkleModulation mod) {
  switch (mod) {
    case CurveWrinkleModulation::kDirectional: return "directional";
    case CurveWrinkleModulation::kArea: return "area";
  }
  return "unknown";
}

}  // namespace mimetic
