// tools/cmd_fit.cpp: `mimetic fit`, a muscle template placed on a head from its landmarks
// (fitting/fit.h, docs/fitting.md).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/file_util.h"
#include "fitting/eyes.h"
#include "fitting/fit.h"
#include "fitting/landmarks.h"
#include "fitting/muscle_template.h"
#include "geometry/mesh.h"
#include "io/image.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/rig_file.h"
#include "io/template_file.h"
#include "rig/offline/rig_spec.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/render/render.h"

namespace mimetic::tools {
namespace {

const char* kFitUsage =
    "usage: mimetic fit TEMPLATE --mesh HEAD --landmarks FILE --out RIG\n"
    "                   [--units mm|cm|dm|m|in] [--thickness-map PNG]\n\n"
    "Places the muscles of TEMPLATE (a muscle template, docs/template-format.md, e.g.\n"
    "assets/head/default.template.json) on HEAD from its 68 facial landmarks and writes a rig\n"
    "file (docs/rig-format.md) whose mesh path is relative to the rig. The template is in\n"
    "units of the outer eye-corner distance, so heads of any size, unit and topology fit.\n"
    "When HEAD's file also holds a mesh named \"eyes\" (the eyeballs, as the sample head's\n"
    "does), the rig gets an `eyes` block: one sphere fitted to each of its connected parts,\n"
    "and the band of skin that slides on them (within 1/6 of their radius of their surface,\n"
    "fading out by 2/3; docs/model.md §24), so the lids slide over the eyeballs.\n\n"
    "options:\n"
    "  --mesh HEAD           the head mesh: .obj, .gltf or .glb\n"
    "  --landmarks FILE      landmark JSON (docs/landmarks-format.md): 68 points, or 68 vertex\n"
    "                        indices into HEAD\n"
    "  --units U             mesh units written into the rig; default: guessed from the\n"
    "                        eye-corner distance (about 9 cm on adults), and said so\n"
    "  --thickness-map PNG   also write the skin thickness as a grayscale texture-space map\n"
    "                        (needs UVs) and reference it from the rig instead of per-vertex\n"
    "                        values\n"
    "  --out RIG             the rig file to write (.rig.json)\n";

void PrintDiagnostics(const Diagnostics& diag) {
  if (!diag.empty()) std::fputs(diag.Format().c_str(), stderr);
}

std::string Absolute(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::absolute(path, ec);
  return ec ? path : p.lexically_normal().string();
}

int Fail(const Diagnostics& diag, const char* what) {
  PrintDiagnostics(diag);
  std::fprintf(stderr, "mimetic fit: %s: %zu error(s); nothing was written\n", what,
               diag.ErrorCount());
  return 1;
}

}  // namespace

int CmdFit(const Args& args) {
  const ParsedArgs parsed =
      ParseArgs(args, {"mesh", "landmarks", "units", "thickness-map", "out"}, {});
  if (parsed.help) return std::fputs(kFitUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("fit", parsed.error, kFitUsage);
  if (parsed.positional.size() != 1)
    return UsageError("fit", parsed.positional.empty() ? "missing TEMPLATE" : "expected one TEMPLATE",
                      kFitUsage);
  const std::string mesh_path = parsed.Get("mesh"), lm_path = parsed.Get("landmarks");
  const std::string out_path = parsed.Get("out"), map_path = parsed.Get("thickness-map");
  if (mesh_path.empty()) return UsageError("fit", "missing --mesh HEAD", kFitUsage);
  if (lm_path.empty()) return UsageError("fit", "missing --landmarks FILE", kFitUsage);
  if (out_path.empty()) return UsageError("fit", "missing --out RIG", kFitUsage);
  std::string units = parsed.Get("units");
  if (parsed.Has("units") && units != "mm" && units != "cm" && units != "dm" && units != "m" &&
      units != "in")
    return UsageError("fit", "--units " + units + ": expected mm, cm, dm, m or in", kFitUsage);
  if (parsed.Has("thickness-map") &&
      (map_path.size() < 5 || map_path.compare(map_path.size() - 4, 4, ".png") != 0))
    return UsageError("fit", "--thickness-map " + map_path + ": expected a .png file name",
                      kFitUsage);

  // Load everything first and report every problem of every input together.
  Diagnostics diag;
  MuscleTemplate tmpl;
  const bool tmpl_ok = LoadMuscleTemplate(parsed.positional[0], &tmpl, &diag);
  MeshData head;
  Diagnostics mesh_diag;
  const bool mesh_ok = ImportMesh(mesh_path, "", &head, &mesh_diag);
  diag.Append(mesh_diag, mesh_path);
  Landmarks landmarks;
  const bool lm_ok = LoadLandmarks(lm_path, &landmarks, &diag);
  if (!tmpl_ok || !mesh_ok || !lm_ok) return Fail(diag, "cannot read the inputs");

  // Units: given, or guessed from the eye-corner distance.
  std::vector<float3> points;
  Diagnostics lm_diag;
  if (!ResolveLandmarks(landmarks, head, &points, &lm_diag)) {
    diag.Append(lm_diag, lm_path);
    return Fail(diag, "landmarks do not fit the mesh");
  }
  FaceFrame frame;
  if (!ComputeFaceFrame(points, &frame, &lm_diag)) {
    diag.Append(lm_diag, lm_path);
    return Fail(diag, "landmarks do not define a face frame");
  }
  // Before guessing units from them: are they this mesh's, as it lies (mirrored, upside down,
  // another unit)? FitTemplate checks again (and reports warnings); an error stops here.
  if (Diagnostics check; !CheckLandmarksOnHead(points, head, SurfaceQuery(head), &check)) {
    diag.Append(check, lm_path);
    return Fail(diag, "the landmarks do not match the mesh");
  }
  if (units.empty()) {
    units = GuessUnits(frame.scale);
    std::printf("units:      %s (guessed: the outer eye corners are %.4g apart; pass --units to "
                "override)\n", units.c_str(), double(frame.scale));
  } else {
    std::printf("units:      %s\n", units.c_str());
  }

  RigSpec spec;
  FitReport report;
  Diagnostics fit_diag;
  const bool fit_ok = FitTemplate(tmpl, head, landmarks, units, &spec, &fit_diag, &report);
  diag.Append(fit_diag, parsed.positional[0]);
  if (!fit_ok) return Fail(diag, "the template does not fit this head");
  {  // the eyeballs the lids slide on, when the head's file carries them
    std::vector<NamedMeshData> others;
    Diagnostics others_diag;
    if (!ImportOtherMeshes(mesh_path, "", &others, &others_diag)) {
      diag.Append(others_diag, mesh_path);
      return Fail(diag, "cannot read the head file's other meshes");
    }
    for (const NamedMeshData& m : others) {
      if (m.name != "eyes") continue;
      std::vector<EyeSphere> spheres;
      std::string why;
      if (!FitEyeballs(m.mesh, &spheres, &why)) {
        diag.Error(mesh_path + ": mesh 'eyes'", why);
        return Fail(diag, "the eyeballs are not spheres");
      }
      spec.eyes = MakeEyesSpec(spheres);
    }
  }
  PrintDiagnostics(diag);  // warnings

  const std::string out_dir = DirectoryOf(out_path);
  std::error_code ec;
  if (!out_dir.empty()) std::filesystem::create_directories(out_dir, ec);
  spec.mesh_path = Absolute(mesh_path);
  if (!map_path.empty()) {
    std::vector<uint8_t> gray;
    float vmax = 0.f;
    Diagnostics map_diag;
    if (!RasterizeThicknessMap(head, spec.thickness.per_vertex, 512, 2.f, &gray, &vmax, &map_diag)) {
      diag.Append(map_diag, mesh_path);
      return Fail(diag, "cannot make the thickness map");
    }
    Image image;
    image.width = image.height = 512;
    image.rgb.resize(gray.size() * 3);
    for (size_t i = 0; i < gray.size(); ++i)
      image.rgb[3 * i] = image.rgb[3 * i + 1] = image.rgb[3 * i + 2] = gray[i];
    const std::string map_dir = DirectoryOf(map_path);
    if (!map_dir.empty()) std::filesystem::create_directories(map_dir, ec);
    if (!SavePng(map_path, image, &map_diag)) {
      diag.Append(map_diag);
      return Fail(diag, "cannot write the thickness map");
    }
    spec.thickness = ThicknessSpec{};
    spec.thickness.kind = ThicknessSpec::Kind::kImage;
    spec.thickness.image_path = Absolute(map_path);
    spec.thickness.min = 0.f;
    spec.thickness.max = vmax;
    std::printf("thickness:  map %s (512 x 512, black 0, white %.4g %s)\n", map_path.c_str(),
                double(vmax), units.c_str());
  } else {
    float lo = 1e30f, hi = 0.f;
    for (float h : spec.thickness.per_vertex) lo = std::fmin(lo, h), hi = std::fmax(hi, h);
    std::printf("thickness:  per vertex, %.4g .. %.4g %s\n", double(lo), double(hi), units.c_str());
  }

  const FaceFrame& f = report.frame;
  std::printf("face frame: origin (%.4g, %.4g, %.4g), x (%.3f, %.3f, %.3f), y (%.3f, %.3f, %.3f), "
              "z (%.3f, %.3f, %.3f), s = %.4g %s\n",
              f.origin.x, f.origin.y, f.origin.z, f.x.x, f.x.y, f.x.z, f.y.x, f.y.y, f.y.z, f.z.x,
              f.z.y, f.z.z, double(f.scale), units.c_str());
  if (spec.eyes) {
    std::printf("eyes:      ");
    for (const EyeSphere& e : spec.eyes->spheres)
      std::printf(" (%.4g, %.4g, %.4g) radius %.4g,", double(e.center.x), double(e.center.y),
                  double(e.center.z), double(e.radius));
    std::printf(" sliding band %.3g .. %.3g %s\n", double(spec.eyes->band[0]),
                double(spec.eyes->band[1]), units.c_str());
  }
  std::printf("placed %zu muscles (%zu points):\n", spec.muscles.size(), report.points.size());
  for (const PlacedPoint& p : report.points) {
    const float3 l = f.ToLocal(p.position);
    std::printf("  %-32s %-13s at (%8.4g, %8.4g, %8.4g) %s, face (%6.3f, %6.3f) s, depth %.3g %s%s\n",
                p.muscle.c_str(), p.role.c_str(), p.position.x, p.position.y, p.position.z,
                units.c_str(), l.x, l.y, double(p.depth), units.c_str(),
                p.ray_hit ? "" : " (ray missed: nearest surface point)");
  }
  size_t wrinkled = 0;
  for (size_t m = 0; m < spec.muscle_wrinkles.size(); ++m) {
    if (!spec.muscle_wrinkles[m]) continue;
    const MuscleWrinkleSpec& w = *spec.muscle_wrinkles[m];
    if (wrinkled++ == 0) std::printf("muscle wrinkles (docs/model.md §6):\n");
    std::printf("  %-32s lambda_w %.3g, %d wrinkles, depth %.3g %s", spec.muscles[m].name.c_str(),
                double(w.lambda_w), w.count, double(w.depth), units.c_str());
    if (w.gate > 0.f) std::printf(", full from activation %.3g", double(w.gate));
    std::printf("\n");
  }
  if (!spec.curve_wrinkles.empty())
    std::printf("curve wrinkles (docs/model.md §7-8), control points in texture space:\n");
  for (const NamedCurveWrinkle& c : spec.curve_wrinkles) {
    std::printf("  %-20s", c.name.c_str());
    for (const float2& uv : c.spec.control) std::printf(" (%.4f, %.4f)", double(uv.x), double(uv.y));
    std::printf(", depth %.3g, width %.3g %s\n", double(c.spec.depth), double(c.spec.width),
                units.c_str());
  }
  Diagnostics save_diag;
  if (!SaveRigSpec(out_path, spec, &save_diag)) {
    diag.Append(save_diag);
    return Fail(diag, "cannot write the rig");
  }
  std::printf("wrote %s (mesh %s, %zu muscles, %zu with wrinkles, %zu curve wrinkles)\n",
              out_path.c_str(), mesh_path.c_str(), spec.muscles.size(), wrinkled,
              spec.curve_wrinkles.size());
  return 0;
}

}  // namespace mimetic::tools
