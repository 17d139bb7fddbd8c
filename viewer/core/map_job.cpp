// viewer/core/map_job.cpp: see map_job.h.
#include "viewer/core/map_job.h"

#include <cmath>
#include <filesystem>

#include "core/image.h"
#include "io/image.h"
#include "wrinkles/offline/fine_scale.h"

namespace mimetic::viewer {

struct MapJob::Work {
  FineScaleSpec spec;
  std::vector<float3> points;
  FineScaleRigMesh mesh;  // its points span `points`
  std::string out_dir;
  int size = 0;
  uint64_t seed = 1;
};

MapJob::~MapJob() { Wait(); }

void MapJob::Wait() {
  if (worker_.joinable()) worker_.join();
}

bool MapJob::Start(const RigSpec& spec, const Rig& rig, size_t file_vertex_count,
                   const std::string& out_dir, int size, uint64_t seed, std::string* error) {
  if (running_.load()) {
    *error = "the maps are being made already";
    return false;
  }
  if (!spec.fine_scale) {
    *error = "the rig has no fine_scale block (its two direction fields, docs/rig-format.md)";
    return false;
  }
  if (size < 16 || size > kMaxFineScaleSize) {
    *error = "map size " + std::to_string(size) + ": expected 16 to " +
             std::to_string(kMaxFineScaleSize) + " pixels";
    return false;
  }
  auto work = std::make_unique<Work>();
  work->spec = *spec.fine_scale;
  Diagnostics diag;
  if (!MakeFineScaleRigMesh(work->spec, rig.data(), file_vertex_count, &work->mesh, &diag)) {
    *error = diag.Format();
    while (!error->empty() && error->back() == '\n') error->pop_back();
    return false;
  }
  work->points.assign(work->mesh.points.begin(), work->mesh.points.end());
  work->mesh.points = span<const float3>(work->points.data(), work->points.size());
  work->out_dir = out_dir;
  work->size = size;
  work->seed = seed;
  Wait();  // the previous worker has finished (running_ is false): join it
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = false;
  }
  progress_ = 0.f;
  running_ = true;
  worker_ = std::thread([this, w = work.release()] { Run(std::unique_ptr<Work>(w)); });
  return true;
}

void MapJob::Run(std::unique_ptr<Work> w) {
  Diagnostics diag;
  std::vector<std::string> written;
  FineScaleTextureOptions options;
  options.size = w->size;
  options.seed = w->seed;
  options.progress = [this](float f) { progress_ = f; };
  FineScaleMaps maps;
  bool ok = MakeFineScaleMaps(w->spec, w->mesh.view(), w->mesh.anchor_points, options, &maps, &diag);
  if (ok) {
    std::error_code ec;
    std::filesystem::create_directories(w->out_dir, ec);
    if (!std::filesystem::is_directory(w->out_dir)) {
      diag.Error(w->out_dir, "cannot create the folder" + (ec ? ": " + ec.message() : std::string()));
      ok = false;
    }
  }
  const std::vector<float>* heights[3] = {&maps.height[0], &maps.height[1], &maps.merged};
  for (int i = 0; ok && i < 3; ++i) {
    Gray16Image img;  // [0, 1] -> 0..65535, as `mimetic texture` writes them
    img.width = img.height = maps.size;
    img.pixels.resize(heights[i]->size());
    for (size_t p = 0; p < heights[i]->size(); ++p) {
      const float v = std::fmin(1.f, std::fmax(0.f, (*heights[i])[p]));
      img.pixels[p] = uint16_t(std::lround(v * 65535.f));
    }
    const std::string path = (std::filesystem::path(w->out_dir) / kFineMapNames[i]).string();
    ok = SavePng16(path, img, &diag);
    if (ok) written.push_back(path);
  }
  if (ok) {
    Image normal;
    normal.width = normal.height = maps.size;
    normal.rgb = maps.normal;
    const std::string path = (std::filesystem::path(w->out_dir) / kFineMapNames[3]).string();
    ok = SavePng(path, normal, &diag);
    if (ok) written.push_back(path);
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
    ok_ = ok;
    diag_ = std::move(diag);
    written_ = std::move(written);
  }
  progress_ = 1.f;
  running_ = false;
}

bool MapJob::Take(bool* ok, Diagnostics* diag, std::vector<std::string>* written) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!finished_ || running_.load()) return false;
  finished_ = false;
  *ok = ok_;
  *diag = std::move(diag_);
  *written = std::move(written_);
  diag_ = Diagnostics{};
  return true;
}

}  // namespace mimetic::viewer
