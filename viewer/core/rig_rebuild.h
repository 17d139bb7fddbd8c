// viewer/core/rig_rebuild.h: the rig rebuilt from its edited spec off the UI thread
// (docs/viewer.md "Editing the rig").
//
// One worker thread, one build at a time. Request() hands it a spec and returns at once; a
// request made while a build runs waits (only the newest waiting one is kept: edits coalesce),
// and a build that finishes after a newer request is dropped (its rig is stale). Take() gives
// the newest build once it is done; the Session swaps it in on the UI thread between frames.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_builder.h"
#include "rig/offline/rig_spec.h"
#include "rig/runtime/rig.h"

namespace mimetic::viewer {

class RigRebuilder {
 public:
  struct Result {
    uint64_t generation = 0;
    bool ok = false;
    RigSpec spec;  // what was built
    Rig rig;       // ok: the new rig
    Diagnostics diag;
    double ms = 0.0;  // the build's time
  };

  RigRebuilder() = default;
  ~RigRebuilder();  // waits for a running build (BuildRig cannot be interrupted), then stops
  RigRebuilder(const RigRebuilder&) = delete;
  RigRebuilder& operator=(const RigRebuilder&) = delete;

  // Builds `spec` on `mesh` (kept alive by the pointer) on the worker; returns at once with
  // the request's generation.
  uint64_t Request(RigSpec spec, std::shared_ptr<const MeshData> mesh);
  // Drops every waiting and running request (another rig was loaded).
  void Cancel();
  // The newest request's build when it is done (then it is handed over once); false while
  // it runs, or when there is none.
  bool Take(Result* out);
  // A request waits or builds.
  bool busy() const;
  // Milliseconds the running build has taken so far (0 when none runs).
  double elapsed_ms() const;
  // How far the newest build has got (BuildOptions::progress): the share done in [0, 1] and
  // the stage's name; 0 and "queued" from a request until its build starts, 1 and "done" after.
  float progress() const { return progress_.load(); }
  const char* stage() const { return stage_.load(); }
  // Blocks until nothing waits or builds.
  void Wait();
  // The generation of the newest request (0: none yet).
  uint64_t requested() const;

  // Test hook: called on the worker before each build (set it before the first Request).
  std::function<void()> before_build;

 private:
  void Loop();

  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::thread worker_;
  bool stop_ = false, running_ = false;
  uint64_t latest_ = 0;  // the newest request's generation
  struct Pending {
    uint64_t generation;
    RigSpec spec;
    std::shared_ptr<const MeshData> mesh;
  };
  std::optional<Pending> pending_;
  std::unique_ptr<Result> done_;
  std::chrono::steady_clock::time_point started_{};
  std::atomic<float> progress_{1.f};
  std::atomic<const char*> stage_{"done"};  // string literals only
};

}  // namespace mimetic::viewer
