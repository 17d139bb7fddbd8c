// viewer/core/map_job.h: the fine-scale wrinkle maps of the edited rig made off the UI thread
// (the Directions panel's "Regenerate maps"; docs/viewer.md "Editing the rig"). The same
// library code as `mimetic texture` (wrinkles/offline/fine_scale.h MakeFineScaleMaps): the two
// 16-bit height maps, their merge and the 8-bit normal map, written (atomically) into a folder.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/diagnostics.h"
#include "rig/offline/rig_builder.h"
#include "rig/offline/rig_spec.h"
#include "rig/runtime/rig.h"

namespace mimetic::viewer {

class MapJob {
 public:
  MapJob() = default;
  ~MapJob();  // waits for a running job
  MapJob(const MapJob&) = delete;
  MapJob& operator=(const MapJob&) = delete;

  // Starts the maps of `spec`'s fine_scale block on the welded mesh of `rig` (the rig built
  // from the file's mesh; `file_vertex_count` its vertices) at `size` x `size` pixels with
  // `seed`, to be written into `out_dir` (created when missing). Everything the job reads is
  // copied first. False with *error (nothing started) when one runs or the inputs are wrong.
  bool Start(const RigSpec& spec, const Rig& rig, size_t file_vertex_count,
             const std::string& out_dir, int size, uint64_t seed, std::string* error);
  bool busy() const { return running_.load(); }
  float progress() const { return progress_.load(); }  // [0, 1]
  // The finished job, once: ok, its messages and the files it wrote. False when none finished.
  bool Take(bool* ok, Diagnostics* diag, std::vector<std::string>* written);
  // Blocks until no job runs.
  void Wait();

 private:
  struct Work;
  void Run(std::unique_ptr<Work> work);

  std::thread worker_;
  std::atomic<bool> running_{false};
  std::atomic<float> progress_{0.f};
  std::mutex mutex_;
  bool finished_ = false, ok_ = false;
  Diagnostics diag_;
  std::vector<std::string> written_;
};

// The file names the job writes in its folder (as `mimetic texture` does).
inline constexpr const char* kFineMapNames[4] = {"fine_height_1.png", "fine_height_2.png",
                                                 "fine_height.png", "fine_normal.png"};

}  // namespace mimetic::viewer
