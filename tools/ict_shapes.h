// tools/ict_shapes.h: ICT-FaceKit's expression shapes (ARKit names, ict-facekit/arkit/README.md)
// and its brow raise, with what the rig claims about each: `mimetic fidelity` measures the
// claimed ones, `mimetic calibrate` trains on the ones marked `trained` (docs/fidelity.md).
#pragma once

#include "core/span.h"

namespace mimetic::tools {

struct IctShape {
  const char* name;
  const char* file;     // under the data directory (default ../shared/data)
  const char* why_not;  // nullptr: claimed; else why linear and sheet muscles cannot make it
  bool trained = false; // in the default calibration set (the rest is held out)
};

span<const IctShape> IctShapes();
const IctShape* FindIctShape(const char* name);

}  // namespace mimetic::tools
