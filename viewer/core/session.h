// viewer/core/session.h: what the viewer shows, without any GL: the rig, the expression library,
// the clip, the pose, one evaluated frame with its overlay field, and the messages of every load.
//
// Errors never kill it (docs/viewer.md "Errors"): a rig, clip or library that fails to load
// leaves the session as it was and adds every message of the failure to messages().
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/image.h"
#include "core/math.h"
#include "expressions/offline/clip_spec.h"
#include "expressions/runtime/clip.h"
#include "io/expression_file.h"
#include "io/companion_meshes.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"
#include "viewer/core/edit.h"
#include "viewer/core/overlays.h"
#include "viewer/core/rig_rebuild.h"
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

// The side file an autosave writes for `path`: PATH.autosave.
std::string AutosavePath(const std::string& path);

// Milliseconds since `start`.
double MillisecondsSince(std::chrono::steady_clock::time_point start);

class Session {
 public:
  // `threads`: evaluation threads in total (0: std::thread::hardware_concurrency()).
  explicit Session(unsigned threads = 0);
  ~Session();  // waits for rig loads still running (StartRigLoad)

  // --- Loading (false: nothing changed, messages added). ---------------------------------
  // A rig replaces the current one; the pose is reset, the clip dropped (it was built for the
  // old rig's muscles) and the library rechecked against the new muscles.
  bool LoadRigFile(const std::string& path);
  // The same off the UI thread (a rig file takes a second or more to build): the load runs on
  // its own thread and the session keeps showing the current rig; PollRigLoad, called once a
  // frame, adopts the newest load's rig when it is done (true: a new rig is shown; false: none
  // finished, or it failed and its messages were added). A newer StartRigLoad supersedes an
  // older one still running (its result is dropped). A load that finishes after the clip or
  // the rig was edited (edits the prompt before loading did not see) is not shown: a message
  // says so and the edits stay.
  void StartRigLoad(const std::string& path);
  bool PollRigLoad();
  bool rig_loading() const;
  const std::string& rig_loading_path() const { return loading_path_; }
  // Blocks until the newest load is done, then PollRigLoad's answer (false when none).
  bool WaitRigLoad();
  // The rig's mesh file's other meshes (the sample head's eyeballs: io ImportOtherMeshes),
  // read with the rig and drawn unposed beside it; none for a .mrig or an OBJ.
  const CompanionMeshes& companions() const { return companions_; }
  // Needs a rig; a .clip.json is built with the library's expressions.
  bool LoadClipFile(const std::string& path);
  bool LoadLibraryFile(const std::string& path);
  // Fine-scale height maps (docs/viewer.md "Fine scale"): DIR/fine_height_1.png and
  // fine_height_2.png, 16-bit, as `mimetic texture` writes them. Needs a rig with texture
  // coordinates; both maps must load and have the same size, else nothing changes.
  bool LoadFineMaps(const std::string& dir);
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
  // Fine-scale bump maps (when loaded): on/off and the depth of a full furrow at amplitude 1,
  // mesh units (mimetic render --fine-depth).
  bool fine_enabled = true;
  float fine_depth = 0.15f;
  bool has_fine_maps() const { return fine_loaded_; }
  const std::string& fine_dir() const { return fine_dir_; }
  const Gray16Image& fine_height(int k) const { return fine_height_[k]; }
  // The maps are drawn this frame: loaded, switched on, and the rig has texture coordinates.
  bool fine_active() const;
  // Per output vertex the two fine-scale amplitudes (a1, a2) of the last Evaluate: the
  // evaluator's (EvaluateJob::out_fine_amplitudes) when the rig has fine-scale fields, else 1.
  // Empty when fine_active() was false.
  const std::vector<float>& fine_amplitudes() const { return fine_amplitudes_; }
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

  // --- Editing (docs/viewer.md "Authoring"). -----------------------------------------------
  // Every edit is a Command (edit.h) applied here: on success it is on the undo stack and the
  // clip (when the clip or the library changed) is rebuilt for playback; on failure nothing
  // changed and the message (also in messages()) is in *error when given. Loading a rig, clip
  // or library forgets the undo and redo stacks (their commands name the old file's keys).
  bool Edit(CommandPtr command, std::string* error = nullptr);
  bool Undo();
  bool Redo(std::string* error = nullptr);
  const EditHistory& history() const { return history_; }
  // The EditDoc bits of the last command done, undone or redone.
  unsigned last_touched() const { return last_touched_; }
  // The clip spec being edited: a .clip.json that was loaded, or a new clip. A compiled .mclip
  // has no spec and cannot be edited.
  bool has_clip_spec() const { return has_clip_spec_; }
  const ClipSpec& clip_spec() const { return clip_spec_; }
  // Starts a new, empty clip to be saved at `path` (its name: the file name without
  // .clip.json). Needs a rig.
  bool NewClip(const std::string& path);
  // A pose setting by name (the Muscles panel, `set NAME VALUE` of a script): a muscle, NAME
  // for NAME_L and NAME_R, or "jaw".
  bool SetByName(const std::string& name, float value, std::string* error = nullptr);
  // The keys selected on the timeline and the copied keys (the commands take them).
  std::vector<KeyRef> selection;
  KeyClipboard clipboard;

  // Saving (atomic: temp file + rename). `path` empty: the file it was loaded from. A failed
  // save says why in messages() (and *error) and keeps the edits and the dirty flag.
  bool SaveClipFile(const std::string& path = "", std::string* error = nullptr);
  bool SaveLibraryFile(const std::string& path = "", std::string* error = nullptr);
  bool clip_dirty() const { return has_clip_spec_ && history_.dirty(kEditClip); }
  bool library_dirty() const { return history_.dirty(kEditLibrary); }

  // Autosave: the edited clip, library and rig spec, when they have changes not saved nor
  // autosaved yet, written to AutosavePath(their file). False (with messages) when a write
  // failed. (A recovered rig spec is rebuilt off the UI thread like an edit.)
  bool Autosave();
  // The autosave files of the current clip, library and rig that exist (newer edits to recover).
  std::vector<std::string> PendingAutosaves() const;
  // Replaces the clip, library and rig spec with their autosaves (each must read and build; the
  // rig's must name the same mesh and muscles); they are then dirty (not saved to their own
  // files). Returns how many were recovered.
  int RecoverAutosaves();
  // Removes the autosave files of the current clip, library and rig.
  void DiscardAutosaves();

  // --- Editing the rig (docs/viewer.md "Editing the rig"; viewer/core/rig_edit.h). -------
  // The spec the rig is built from, as edited (nullptr: no rig, or a compiled .mrig). A rig
  // edit (Edit with a kEditRig command, its undo or redo) changes it at once and starts a
  // rebuild off the UI thread (RigRebuilder: a newer edit supersedes a running build); the
  // session keeps showing the last good rig until PollRigRebuild swaps the new one in. The
  // edit is checked first by the rig file's own rules (the spec's text read back).
  const RigSpec* rig_spec() const { return rig_spec_.get(); }
  bool rig_dirty() const { return rig_spec_ && history_.dirty(kEditRig); }
  // A rebuild waits or runs (the UI shows its progress bar and rig_rebuild_ms()).
  bool rig_rebuilding() const { return rebuilder_.busy(); }
  double rig_rebuild_ms() const { return rebuilder_.elapsed_ms(); }
  // The running rebuild's share done and stage (RigRebuilder::progress, stage).
  float rig_rebuild_progress() const { return rebuilder_.progress(); }
  const char* rig_rebuild_stage() const { return rebuilder_.stage(); }
  // The spec the shown rig was built from differs from rig_spec() (an edit is not built yet,
  // or its build failed).
  bool rig_stale() const { return rig_spec_ && built_generation_ != rebuilder_.requested(); }
  // The generation of the newest rebuild requested (it grows with every rig edit, undo and
  // redo): a caller that must wait for its own edit's build compares it before and after,
  // since a fast build (one refused early) can be over before rig_rebuilding() is asked.
  uint64_t rig_requested() const { return rebuilder_.requested(); }
  // On the UI thread between frames: swaps in a finished rebuild (true: the rig changed, so
  // its mesh must be uploaded again; the pose and the clip stay). A failed build keeps the
  // last good rig and puts its messages in messages().
  bool PollRigRebuild();
  // Blocks until the rebuild is done, then PollRigRebuild (the headless and script path).
  // False when the last build failed.
  bool WaitRigRebuild();
  // Saves the edited spec as a rig file (atomic; `path` empty: the file it was loaded from).
  bool SaveRigFile(const std::string& path = "", std::string* error = nullptr);
  // Edit, merging into the previous command when it was an Edit with the same non-empty
  // `merge` tag and nothing was done since (a continuous drag is one undo step).
  bool EditMerged(CommandPtr command, const std::string& merge, std::string* error = nullptr);
  // Ends a merge (the next EditMerged starts a new undo step).
  void EndMerge() { merge_tag_.clear(); }
  // Test hook: RigRebuilder::before_build (set before the first rig edit).
  void SetRebuildHook(std::function<void()> hook) { rebuilder_.before_build = std::move(hook); }
  // The number of file vertices of the rig's mesh (direction vectors name them).
  size_t mesh_vertex_count() const { return rig_ ? rig_->mesh.vertex_count() : 0; }

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
              std::vector<float3>* normals, std::vector<float>* tension, EvaluateContext* ctx,
              std::vector<float>* fine_amplitudes = nullptr);
  void CheckLibrary();
  EditTarget Target();
  // Rebuilds the clip from the spec (after an edit of the clip or library); false with *error
  // (nullptr: ignore errors) when the spec breaks a rule or does not build.
  bool Rebuild(unsigned touched, std::string* error);
  bool Fail(const std::string& what, std::string* error);
  bool CheckRigSpec(std::string* error);
  void RequestRigRebuild();
  void AdoptRig();  // the rest positions, contexts and bounds of rig_ (after a load or a swap)
  bool SaveDocument(const char* what, const std::string& path, std::string* current_path,
                    EditDoc document, const std::function<bool(Diagnostics*)>& write,
                    std::string* error);

  Gray16Image fine_height_[2];
  std::string fine_dir_;
  bool fine_loaded_ = false;
  std::vector<float> fine_amplitudes_;
  ThreadPool pool_;
  std::unique_ptr<LoadedRig> rig_;
  std::string rig_path_;
  std::unique_ptr<RigSpec> rig_spec_;
  std::shared_ptr<const MeshData> rig_mesh_;
  uint64_t built_generation_ = 0;  // the rebuild the shown rig came from
  std::string merge_tag_;
  size_t merge_undo_size_ = 0;
  std::unique_ptr<CompiledClip> clip_;
  ClipSpec clip_spec_;
  bool has_clip_spec_ = false;
  unsigned last_touched_ = 0;
  EditHistory history_;
  uint64_t autosaved_[3] = {0, 0, 0};  // clip, library, rig versions last autosaved
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
  // Rig loads off the UI thread (StartRigLoad): each its own thread and result; the newest is
  // `load_`, older ones are only joined.
  struct PendingLoad {
    std::string path;
    std::mutex mutex;
    bool done = false, ok = false;
    std::unique_ptr<LoadedRig> rig;
    CompanionMeshes companions;
    Diagnostics diag;
  };
  CompanionMeshes companions_;
  std::shared_ptr<PendingLoad> load_;
  std::string loading_path_;
  uint64_t load_versions_[2] = {0, 0};  // the clip's and the rig's edit versions at the start
  std::vector<std::pair<std::thread, std::shared_ptr<PendingLoad>>> loaders_;
  void JoinFinishedLoaders(bool all);
  bool AdoptLoadedRig(const std::string& path, std::unique_ptr<LoadedRig> loaded, const Diagnostics& diag,
                      CompanionMeshes companions = {});
  RigRebuilder rebuilder_;  // last: its destructor joins the worker before the rest goes
};

}  // namespace mimetic::viewer
