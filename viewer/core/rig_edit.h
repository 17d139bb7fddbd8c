// viewer/core/rig_edit.h: edits of the rig itself (docs/viewer.md "Editing the rig") as command
// objects on the rig's spec (the parsed rig file, rig/offline/rig_spec.h), without any GL.
//
// Each command replaces one part of the spec whole (one muscle with its wrinkle block, one
// curve wrinkle, one direction field of `fine_scale`) and keeps the part it replaced: Revert
// puts those bits back, so undo restores the spec bit for bit. The Make*Edit functions below
// turn one parameter change ("muscle zygomaticus_major_L strength 1.2") into such a command,
// checking the value first: a refused value changes nothing and the message names the field
// (`muscles[16] zygomaticus_major_L: strength: expected a finite number >= 0, got nan`). The
// rules between fields (falloff_end > falloff_start, ...) are the rig file's own: the Session
// checks the edited spec by reading its text back (ParseRigSpec) before keeping the command.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rig/offline/rig_spec.h"
#include "viewer/core/edit.h"

namespace mimetic::viewer {

// --- The whole-part commands. --------------------------------------------------------------
// Muscle `index` (rig order = the file's) becomes `muscle` with wrinkle block `wrinkles`.
// `what` is its Describe() ("muscle NAME strength 1.2").
CommandPtr MakeSetMuscleSpec(uint32_t index, MuscleSpec muscle,
                             std::optional<MuscleWrinkleSpec> wrinkles, std::string what);
CommandPtr MakeSetCurveWrinkleSpec(uint32_t index, CurveWrinkleSpec curve, std::string what);
// Direction field `field` (0 or 1) of fine_scale becomes `spec`.
CommandPtr MakeSetDirectionField(uint32_t field, DirectionFieldSpec spec, std::string what);

// --- One parameter (the panels and `--script` lines; docs/viewer.md "Scripts"). -----------
// Muscle NAME's parameter PARAM set to ARGS (words as a script gives them):
//   strength K | falloff waters|smooth | motion chord|tangent
//   linear: attachment X Y Z | insertion X Y Z | zone_angle DEG | falloff_start RS |
//           falloff_end RF
//   sheet:  attachment I X Y Z | insertion I X Y Z (I = 0 or 1) | length LS | width WS |
//           falloff_start RS
//   wrinkles none | wrinkles on (a default block) | wrinkles.lambda_w L | wrinkles.count N |
//   wrinkles.depth K0 | wrinkles.shape A | wrinkles.phi_c DEG (linear) | wrinkles.h_c H (sheet)
// nullptr with *error when the muscle, the parameter or a value is wrong.
CommandPtr MakeMuscleEdit(const RigSpec& spec, const std::string& muscle, const std::string& param,
                          const std::vector<std::string>& args, std::string* error);
// Curve wrinkle NAME: point I U V (I in 0..3, a control point in texture space) | depth D |
// width W | profile bando|yang_zhang|yang_zhang_exact | modulation directional|area |
// rest_amplitude R.
CommandPtr MakeCurveEdit(const RigSpec& spec, const std::string& curve, const std::string& param,
                         const std::vector<std::string>& args, std::string* error);
// Direction field FIELD (its name, or 0 / 1) at file vertex VERTEX: ARGS = DX DY DZ MAG (the
// direction, scaled to length MAG: the anchor is added, or the one at VERTEX replaced) or
// "delete" (the field keeps at least one anchor). `vertex_count`: the mesh's file vertices.
CommandPtr MakeDirectionEdit(const RigSpec& spec, size_t vertex_count, const std::string& field,
                             uint32_t vertex, const std::vector<std::string>& args,
                             std::string* error);

// Exact forms the panels use (the same commands, values already numbers).
CommandPtr MakeMuscleValueEdit(const RigSpec& spec, uint32_t muscle, const std::string& param,
                               const std::vector<float>& values, std::string* error);
CommandPtr MakeCurvePointEdit(const RigSpec& spec, uint32_t curve, int point, float2 uv,
                              std::string* error);

// Index of the muscle / curve wrinkle / direction field by name; -1 when none.
int FindSpecMuscle(const RigSpec& spec, const std::string& name);
int FindSpecCurve(const RigSpec& spec, const std::string& name);
int FindSpecField(const RigSpec& spec, const std::string& name);

// The profile and modulation names of the rig file ("bando", "yang_zhang", ...).
bool ParseCurveProfile(const std::string& text, CurveWrinkleProfile* out);
bool ParseCurveModulation(const std::string& text, CurveWrinkleModulation* out);

}  // namespace mimetic::viewer
