// tools/ict_shapes.h: ICT-FaceKit's expression shapes (ARKit names, ict-facekit/arkit/README.md)
// and its brow raise, with what the rig claims about each: `mimetic fidelity` measures the
// claimed ones, `mimetic calibrate` trains on the ones marked `trained` (docs/fidelity.md).
#pragma once

#include <string>
#include <vector>

#include "core/span.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_builder.h"
#include "rig/offline/rig_spec.h"

namespace mimetic::tools {

struct IctShape {
  const char* name;
  const char* file;     // under the data directory (default ../shared/data)
  const char* why_not;  // nullptr: claimed; else why linear and sheet muscles cannot make it
  bool trained = false; // in the default calibration set (the rest is held out)
};

span<const IctShape> IctShapes();
const IctShape* FindIctShape(const char* name);

// The default template fitted to the ICT neutral and built, as `mimetic fidelity`,
// `mimetic make-library` and docs/fitting.md do it.
struct IctRig {
  std::string neutral_path;  // data + /ict-facekit/ict_skin_neutral.obj
  MeshData neutral;
  std::string units;         // the fitted rig's units (GuessUnits of the landmark frame)
  std::vector<float3> landmarks;  // the 68 iBUG landmarks on the neutral
  RigSpec spec;
  Rig rig;
  double seconds = 0;        // reading, fitting and building
};
// Reads the template, the ICT neutral under `data` and its landmarks, fits and builds. On
// failure: false, every problem in `diag` (prefixed with its file) and what went wrong in
// `what` (one sentence for the command's closing line).
bool FitIctRig(const std::string& data, const std::string& template_path,
               const std::string& landmarks_path, IctRig* out, Diagnostics* diag,
               std::string* what);

}  // namespace mimetic::tools
