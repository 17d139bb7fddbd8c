// tools/cmd_compare.cpp: `mimetic compare`, how close a mesh is to another (fitting/compare.h).
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/file_util.h"
#include "fitting/compare.h"
#include "geometry/mesh.h"
#include "io/image.h"
#include "io/mesh_io.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/render/heat_map.h"
#include "tools/render/render.h"

namespace mimetic::tools {

static const char* kCompareUsage =
    "usage: mimetic compare A B [--neutral N] [--region all|moved:T|FILE]\n"
    "                       [--heatmap IMAGE.png [--heatmap-max D] [--yaw DEG] [--size N]]\n"
    "                       [--json FILE.json]\n\n"
    "Measures how close mesh A (say, a rig's output) is to mesh B (a real expression shape);\n"
    "meshes are .obj, .gltf or .glb. Distances are in mesh units (docs/model.md §13):\n"
    "  B -> A      mean and max distance from each vertex of B's region to A's surface\n"
    "              (the nearest point of any triangle; Bando et al. 2002 §8), and A -> B.\n"
    "With --neutral N (B's neutral, the same vertex count):\n"
    "  ratio       mean(B -> A) / mean(B -> N): below 1, A is closer to B than doing nothing.\n"
    "When A and B also share topology (vertex count and triangles), per vertex:\n"
    "  error       |A_v - B_v|, mean and max\n"
    "  cosine      sum |dB| cos(dA, dB) / sum |dB|, dA = A - N, dB = B - N (1: same directions)\n"
    "  magnitude   sum |dA| / sum |dB| (1: A moves as much as B)\n\n"
    "--region picks B's vertices: all (default); moved:T, those farther than T from the\n"
    "neutral; or FILE, a list of vertex indices (0-based; whitespace, commas or a JSON array;\n"
    "'#' starts a comment).\n"
    "--heatmap renders B coloured by its distance to A, blue 0 to red D (--heatmap-max,\n"
    "default the largest distance; grey outside the region), with the scale along the\n"
    "bottom; --yaw and --size as in `mimetic render`.\n"
    "--json writes every number to FILE (atomically).\n";

// Reads a vertex list: non-negative integers separated by white space, commas or brackets;
// '#' to the end of a line is a comment.
static bool ReadVertexList(const std::string& path, std::vector<uint32_t>* out,
                           Diagnostics* diag) {
  std::string text;
  if (!ReadFile(path, &text, diag)) return false;
  int line = 1;
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\n') ++line, ++i;
    else if (c == '#') while (i < text.size() && text[i] != '\n') ++i;
    else if (std::isspace(static_cast<unsigned char>(c)) || c == ',' || c == '[' || c == ']') ++i;
    else {
      size_t j = i;
      while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j])) &&
             text[j] != ',' && text[j] != ']' && text[j] != '#')
        ++j;
      const std::string token = text.substr(i, j - i);
      bool digits = token.size() <= 10;
      for (char d : token) digits = digits && std::isdigit(static_cast<unsigned char>(d));
      const unsigned long long v = digits ? std::strtoull(token.c_str(), nullptr, 10) : 0;
      if (!digits || v > 0xFFFFFFFEull) {
        diag->Error(path + ":" + std::to_string(line),
                    "'" + token.substr(0, 40) + "' is not a vertex index; expected a whole "
                    "number >= 0");
        return false;
      }
      out->push_back(static_cast<uint32_t>(v));
      i = j;
    }
  }
  return true;
}

static std::string Num(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// A JSON string literal of `s`.
static std::string JsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else out += c;
  }
  return out + "\"";
}

static std::string DistanceJson(const SurfaceDistance& s) {
  return "{\"mean\": " + Num(s.mean) + ", \"max\": " + Num(s.max) +
         ", \"count\": " + std::to_string(s.count) + "}";
}

int CmdCompare(const Args& args) {
  const ParsedArgs parsed = ParseArgs(
      args, {"neutral", "region", "heatmap", "heatmap-max", "yaw", "size", "json"}, {});
  if (parsed.help) return std::fputs(kCompareUsage, stdout), 0;
  if (!parsed.error.empty()) return UsageError("compare", parsed.error, kCompareUsage);
  if (parsed.positional.size() != 2)
    return UsageError("compare",
                      "expected two meshes A and B, got " + std::to_string(parsed.positional.size()),
                      kCompareUsage);
  if (parsed.Has("heatmap")) {
    const std::string bad_ext = CheckOutputExtension("heatmap", parsed.Get("heatmap"), {".png"});
    if (!bad_ext.empty()) return UsageError("compare", bad_ext, kCompareUsage);
  }
  double heat_max = 0, yaw = 0, size = 800;
  if (parsed.Has("heatmap-max") && !ParseNumber(parsed.Get("heatmap-max"), 1e-30, 1e30, &heat_max))
    return UsageError("compare", "--heatmap-max '" + parsed.Get("heatmap-max") +
                                     "': expected a distance > 0 (mesh units)",
                      kCompareUsage);
  if (parsed.Has("yaw") && !ParseNumber(parsed.Get("yaw"), -3600, 3600, &yaw))
    return UsageError("compare", "--yaw '" + parsed.Get("yaw") + "': expected degrees",
                      kCompareUsage);
  if (parsed.Has("size") && (!ParseNumber(parsed.Get("size"), 16, 8192, &size) ||
                             size != std::floor(size)))
    return UsageError("compare", "--size '" + parsed.Get("size") +
                                     "': expected a whole number of pixels in [16, 8192]",
                      kCompareUsage);
  for (const char* k : {"heatmap-max", "yaw", "size"})
    if (parsed.Has(k) && !parsed.Has("heatmap"))
      return UsageError("compare", std::string("--") + k + " goes with --heatmap", kCompareUsage);

  CompareOptions options;
  const std::string region = parsed.Get("region", "all");
  Diagnostics diag;
  if (region == "all") {
    options.region.kind = CompareRegion::Kind::kAll;
  } else if (region.rfind("moved:", 0) == 0) {
    double t = 0;
    if (!ParseNumber(region.substr(6), 0, 1e30, &t))
      return UsageError("compare", "--region '" + region +
                                       "': expected moved:T with a distance T >= 0",
                        kCompareUsage);
    options.region.kind = CompareRegion::Kind::kMoved;
    options.region.threshold = static_cast<float>(t);
  } else {
    options.region.kind = CompareRegion::Kind::kVertices;
    if (!ReadVertexList(region, &options.region.vertices, &diag)) {
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
  }

  MeshData a, b, neutral;
  const std::string& path_a = parsed.positional[0];
  const std::string& path_b = parsed.positional[1];
  Diagnostics local;
  if (!ImportMesh(path_a, "", &a, &local)) {
    diag.Append(local, path_a);
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  local.Clear();
  if (!ImportMesh(path_b, "", &b, &local)) {
    diag.Append(local, path_b);
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }
  if (parsed.Has("neutral")) {
    local.Clear();
    if (!ImportMesh(parsed.Get("neutral"), "", &neutral, &local)) {
      diag.Append(local, parsed.Get("neutral"));
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
    options.neutral = &neutral;
  }
  CompareResult r;
  local.Clear();
  if (!CompareMeshes(a, b, options, &r, &local)) {
    diag.Append(local, "compare");
    std::fputs(diag.Format().c_str(), stderr);
    return 1;
  }

  std::printf("A: %s (%zu vertices), B: %s (%zu vertices), %s\n", path_a.c_str(),
              a.vertex_count(), path_b.c_str(), b.vertex_count(),
              r.same_topology ? "same topology" : "different topology");
  std::printf("region: %u of B's vertices", r.region_count);
  if (options.region.kind == CompareRegion::Kind::kMoved)
    std::printf(" (moved more than %g from the neutral)", double(options.region.threshold));
  std::printf("\n");
  std::printf("B -> A surface: mean %.6g, max %.6g\n", r.b_to_a.mean, r.b_to_a.max);
  std::printf("A -> B surface: mean %.6g, max %.6g (%u vertices of A)\n", r.a_to_b.mean,
              r.a_to_b.max, r.a_to_b.count);
  if (r.has_neutral_measures)
    std::printf("neutral: B -> neutral surface mean %.6g, max %.6g; ratio %.4g; B moves %.6g "
                "on average\n",
                r.b_to_neutral.mean, r.b_to_neutral.max, r.ratio, r.mean_b_displacement);
  if (r.has_vertex_measures)
    std::printf("per vertex: error mean %.6g, max %.6g; cosine %.4f; magnitude %.4f\n",
                r.vertex_error.mean, r.vertex_error.max, r.direction_cosine, r.magnitude_ratio);
  else if (options.neutral && !r.same_topology)
    std::printf("per vertex: not measured (A and B do not share topology)\n");

  if (parsed.Has("heatmap")) {
    const float max = heat_max > 0 ? float(heat_max) : float(r.b_to_a.max);
    MeshData shown = b;
    shown.normals.clear();
    const std::vector<float3> colors = HeatColors(r.b_distance, max, &r.in_region);
    RenderOptions ro;
    ro.width = ro.height = static_cast<int>(size);
    ro.yaw_deg = static_cast<float>(yaw);
    ro.vertex_colors = &colors;
    Image image = RenderMesh(shown, ro);
    DrawHeatLegend(&image, std::max(6, ro.height / 40), std::max(4, ro.width / 50));
    if (!SavePng(parsed.Get("heatmap"), image, &diag)) {
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
    std::printf("wrote %s: B coloured by distance to A, blue 0 to red %g\n",
                parsed.Get("heatmap").c_str(), double(max));
  }
  if (parsed.Has("json")) {
    std::string j = "{\n  \"a\": " + JsonString(path_a) + ",\n  \"b\": " + JsonString(path_b) + ",\n";
    j += "  \"same_topology\": " + std::string(r.same_topology ? "true" : "false") + ",\n";
    j += "  \"region_count\": " + std::to_string(r.region_count) + ",\n";
    j += "  \"b_to_a\": " + DistanceJson(r.b_to_a) + ",\n";
    j += "  \"a_to_b\": " + DistanceJson(r.a_to_b);
    if (r.has_neutral_measures)
      j += ",\n  \"b_to_neutral\": " + DistanceJson(r.b_to_neutral) + ",\n  \"ratio\": " +
           Num(r.ratio) + ",\n  \"mean_b_displacement\": " + Num(r.mean_b_displacement);
    if (r.has_vertex_measures)
      j += ",\n  \"vertex_error\": " + DistanceJson(r.vertex_error) +
           ",\n  \"direction_cosine\": " + Num(r.direction_cosine) +
           ",\n  \"magnitude_ratio\": " + Num(r.magnitude_ratio) +
           ",\n  \"mean_a_displacement\": " + Num(r.mean_a_displacement);
    j += "\n}\n";
    if (!WriteFileAtomic(parsed.Get("json"), j, &diag)) {
      std::fputs(diag.Format().c_str(), stderr);
      return 1;
    }
    std::printf("wrote %s\n", parsed.Get("json").c_str());
  }
  return 0;
}

}  // namespace mimetic::tools
