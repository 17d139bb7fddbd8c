// wrinkles/offline/wrinkle_spec.h: authored wrinkle descriptions (docs/model.md §6-8), independent of
// any file format: the rig loader fills them from JSON, the builder turns them into run-time
// tables (wrinkle_builder.h). Lengths in mesh units, angles in radians, curve control points in
// texture space.
#pragma once

#include <string>

#include "core/diagnostics.h"
#include "core/math.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {

// The optional wrinkle block of a muscle (001 §2.2-2.3, docs/model.md §6).
struct MuscleWrinkleSpec {
  float lambda_w = 0.5f;  // lambda_w in [0, 1): the region starts at lambda_w R (or Ls)
  int count = 3;          // n_w >= 1: wrinkles across the region (001 eq. 6)
  float depth = 0.f;      // k0 >= 0, furrow depth factor (001 eq. 5), mesh units
  float shape = 0.f;      // alpha, shape modulation (001 eq. 5), finite (0: saw-tooth)
  float phi_c = 0.f;      // linear muscles: angle where attenuation starts, radians,
                          // [0, zone angle) (001 eq. 12)
  float h_c = 0.f;        // sheet muscles: distance from the central fiber where attenuation
                          // starts, mesh units, [0, Ws/2) (001 eq. 15)
  float gate = 0.f;       // the muscle's activation at which its wrinkles reach full amplitude,
                          // [0, 1]: W times WrinkleGate(a, gate); 0 = no gate (001: by
                          // compression alone) (docs/model.md §6)
};

enum class WrinkleMuscleKind { kLinear, kSheet };

// The muscle geometry the wrinkle region needs (kept here so that wrinkles/ does not depend on
// muscles/; the rig builder copies it from MuscleSpec).
struct WrinkleMuscleGeometry {
  WrinkleMuscleKind kind = WrinkleMuscleKind::kLinear;
  // Linear (001 §2.2): mA, mI, maximal angle phi (Waters' zone angle), radius R (Waters' Rf).
  float3 attachment;            // mA, mesh units
  float3 insertion;             // mI
  float zone_angle = 0.f;       // phi, radians, (0, pi)
  float radius = 0.f;           // R, mesh units, > 0
  // Sheet (001 §2.3): attachment line mA1 mA2, insertion line mI1 mI2, AOI length and width.
  float3 attachment_line[2];    // mA1, mA2
  float3 insertion_line[2];     // mI1, mI2
  float length = 0.f;           // Ls, mesh units, > 0
  float width = 0.f;            // Ws, mesh units, > 0
};

// A curve wrinkle (000 §6-7, 002 §5, 004; docs/model.md §7-8).
struct CurveWrinkleSpec {
  float2 control[4];            // cubic Bezier control points of the furrow, texture space
  float depth = 0.f;            // d (Bando) or rest depth h0 (Yang-Zhang), mesh units, > 0
  float width = 0.f;            // w (Bando) or rest half width a0 (Yang-Zhang), mesh units, > 0
  CurveWrinkleModulation modulation = CurveWrinkleModulation::kDirectional;
  float rest_amplitude = 0.f;   // r (000 eq. 5, directional) or k_r (002 eq. 6, area), [0, 1]
  CurveWrinkleProfile profile = CurveWrinkleProfile::kBando;
};

// Record every problem of a spec under `where` (a JSON path such as `muscles[2].wrinkles`);
// return false when any error was recorded.
bool ValidateMuscleWrinkleSpec(const MuscleWrinkleSpec& spec, const WrinkleMuscleGeometry& muscle,
                               const std::string& where, Diagnostics* diag);
bool ValidateCurveWrinkleSpec(const CurveWrinkleSpec& spec, const std::string& where,
                              Diagnostics* diag);

const char* CurveWrinkleProfileName(CurveWrinkleProfile profile);      // "bando", ...
const char* CurveWrinkleModulationName(CurveWrinkleModulation mod);    // "directional", "area"

}  // namespace mimetic
