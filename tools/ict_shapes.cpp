// tools/ict_shapes.cpp: the table of tools/ict_shapes.h.
#include "tools/ict_shapes.h"

#include <chrono>
#include <cstring>
#include <vector>

#include "fitting/fit.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/template_file.h"

namespace mimetic::tools {
namespace {
// ICT-FaceKit's shapes (ARKit names, ict-facekit/arkit/README.md) and the brow raise.
constexpr const char* kSphincterOris =
    "orbicularis oris, a sphincter (the rig has linear and sheet muscles only)";
constexpr const char* kSphincterOculi =
    "orbicularis oculi, a sphincter, and the eyelids (the rig has neither)";
constexpr const char* kJawOpen =
    "the jaw, not a muscle: the jaw stage makes it, measured in docs/jaw.md (ratio 0.38)";
constexpr const char* kJawOther =
    "the jaw's protrusion or lateral turn: not modelled (its glide is tied to the opening, docs/jaw.md)";
constexpr const char* kMouthClose =
    "the jaw opens with the lips kept shut: orbicularis oris, a sphincter";
constexpr const char* kEyes = "the eyeballs turn; the lids follow (no eyes or lids in the rig)";
const IctShape kShapes[] = {
    {"browRaise (AU1+2)", "ict-facekit/ict_skin_browRaise_AU1+AU2.obj", nullptr, true},
    {"browInnerUp_L", "ict-facekit/arkit/browInnerUp_L.obj", nullptr},
    {"browInnerUp_R", "ict-facekit/arkit/browInnerUp_R.obj", nullptr},
    {"browOuterUp_L", "ict-facekit/arkit/browOuterUp_L.obj", nullptr},
    {"browOuterUp_R", "ict-facekit/arkit/browOuterUp_R.obj", nullptr},
    {"browDown_L", "ict-facekit/arkit/browDown_L.obj", nullptr, true},
    {"browDown_R", "ict-facekit/arkit/browDown_R.obj", nullptr},
    {"mouthSmile_L", "ict-facekit/arkit/mouthSmile_L.obj", nullptr, true},
    {"mouthSmile_R", "ict-facekit/arkit/mouthSmile_R.obj", nullptr},
    {"mouthDimple_L", "ict-facekit/arkit/mouthDimple_L.obj", nullptr, true},
    {"mouthDimple_R", "ict-facekit/arkit/mouthDimple_R.obj", nullptr},
    {"mouthStretch_L", "ict-facekit/arkit/mouthStretch_L.obj", nullptr, true},
    {"mouthStretch_R", "ict-facekit/arkit/mouthStretch_R.obj", nullptr},
    {"mouthUpperUp_L", "ict-facekit/arkit/mouthUpperUp_L.obj", nullptr, true},
    {"mouthUpperUp_R", "ict-facekit/arkit/mouthUpperUp_R.obj", nullptr},
    {"mouthLowerDown_L", "ict-facekit/arkit/mouthLowerDown_L.obj", nullptr, true},
    {"mouthLowerDown_R", "ict-facekit/arkit/mouthLowerDown_R.obj", nullptr},
    {"mouthShrugUpper", "ict-facekit/arkit/mouthShrugUpper.obj", nullptr},
    {"mouthLeft", "ict-facekit/arkit/mouthLeft.obj", nullptr},
    {"mouthRight", "ict-facekit/arkit/mouthRight.obj", nullptr},
    {"cheekPuff_L", "ict-facekit/arkit/cheekPuff_L.obj",
     "air pressure pushes the cheek out; no muscle pulls it there"},
    {"cheekPuff_R", "ict-facekit/arkit/cheekPuff_R.obj",
     "air pressure pushes the cheek out; no muscle pulls it there"},
    {"cheekRaiser_L", "ict-facekit/arkit/cheekRaiser_L.obj", kSphincterOculi},
    {"cheekRaiser_R", "ict-facekit/arkit/cheekRaiser_R.obj", kSphincterOculi},
    {"cheekSquint_L", "ict-facekit/arkit/cheekSquint_L.obj", kSphincterOculi},
    {"cheekSquint_R", "ict-facekit/arkit/cheekSquint_R.obj", kSphincterOculi},
    {"eyeSquint_L", "ict-facekit/arkit/eyeSquint_L.obj", kSphincterOculi},
    {"eyeSquint_R", "ict-facekit/arkit/eyeSquint_R.obj", kSphincterOculi},
    {"eyeBlink_L", "ict-facekit/arkit/eyeBlink_L.obj", kSphincterOculi},
    {"eyeBlink_R", "ict-facekit/arkit/eyeBlink_R.obj", kSphincterOculi},
    {"eyeWide_L", "ict-facekit/arkit/eyeWide_L.obj",
     "levator palpebrae lifts the upper lid (no lids in the rig)"},
    {"eyeWide_R", "ict-facekit/arkit/eyeWide_R.obj",
     "levator palpebrae lifts the upper lid (no lids in the rig)"},
    {"eyeLookDown_L", "ict-facekit/arkit/eyeLookDown_L.obj", kEyes},
    {"eyeLookDown_R", "ict-facekit/arkit/eyeLookDown_R.obj", kEyes},
    {"eyeLookIn_L", "ict-facekit/arkit/eyeLookIn_L.obj", kEyes},
    {"eyeLookIn_R", "ict-facekit/arkit/eyeLookIn_R.obj", kEyes},
    {"eyeLookOut_L", "ict-facekit/arkit/eyeLookOut_L.obj", kEyes},
    {"eyeLookOut_R", "ict-facekit/arkit/eyeLookOut_R.obj", kEyes},
    {"eyeLookUp_L", "ict-facekit/arkit/eyeLookUp_L.obj", kEyes},
    {"eyeLookUp_R", "ict-facekit/arkit/eyeLookUp_R.obj", kEyes},
    {"jawOpen", "ict-facekit/arkit/jawOpen.obj", kJawOpen},
    {"jawForward", "ict-facekit/arkit/jawForward.obj", kJawOther},
    {"jawLeft", "ict-facekit/arkit/jawLeft.obj", kJawOther},
    {"jawRight", "ict-facekit/arkit/jawRight.obj", kJawOther},
    {"mouthClose", "ict-facekit/arkit/mouthClose.obj", kMouthClose},
    {"mouthFunnel", "ict-facekit/arkit/mouthFunnel.obj", kSphincterOris},
    {"mouthPucker", "ict-facekit/arkit/mouthPucker.obj", kSphincterOris},
    {"mouthPress_L", "ict-facekit/arkit/mouthPress_L.obj", kSphincterOris},
    {"mouthPress_R", "ict-facekit/arkit/mouthPress_R.obj", kSphincterOris},
    {"mouthRollLower", "ict-facekit/arkit/mouthRollLower.obj", kSphincterOris},
    {"mouthRollUpper", "ict-facekit/arkit/mouthRollUpper.obj", kSphincterOris},
};

}  // namespace

span<const IctShape> IctShapes() {
  return span<const IctShape>(kShapes, sizeof(kShapes) / sizeof(kShapes[0]));
}

const IctShape* FindIctShape(const char* name) {
  for (const IctShape& s : kShapes)
    if (std::strcmp(s.name, name) == 0) return &s;
  return nullptr;
}

bool FitIctRig(const std::string& data, const std::string& template_path,
               const std::string& landmarks_path, IctRig* out, Diagnostics* diag,
               std::string* what) {
  const auto start = std::chrono::steady_clock::now();
  MuscleTemplate tmpl;
  Landmarks landmarks;
  Diagnostics local;
  out->neutral_path = data + "/ict-facekit/ict_skin_neutral.obj";
  const bool tmpl_ok = LoadMuscleTemplate(template_path, &tmpl, diag);
  const bool mesh_ok = ImportMesh(out->neutral_path, "", &out->neutral, &local);
  diag->Append(local, out->neutral_path);
  const bool lm_ok = LoadLandmarks(landmarks_path, &landmarks, diag);
  if (!tmpl_ok || !mesh_ok || !lm_ok) {
    *what = "cannot read the inputs (is --data the folder that holds ict-facekit/?)";
    return false;
  }
  std::vector<float3> points;
  FaceFrame frame;
  local.Clear();
  if (!ResolveLandmarks(landmarks, out->neutral, &points, &local) ||
      !ComputeFaceFrame(points, &frame, &local)) {
    diag->Append(local, landmarks_path);
    *what = "the landmarks do not fit the ICT neutral";
    return false;
  }
  out->units = GuessUnits(frame.scale);
  out->landmarks = points;
  local.Clear();
  if (!FitTemplate(tmpl, out->neutral, landmarks, out->units, &out->spec, &local)) {
    diag->Append(local, template_path);
    *what = "the template does not fit the ICT neutral";
    return false;
  }
  local.Clear();
  if (!BuildRig(out->spec, out->neutral, {}, &out->rig, &local)) {
    diag->Append(local, template_path);
    *what = "the fitted rig does not build";
    return false;
  }
  out->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}

}  // namespace mimetic::tools
