// fitting/muscle_template.h: a head-independent muscle layout, expressed relative to the
// 68 iBUG facial landmarks (docs/template-format.md, docs/fitting.md).
//
// A template says where each Waters muscle (docs/model.md §2 linear, §3 sheet) lies on a face in
// the face frame of fit.h: origin at the nose bridge top (landmark 27), x from the subject's
// right outer eye corner (36) to the left one (45), y up (chin 8 -> bridge 27, made
// orthogonal to x), z = x cross y toward the viewer, unit s = |45 - 36|. Every length in a
// template (offsets, depths, radii, strengths, thickness) is in units of s, so one template
// fits heads of any size, unit and proportion; FitTemplate (fit.h) turns it into a RigSpec.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "rig/runtime/rig.h"
#include "muscles/offline/muscle_spec.h"
#include "wrinkles/offline/wrinkle_spec.h"

namespace mimetic {

inline constexpr int kTemplateLandmarkCount = 68;  // iBUG / Multi-PIE 68-point order


// One point of a muscle: the weighted mean of some landmarks, moved by `offset` in the face
// plane, projected onto the surface along -z of the face frame, then `depth` under it along
// the inward surface normal.
struct TemplatePoint {
  std::vector<int> landmarks;  // iBUG indices in [0, 68), at least one, no repeats
  std::vector<float> weights;  // one per landmark, >= 0, normalised to sum 1 by the parser
  float2 offset;               // face-frame (dx, dy), units of s
  float depth = 0.f;           // under the surface along the inward normal, units of s, >= 0
};

struct TemplateMuscle {
  std::string name;  // unique; `_L` / `_R` = subject's left (+x) / right
  MuscleType type = MuscleType::kLinear;
  float strength = 0.f;  // contraction at activation 1, units of s, >= 0
  MuscleFalloff falloff = MuscleFalloff::kWaters;  // copied into the fitted rig
  MuscleMotion motion = MuscleMotion::kChord;      // copied into the fitted rig
  float tangent_radius = 0.f;  // units of s, >= 0; the fitted rig's is this times s
  // True when the file names `motion`: mimetic calibrate then keeps it (docs/model.md §17).
  bool motion_given = false;
  // True for the copy a `mirror` entry adds (it follows its source in `muscles`); the writer
  // writes the source with `"mirror": true` and not the copy.
  bool mirrored_copy = false;
  // Linear: attachment[0] = v1 (bone), insertion[0] = v2 (skin). Sheet: both ends of the
  // attachment line and of the insertion line.
  TemplatePoint attachment[2];
  TemplatePoint insertion[2];
  float zone_angle_deg = 0.f;  // linear: Omega, degrees, (0, 180)
  float falloff_start = 0.f;   // linear: Rs; sheet: Rs in (0, length); units of s
  float falloff_end = 0.f;     // linear: Rf > Rs, units of s
  float length = 0.f;          // sheet: Ls, units of s, > 0
  float width = 0.f;           // sheet: Ws, units of s, > 0
  // The optional wrinkle block (docs/model.md §6), as in the rig file but with `depth` (k0) and
  // `h_c` in units of s; `phi_c` in radians (the file says degrees). Mirrored copies share it.
  std::optional<MuscleWrinkleSpec> wrinkles;
};

// A curve wrinkle (docs/model.md §7-8) placed relative to the landmarks: its 4 Bezier control
// points are template points (depth 0) that the fit casts onto the head and turns into the
// texture coordinates of the surface hit; depth and width in units of s.
struct TemplateCurveWrinkle {
  std::string name;           // unique among curve wrinkles (after mirroring)
  TemplatePoint control[4];   // depth is always 0 (the curve lies in the skin)
  float depth = 0.f;          // d (Bando) or h0 (Yang-Zhang), units of s, > 0
  float width = 0.f;          // w (Bando) or a0 (Yang-Zhang), units of s, > 0
  CurveWrinkleProfile profile = CurveWrinkleProfile::kBando;
  CurveWrinkleModulation modulation = CurveWrinkleModulation::kDirectional;
  float rest_amplitude = 0.f;  // [0, 1]
  bool mirrored_copy = false;  // as for muscles
};

// A region of the skin-thickness map (Bando et al. 2003 §6: the face is divided into regions
// filled with their thickness, then blurred): a Gaussian weight around `center` with the
// given radii (standard deviations) in the face plane.
struct ThicknessRegion {
  std::string name;
  float2 center;  // face-frame (x, y), units of s
  float2 radius;  // (sx, sy) > 0, units of s
  float value = 0.f;  // thickness at the region's centre, units of s, >= 0
  bool mirrored_copy = false;  // as for muscles
};

// h(p) = (w0 * base + sum_i g_i(p) v_i) / (w0 + sum_i g_i(p)), a normalised Gaussian blend,
// g_i = exp(-((x - cx)^2 / sx^2 + (y - cy)^2 / sy^2) / 2) * F(z), w0 = exp(-2) (the base takes
// over two radii away from every region), F(z) = smoothstep(front[0], front[1], z): the
// regions hold on the face only, not on the back of the head that projects onto it.
struct TemplateThickness {
  float base = 0.f;  // units of s, >= 0
  float front[2] = {-1.f, -0.5f};  // face-frame z range of the fade, units of s
  std::vector<ThicknessRegion> regions;
};

// The jaw (docs/model.md §18) placed from the landmarks: the subject's right condyle is the
// weighted mean of `landmarks` moved by `offset` (face frame, units of s; no projection: the
// condyle lies inside the head); the left one mirrors it (landmarks mirrored, dx negated). The
// fit takes the mouth point from the inner lip midline (62, 66) and the mouth width from the
// outer corners (48, 54); the blend parameters are copied into the rig.
struct TemplateJaw {
  std::vector<int> landmarks;  // iBUG indices, at least one, no repeats
  std::vector<float> weights;  // one per landmark, normalised to sum 1
  float3 offset{};             // face-frame (dx, dy, dz), units of s
  float range_deg = 0.f;       // (0, 90]
  float3 translation{};        // the glide at jaw = 1: face-frame (dx, dy, dz), units of s
  float lip_blend_deg = 2.f, cheek_blend_deg = 12.f, cheek_drop_deg = 0.f;
  float corner_fade = 0.2f;  // fraction of the mouth width (JawSpec::corner_fade)
  float thickness_fade = 0.3f;  // fraction of the mouth width (JawSpec::thickness_fade)
  float back[2] = {0.2f, 0.6f};
  float neck_deg[2] = {90.f, 180.f};
};

// A tension region (docs/tension.md): a named mask the fit turns into per-vertex weights of the
// rig, g(p) = exp(-((x - cx)^2 / sx^2 + (y - cy)^2 / sy^2) / 2) F(z) in the face frame (F the
// thickness map's front fade), set to 0 below kTensionRegionCut so that the rig lists only the
// points inside it.
struct TemplateTensionRegion {
  std::string name;               // unique among the regions (after mirroring)
  float2 center;                  // face-frame (x, y), units of s
  float2 radius;                  // (sx, sy) > 0, units of s
  float reference = kDefaultTensionReference;  // c0 of the rig (docs/model.md §19), > 0
  bool mirrored_copy = false;     // as for muscles
};
inline constexpr float kTensionRegionCut = 0.01f;

// A default fine-scale direction vector (docs/model.md §20, docs/template-format.md): placed by
// the fit on the head vertex nearest to face-frame (x, y) = `at` among those facing forward
// (the thickness map's front fade above 1/2); its direction is a face-frame vector, its length
// `magnitude` (000 eq. 1's m).
struct TemplateDirectionAnchor {
  std::string name;       // unique within its field (after mirroring)
  float2 at;              // face-frame (x, y), units of s
  float3 direction;       // face frame, non-zero (normalised by the fit)
  float magnitude = 0.5f; // (0, 1]
  bool mirrored_copy = false;  // x of `at` and of `direction` negated
};
struct TemplateFineScale {
  std::string field_names[2];
  std::vector<TemplateDirectionAnchor> fields[2];  // `mirror` expanded, file order
  float rest_amplitude = 0.5f;
};

struct MuscleTemplate {
  std::string file;  // where it was loaded from ("" when parsed from text)
  std::string description;
  TemplateThickness thickness;
  std::vector<TemplateMuscle> muscles;  // `mirror` entries already expanded, file order
  std::vector<TemplateCurveWrinkle> curve_wrinkles;  // likewise
  std::optional<TemplateJaw> jaw;  // absent = the fitted rig has no jaw
  std::vector<TemplateTensionRegion> tension_regions;  // `mirror` expanded, file order
  std::optional<TemplateFineScale> fine_scale;  // absent = the fitted rig has none
  // The fitted rig's refinement.falloff_error (docs/model.md §11): refinement where each
  // muscle's fall-off bends; a fraction of a muscle's peak, so it has no units. 0 (absent) = off.
  float falloff_error = 0.f;
};

// The weight of tension region `r` at face-frame position `p` (units of s), in [0, 1]; `front`
// the thickness map's fade (TemplateThickness::front).
float EvaluateTensionRegion(const TemplateTensionRegion& r, const float front[2], float3 p);

// A number as a template file holds it: 4 significant digits, the shortest decimal that prints
// so ("0.1", not "0.10000000149"). io/template_file.cpp writes every number through it, and
// `mimetic calibrate` keeps its template at these digits, so what it measured is what it writes.
double TemplateDigits(double v);

// Thickness at face-frame position `p` (units of s, as FaceFrame::ToLocal gives), units of s.
float EvaluateTemplateThickness(const TemplateThickness& t, float3 p);

}  // namespace mimetic
