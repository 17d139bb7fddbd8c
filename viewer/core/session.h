// viewer/core/session.h: what the viewer shows, without any GL: the rig, the expression library,
// the clip, the pose, one evaluated frame with its overlay field, and the messages of every load.
//
// Errors never kill it (docs/viewer.md "Errors"): a rig, clip or library that fails to load
// leaves the session as it was and adds every message of the failure to messages().
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "expressions/offline/clip_spec.h"
#include "expressions/runtime/clip.h"
#include "io/expression_file.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"
#include "viewer/core/overlays.h"
#include "viewer/core/thread_pool.h"
#include "viewer/core/timeline.h"

namespace mimetic::viewer {

struct Message {
  bool error = true;
  std::string text;  // "FILE: where: what"
};

// The default expression library for a rig: assets/expressions/default.library.json (or
// expressions/default.library.json) in the rig's folder or up to four folders above; "" when
// there is none.
std::string DefaultLibraryPath(const std::string& rig_path);

// Milliseconds since `start`.
double MillisecondsSince(std::chrono::steady_clock::time_point start);

class Session {
 public:
  // `threads`: evaluation threads in total (0: std::thread::hardware_concurrency()).
  explicit Session(unsigned threads = 0);

  // --- Loading (false: nothing changed, messages added). ---------------------------------
  // A rig replaces the current one; the pose is reset, the clip dropped (it was built for the
  // old rig's muscles) and the library rechecked against the new muscles.
  bool LoadRigFile(const std::string& path);
  // Needs a rig; a .clip.json is built with the library's expressions.
  bool LoadClipFile(const std::string& path);
  bool LoadLibraryFile(const std::string& path);
  // Applies NAME=VALUE settings (mimetic eval --set: BindActivations, jaw=VALUE): false with
  // messages (the pose unchanged) on any bad one.
  bool ApplySettings(const std::vector<std::string>& sets);

  const std::vector<Message>& messages() const { return messages_; }
  void ClearMessages() { messages_.clear(); }
  void AddMessages(const Diagnostics& diag, const std::string& closing);

  // --- State. ------------------------------------------------------------------------------
  bool has_rig() const { return rig_ != nullptr; }
  const LoadedRig& loaded() const { return *rig_; }
  const Rig& rig() const { return rig_->rig; }
  const std::string& rig_path() const { return rig_path_; }
  bool has_clip() const { return clip_ != nullptr; }
  const CompiledClip& clip() const { return *clip_; }
  const std::string& clip_path() const { return clip_path_; }
  const std::vector<TimelineChannel>& timeline() const { return timeline_; }
  const std::vector<Expression>& library() const { return library_; }
  const std::string& library_path() const { return library_path_; }

  // The pose (edited by the panels): one activation per muscle in rig order, the jaw.
  std::vector<float> activations;
  float jaw = 0.f;
  SkinLayers layers;          // ANDed with the rig's own
  bool muscles_enabled = true;  // off: every activation evaluates as 0 (the layer toggle)
  bool jaw_enabled = true;      // off: the jaw evaluates as 0
  bool limit_folds = true;
  // Expression weights, one per library entry (the blend the Expressions panel sets).
  std::vector<float> expression_weights;

  // Activations (and jaw) = the weighted blend of the library's expressions:
  //   a_m = min(1, sum_e w_e a_{e,m}), jaw = min(1, sum_e w_e jaw_e)
  // (an expression's muscles missing from the rig are skipped; they were reported on load).
  void ApplyExpressionBlend();
  // Activations and jaw from the clip at `time` (ClipSampleJob; the jaw only when the clip
  // animates it). False without a clip.
  bool SampleClip(float time);
  void ResetPose();

  // --- One frame. --------------------------------------------------------------------------
  // Evaluates the pose (EvaluateJob with the pool): positions and normals per output vertex;
  // the tension outputs when `overlay` reads them; then the overlay's field (a second
  // evaluation without the wrinkle layers for kWrinkle; X1 and the shrinkage probes for
  // kShrinkage). False without a rig or when the job does not validate.
  bool Evaluate(Overlay overlay);
  const std::vector<float3>& positions() const { return positions_; }
  const std::vector<float3>& normals() const { return normals_; }
  const std::vector<float3>& rest_positions() const { return rest_positions_; }
  const OverlayField& overlay_field() const { return field_; }
  double evaluate_ms() const { return evaluate_ms_; }  // the last Evaluate's EvaluateJob
  double overlay_ms() const { return overlay_ms_; }    // its overlay work (extra evaluations)
  unsigned threads() const { return pool_.threads(); }
  // Bounding box of the rest positions.
  float3 bounds_lo() const { return lo_; }
  float3 bounds_hi() const { return hi_; }
  // Names of the layers the rig compiled (for the stats and the layer toggles).
  std::vector<std::string> RigLayerNames() const;
  // Names of the layers this frame ran (compiled and switched on).
  std::vector<std::string> ActiveLayerNames() const;

 private:
  bool RunJob(const SkinLayers& layers, std::vector<float3>* positions,
              std::vector<float3>* normals, std::vector<float>* tension, EvaluateContext* ctx);
  void CheckLibrary();

  ThreadPool pool_;
  std::unique_ptr<LoadedRig> rig_;
  std::string rig_path_;
  std::unique_ptr<CompiledClip> clip_;
  ClipSpec clip_spec_;
  std::string clip_path_;
  std::vector<TimelineChannel> timeline_;
  std::vector<Expression> library_;
  std::string library_path_;
  std::vector<Message> messages_;

  EvaluateContext context_, aux_context_;
  std::vector<float3> positions_, normals_, rest_positions_, aux_positions_;
  std::vector<float> tension_, shrinkage_, point_shrinkage_, zeros_;
  OverlayField field_;
  double evaluate_ms_ = 0.0, overlay_ms_ = 0.0;
  float3 lo_{}, hi_{};
};

}  // namespace mimetic::viewer
