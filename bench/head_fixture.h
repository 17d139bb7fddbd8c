// bench/head_fixture.h: the procedural sample head at ~`vertices` vertices with the default
// template fitted to it (refinement off), the fixture of bench_evaluate and bench_fine_scale.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "content/sample_head.h"
#include "fitting/fit.h"
#include "fitting/landmarks.h"
#include "fitting/muscle_template.h"
#include "io/template_file.h"
#include "rig/offline/rig_builder.h"

namespace mimetic::bench {

struct FittedHead {
  SampleHead head;
  RigSpec spec;
};

// Exits with the diagnostics when a step fails (a benchmark cannot run without it).
inline FittedHead FitSampleHead(int vertices) {
  auto die = [](const Diagnostics& diag, const char* what) {
    std::fprintf(stderr, "bench: %s\n%s", what, diag.Format().c_str());
    std::exit(1);
  };
  FittedHead f;
  SampleHeadOptions options;
  const double k = std::sqrt(double(vertices) / 33741.0);  // defaults: 240 x 140 -> 33,741
  options.columns = 2 * int(std::lround(120.0 * k));
  options.rows = int(std::lround(140.0 * k));
  f.head = MakeSampleHead(options);
  MuscleTemplate tmpl;
  Diagnostics diag;
  if (!LoadMuscleTemplate(std::string(MIMETIC_SOURCE_DIR) + "/assets/head/default.template.json",
                          &tmpl, &diag))
    die(diag, "cannot load the default template");
  Landmarks landmarks;
  landmarks.points = f.head.landmarks;
  if (!FitTemplate(tmpl, f.head.mesh, landmarks, "mm", &f.spec, &diag)) die(diag, "cannot fit");
  f.spec.refinement.enabled = false;
  return f;
}

}  // namespace mimetic::bench
