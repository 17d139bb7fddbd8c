// viewer/core/session.cpp: see session.h.
#include "viewer/core/session.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <set>

#include "expressions/offline/activation_binding.h"
#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"
#include "io/clip_file.h"
#include "core/file_util.h"
#include "io/expression_library.h"
#include "io/image.h"
#include "io/rig_file.h"
#include "rig/offline/jaw_setting.h"
#include "rig/offline/rig_builder.h"
#include "wrinkles/runtime/strain_jobs.h"

namespace mimetic::viewer {
namespace {

span<float> Floats(std::vector<float3>& v) { return {reinterpret_cast<float*>(v.data()), 3 * v.size()}; }

}  // namespace

std::string DefaultLibraryPath(const std::string& rig_path) {
  std::error_code ec;
  std::filesystem::path dir = std::filesystem::absolute(rig_path, ec).parent_path();
  for (int i = 0; i < 5 && !dir.empty(); ++i, dir = dir.parent_path()) {
    for (const char* rel : {"expressions/default.library.json",
                            "assets/expressions/default.library.json"}) {
      const std::filesystem::path p = dir / rel;
      if (std::filesystem::is_regular_file(p, ec)) return p.string();
    }
    if (dir == dir.parent_path()) break;
  }
  return "";
}

std::string AutosavePath(const std::string& path) { return path + ".autosave"; }

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

Session::Session(unsigned threads)
    : pool_(threads ? threads : std::max(1u, std::thread::hardware_concurrency())) {}

void Session::AddMessages(const Diagnostics& diag, const std::string& closing) {
  for (const Diagnostic& d : diag.items())
    messages_.push_back({d.severity == Severity::kError,
                         d.where.empty() ? d.what : d.where + ": " + d.what});
  if (!closing.empty()) messages_.push_back({diag.HasErrors(), closing});
}

namespace {
// The rig's mesh file's other meshes (io/companion_meshes.h); a file that fails to give them
// is a warning (the rig itself loaded), not an error.
CompanionMeshes LoadCompanions(const LoadedRig& loaded, Diagnostics* diag) {
  CompanionMeshes out;
  Diagnostics local;
  if (!LoadCompanionMeshes(loaded, &out, &local)) {
    out = CompanionMeshes{};
    diag->Warning(loaded.spec.mesh_path, "its other meshes are not drawn: " + local.Format());
  }
  return out;
}
}  // namespace

bool Session::LoadRigFile(const std::string& path) {
  auto loaded = std::make_unique<LoadedRig>();
  Diagnostics diag;
  const bool ok = LoadRig(path, loaded.get(), &diag);
  CompanionMeshes companions;
  if (ok) companions = LoadCompanions(*loaded, &diag);
  return AdoptLoadedRig(path, ok ? std::move(loaded) : nullptr, diag, std::move(companions));
}

Session::~Session() { JoinFinishedLoaders(true); }

void Session::StartRigLoad(const std::string& path) {
  JoinFinishedLoaders(false);
  auto job = std::make_shared<PendingLoad>();
  job->path = path;
  load_ = job;
  loading_path_ = path;
  load_versions_[0] = history_.version(kEditClip);
  load_versions_[1] = history_.version(kEditRig);
  std::thread worker([job] {
    auto loaded = std::make_unique<LoadedRig>();
    Diagnostics diag;
    const bool ok = LoadRig(job->path, loaded.get(), &diag);
    CompanionMeshes companions;
    if (ok) companions = LoadCompanions(*loaded, &diag);
    std::lock_guard<std::mutex> lock(job->mutex);
    job->companions = std::move(companions);
    job->ok = ok;
    job->rig = std::move(loaded);
    job->diag = std::move(diag);
    job->done = true;
  });
  loaders_.emplace_back(std::move(worker), job);
}

void Session::JoinFinishedLoaders(bool all) {
  for (size_t i = 0; i < loaders_.size();) {
    bool done = all;
    if (!done) {
      std::lock_guard<std::mutex> lock(loaders_[i].second->mutex);
      done = loaders_[i].second->done;
    }
    if (done) {
      if (loaders_[i].first.joinable()) loaders_[i].first.join();
      loaders_.erase(loaders_.begin() + std::ptrdiff_t(i));
    } else {
      ++i;
    }
  }
}

bool Session::rig_loading() const {
  if (!load_) return false;
  std::lock_guard<std::mutex> lock(load_->mutex);
  return !load_->done;
}

bool Session::PollRigLoad() {
  if (!load_) return false;
  std::unique_ptr<LoadedRig> rig;
  CompanionMeshes companions;
  Diagnostics diag;
  bool ok = false;
  {
    std::lock_guard<std::mutex> lock(load_->mutex);
    if (!load_->done) return false;
    ok = load_->ok;
    rig = std::move(load_->rig);
    companions = std::move(load_->companions);
    diag = std::move(load_->diag);
  }
  const std::string path = load_->path;
  load_.reset();
  loading_path_.clear();
  JoinFinishedLoaders(false);
  if (ok && (history_.version(kEditClip) != load_versions_[0] ||
             history_.version(kEditRig) != load_versions_[1])) {
    messages_.push_back({true, path + ": loaded, but not shown: the clip or the rig was edited "
                                      "while it loaded, and showing it would drop those edits; "
                                      "load it again to replace them"});
    return false;
  }
  return AdoptLoadedRig(path, ok ? std::move(rig) : nullptr, diag, std::move(companions));
}

bool Session::WaitRigLoad() {
  if (!load_) return false;
  for (auto& [thread, job] : loaders_)
    if (job == load_) {
      thread.join();
      thread = std::thread();
    }
  return PollRigLoad();
}

bool Session::AdoptLoadedRig(const std::string& path, std::unique_ptr<LoadedRig> loaded,
                             const Diagnostics& diag, CompanionMeshes companions) {
  if (!loaded) {
    AddMessages(diag, path + ": " + std::to_string(diag.ErrorCount()) +
                          " error(s); the rig was not loaded" +
                          (rig_ ? " (still showing " + rig_path_ + ")" : ""));
    return false;
  }
  AddMessages(diag, "");
  rig_ = std::move(loaded);
  companions_ = std::move(companions);
  rig_path_ = path;
  rebuilder_.Cancel();  // a rebuild of the old rig's spec is stale
  built_generation_ = rebuilder_.requested();
  merge_tag_.clear();
  if (rig_->compiled) {
    rig_spec_.reset();
    rig_mesh_.reset();
  } else {
    rig_spec_ = std::make_unique<RigSpec>(rig_->spec);
    rig_mesh_ = std::make_shared<const MeshData>(rig_->mesh);
  }
  clip_.reset();
  clip_path_.clear();
  timeline_.clear();
  has_clip_spec_ = false;
  clip_spec_ = ClipSpec{};
  selection.clear();
  history_.Clear();
  history_.MarkSaved(kEditClip);
  history_.MarkSaved(kEditRig);
  AdoptRig();
  ResetPose();
  CheckLibrary();
  return true;
}

void Session::AdoptRig() {
  const Rig& rig = rig_->rig;
  context_.Resize(rig);
  aux_context_.Resize(rig);
  const MeshData rest = RestMesh(rig);
  rest_positions_ = rest.positions;
  positions_ = rest_positions_;
  normals_.assign(rig.vertex_count(), float3{0.f, 0.f, 1.f});
  field_ = OverlayField{};
  lo_ = hi_ = rest_positions_.empty() ? float3{} : rest_positions_[0];
  for (const float3& p : rest_positions_) {
    lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y), std::min(lo_.z, p.z)};
    hi_ = {std::max(hi_.x, p.x), std::max(hi_.y, p.y), std::max(hi_.z, p.z)};
  }
}

void Session::CheckLibrary() {
  if (!rig_ || library_.empty()) return;
  Diagnostics diag;
  std::vector<std::string> names = rig().muscle_names();
  names.push_back(kJawInputName);
  if (CheckLibraryMuscles(library_, names, library_path_, &diag)) return;
  // Not fatal here: the blend skips unknown muscles. A library made for another rig names
  // dozens of them; past a few, one summary line says how many and which instead.
  constexpr size_t kListed = 3;
  Diagnostics warnings;
  for (size_t i = 0; i < diag.items().size() && i < kListed; ++i)
    warnings.Warning(diag.items()[i].where, diag.items()[i].what);
  if (diag.items().size() > kListed) {
    std::set<std::string> unknown, expressions;
    const std::set<std::string> known(names.begin(), names.end());
    for (const Expression& e : library_)
      for (const auto& [muscle, value] : e.activations)
        if (!known.count(muscle)) unknown.insert(muscle), expressions.insert(e.name);
    std::string list;
    for (const std::string& m : unknown) list += (list.empty() ? "" : ", ") + m;
    warnings.Warning(library_path_,
                     std::to_string(diag.items().size() - kListed) + " more activations name muscles the rig lacks (" +
                         std::to_string(expressions.size()) + " of " + std::to_string(library_.size()) +
                         " expressions, " + std::to_string(unknown.size()) + " muscles: " + list +
                         "); the blends skip them (is the library made for another rig?)");
  }
  AddMessages(warnings, "");
}

bool Session::LoadLibraryFile(const std::string& path) {
  std::vector<Expression> library;
  Diagnostics diag;
  if (!LoadExpressionLibrary(path, &library, &diag)) {
    AddMessages(diag, path + ": " + std::to_string(diag.ErrorCount()) +
                          " error(s); the expression library was not loaded");
    return false;
  }
  AddMessages(diag, "");
  library_ = std::move(library);
  library_path_ = path;
  expression_weights.assign(library_.size(), 0.f);
  history_.Clear();
  history_.MarkSaved(kEditLibrary);
  CheckLibrary();
  if (has_clip_spec_) Rebuild(kEditLibrary, nullptr);  // its expressions may have changed
  return true;
}

bool Session::LoadClipFile(const std::string& path) {
  if (!rig_) {
    messages_.push_back({true, path + ": no rig is loaded; open a rig before its clips"});
    return false;
  }
  auto clip = std::make_unique<CompiledClip>();
  ClipSpec spec;
  Diagnostics diag;
  bool ok = false;
  if (IsCompiledClipPath(path)) {
    std::string why;
    ok = LoadClipBinaryFile(path, clip.get(), &why);
    if (!ok) diag.Error("", why);
    if (ok && clip->muscle_count() != rig().muscle_count()) {
      diag.Error(path, "compiled for " + std::to_string(clip->muscle_count()) +
                           " muscles, but the rig " + rig_path_ + " has " +
                           std::to_string(rig().muscle_count()) +
                           " (mimetic build CLIP.clip.json --rig RIG --out FILE.mclip)");
      ok = false;
    }
  } else if (LoadClip(path, &spec, &diag)) {
    Diagnostics build;
    ok = BuildClip(spec, rig().muscle_names(), library_, clip.get(), &build);
    diag.Append(build, path);
    if (!ok && library_.empty())
      diag.Error(path, "no expression library is loaded (--library LIB, or the Expressions "
                       "panel), so its expression channels have nothing to name");
  }
  if (!ok) {
    AddMessages(diag, path + ": " + std::to_string(diag.ErrorCount()) +
                          " error(s); the clip was not loaded");
    return false;
  }
  if (clip->animates_jaw() && rig().jaw().empty())
    diag.Warning(path, "animates the jaw, but the rig has none (the jaw values do nothing)");
  AddMessages(diag, "");
  clip_ = std::move(clip);
  has_clip_spec_ = !IsCompiledClipPath(path);
  clip_spec_ = std::move(spec);
  clip_path_ = path;
  selection.clear();
  history_.Clear();
  history_.MarkSaved(kEditClip);
  timeline_ = ListTimeline(*clip_, rig().muscle_names(),
                           IsCompiledClipPath(path) ? nullptr : &clip_spec_);
  return true;
}

EditTarget Session::Target() {
  static const std::vector<std::string> kNoMuscles;
  EditTarget t;
  t.has_clip = &has_clip_spec_;
  t.clip = &clip_spec_;
  t.library = &library_;
  t.activations = &activations;
  t.jaw = &jaw;
  t.muscle_names = rig_ ? &rig().muscle_names() : &kNoMuscles;
  t.rig_spec = rig_spec_.get();
  return t;
}

bool Session::Fail(const std::string& what, std::string* error) {
  messages_.push_back({true, what});
  if (error) *error = what;
  return false;
}

bool Session::Rebuild(unsigned touched, std::string* error) {
  if (touched & kEditLibrary) {
    if (expression_weights.size() != library_.size()) expression_weights.assign(library_.size(), 0.f);
  }
  if (!(touched & (kEditClip | kEditLibrary)) || !has_clip_spec_) return true;
  if (!rig_ || clip_spec_.channels.empty()) {  // nothing to play yet
    clip_.reset();
    timeline_.clear();
    return true;
  }
  Diagnostics diag;
  auto clip = std::make_unique<CompiledClip>();
  if (!CheckClipSpec(clip_spec_, &diag) ||
      !BuildClip(clip_spec_, rig().muscle_names(), library_, clip.get(), &diag)) {
    if (error) {
      for (const Diagnostic& d : diag.items())
        if (d.severity == Severity::kError) {
          *error = "the clip would break a rule: " + (d.where.empty() ? d.what : d.where + ": " + d.what);
          break;
        }
    }
    return false;
  }
  clip_ = std::move(clip);
  timeline_ = ListTimeline(*clip_, rig().muscle_names(), &clip_spec_);
  return true;
}

bool Session::Edit(CommandPtr command, std::string* error) {
  merge_tag_.clear();
  if (!command) return Fail("edit: no command", error);
  const std::string what = command->Describe();
  last_touched_ = command->Touches();
  std::string why;
  const auto validate = [this](unsigned touched, std::string* e) {
    return Rebuild(touched, e) && (!(touched & kEditRig) || CheckRigSpec(e));
  };
  if (!history_.Do(std::move(command), Target(), validate, &why))
    return Fail(what + ": " + why, error);
  if (last_touched_ & kEditRig) RequestRigRebuild();
  return true;
}

bool Session::EditMerged(CommandPtr command, const std::string& merge, std::string* error) {
  const bool merging = !merge.empty() && merge == merge_tag_ &&
                       history_.undo_size() == merge_undo_size_ && history_.CanUndo();
  if (merging) {
    // Back to the state before the merged run began; the new command starts from there.
    unsigned touched = 0;
    history_.Undo(Target(), &touched);
    Rebuild(touched, nullptr);
  }
  if (!Edit(std::move(command), error)) {
    if (merging) {  // put the run's last step back
      unsigned touched = 0;
      std::string ignored;
      const auto validate = [this](unsigned t, std::string* e) {
        return Rebuild(t, e) && (!(t & kEditRig) || CheckRigSpec(e));
      };
      // (The spec is back to the one its rebuild was last asked for: nothing to ask again.)
      if (history_.Redo(Target(), validate, &touched, &ignored)) {
        merge_tag_ = merge;  // the drag goes on from its last good step
        merge_undo_size_ = history_.undo_size();
      }
    }
    return false;
  }
  merge_tag_ = merge;
  merge_undo_size_ = history_.undo_size();
  return true;
}

bool Session::Undo() {
  merge_tag_.clear();
  unsigned touched = 0;
  if (!history_.Undo(Target(), &touched)) return false;
  last_touched_ = touched;
  if (touched & kEditClip) selection.clear();
  Rebuild(touched, nullptr);
  if (touched & kEditRig) RequestRigRebuild();
  return true;
}

bool Session::Redo(std::string* error) {
  merge_tag_.clear();
  unsigned touched = 0;
  std::string why;
  const auto validate = [this](unsigned t, std::string* e) {
    return Rebuild(t, e) && (!(t & kEditRig) || CheckRigSpec(e));
  };
  if (!history_.Redo(Target(), validate, &touched, &why)) {
    if (why.empty()) return false;
    return Fail("redo: " + why, error);
  }
  last_touched_ = touched;
  if (touched & kEditClip) selection.clear();
  if (touched & kEditRig) RequestRigRebuild();
  return true;
}

// The edited spec must read back as a rig file: the rules between fields are the reader's.
// The parts no edit changes and that may be large (per-vertex thickness, the tension regions'
// weights; they were checked when the rig loaded) are left out, so that a drag step stays far
// under a frame on any rig.
bool Session::CheckRigSpec(std::string* error) {
  if (!rig_spec_) return true;
  const std::string dir = DirectoryOf(rig_path_);
  RigSpec checked;
  {
    ThicknessSpec thickness = std::move(rig_spec_->thickness);
    std::vector<TensionRegionSpec> regions = std::move(rig_spec_->tension_regions);
    checked = *rig_spec_;
    rig_spec_->thickness = std::move(thickness);
    rig_spec_->tension_regions = std::move(regions);
  }
  checked.thickness = ThicknessSpec{};
  checked.thickness.value = 1.f;  // a constant, as valid as the loaded one was
  std::string why;
  const std::string text = RigSpecText(checked, dir, &why);
  if (text.empty()) {
    if (error) *error = "the rig cannot be written: " + why;
    return false;
  }
  RigSpec reread;
  Diagnostics diag;
  if (ParseRigSpec(text, dir, &reread, &diag)) return true;
  if (error) {
    *error = "the rig would break a rule";
    for (const Diagnostic& d : diag.items())
      if (d.severity == Severity::kError) {
        *error += ": " + (d.where.empty() ? d.what : d.where + ": " + d.what);
        break;
      }
  }
  return false;
}

void Session::RequestRigRebuild() {
  if (!rig_spec_ || !rig_mesh_) return;
  rebuilder_.Request(*rig_spec_, rig_mesh_);
}

bool Session::PollRigRebuild() {
  RigRebuilder::Result result;
  if (!rig_ || !rebuilder_.Take(&result)) return false;
  if (!result.ok) {
    AddMessages(result.diag, rig_path_ + ": the edited rig did not build (" +
                                 std::to_string(result.diag.ErrorCount()) +
                                 " error(s)); still showing the last good rig");
    return false;
  }
  if (!result.diag.empty()) AddMessages(result.diag, "");
  rig_->rig = std::move(result.rig);
  rig_->spec = std::move(result.spec);
  built_generation_ = result.generation;
  AdoptRig();
  activations.resize(rig().muscle_count(), 0.f);
  return true;
}

bool Session::WaitRigRebuild() {
  rebuilder_.Wait();
  PollRigRebuild();
  return !rig_stale();
}

bool Session::SaveRigFile(const std::string& path_in, std::string* error) {
  if (!rig_spec_) return Fail("save rig: the rig has no editable spec (a compiled .mrig)", error);
  const std::string path = path_in.empty() ? rig_path_ : path_in;
  if (path.empty()) return Fail("save rig: no file name given", error);
  if (IsCompiledRigPath(path) && path != rig_path_)
    return Fail(path + ": save rig: a rig file is JSON (.rig.json), not a compiled .mrig", error);
  return SaveDocument("rig", path, &rig_path_, kEditRig,
                      [&](Diagnostics* diag) { return SaveRigSpec(path, *rig_spec_, diag); },
                      error);
}

bool Session::NewClip(const std::string& path) {
  if (!rig_) return Fail(path + ": no rig is loaded; open a rig before making a clip", nullptr);
  std::string name = std::filesystem::path(path).filename().string();
  for (const char* ext : {".clip.json", ".json"})
    if (name.size() > std::strlen(ext) && name.compare(name.size() - std::strlen(ext), std::strlen(ext), ext) == 0) {
      name.resize(name.size() - std::strlen(ext));
      break;
    }
  clip_spec_ = ClipSpec{};
  clip_spec_.name = name.empty() ? "untitled" : name;
  has_clip_spec_ = true;
  clip_.reset();
  timeline_.clear();
  clip_path_ = path;
  selection.clear();
  history_.Clear();
  history_.MarkChanged(kEditClip);  // not saved yet
  return true;
}

bool Session::SetByName(const std::string& name, float value, std::string* error) {
  if (!rig_) return Fail("set " + name + ": no rig is loaded", error);
  if (name == kJawInputName && rig().FindMuscle(name) < 0) return Edit(MakeSetJaw(value), error);
  std::vector<uint32_t> muscles;
  if (const int m = rig().FindMuscle(name); m >= 0) {
    muscles.push_back(uint32_t(m));
  } else {
    const int l = rig().FindMuscle(name + "_L"), r = rig().FindMuscle(name + "_R");
    if (l < 0 || r < 0)
      return Fail("set " + name + ": the rig has no muscle '" + name + "' (nor " + name + "_L and " +
                      name + "_R); the closest: " + ClosestNames(rig().muscle_names(), name),
                  error);
    muscles = {uint32_t(l), uint32_t(r)};
  }
  return Edit(MakeSetMuscles(std::move(muscles), value), error);
}

// A save of the clip or the library: write through `write` (atomic, docs/viewer.md "Safety"),
// then forget the autosaves of the old and the new file and mark that document saved. A failed
// write keeps the edits and says why.
bool Session::SaveDocument(const char* what, const std::string& path, std::string* current_path,
                           EditDoc document, const std::function<bool(Diagnostics*)>& write,
                           std::string* error) {
  if (path.empty()) return Fail(std::string("save ") + what + ": no file name given", error);
  Diagnostics diag;
  if (!write(&diag)) {
    AddMessages(diag, "");
    const std::string first = diag.Format().substr(0, diag.Format().find('\n'));
    return Fail(path + ": the " + what + " was not saved (" + first + "); the edits are kept, unsaved",
                error);
  }
  if (!current_path->empty()) std::remove(AutosavePath(*current_path).c_str());
  std::remove(AutosavePath(path).c_str());
  *current_path = path;
  history_.MarkSaved(document);
  return true;
}

bool Session::SaveClipFile(const std::string& path_in, std::string* error) {
  if (!has_clip_spec_) return Fail("save clip: no clip is open for editing", error);
  const std::string path = path_in.empty() ? clip_path_ : path_in;
  return SaveDocument("clip", path, &clip_path_, kEditClip,
                      [&](Diagnostics* diag) { return SaveClip(path, clip_spec_, diag); }, error);
}

bool Session::SaveLibraryFile(const std::string& path_in, std::string* error) {
  const std::string path = path_in.empty() ? library_path_ : path_in;
  return SaveDocument("library", path, &library_path_, kEditLibrary,
                      [&](Diagnostics* diag) { return SaveExpressionLibrary(path, library_, diag); },
                      error);
}

bool Session::Autosave() {
  bool ok = true;
  if (clip_dirty() && !clip_path_.empty() && history_.version(kEditClip) != autosaved_[0] &&
      !clip_spec_.channels.empty()) {
    Diagnostics diag;
    if (SaveClip(AutosavePath(clip_path_), clip_spec_, &diag)) {
      autosaved_[0] = history_.version(kEditClip);
    } else {
      AddMessages(diag, AutosavePath(clip_path_) + ": the autosave failed");
      ok = false;
    }
  }
  if (rig_dirty() && !rig_path_.empty() && history_.version(kEditRig) != autosaved_[2]) {
    Diagnostics diag;
    if (SaveRigSpec(AutosavePath(rig_path_), *rig_spec_, &diag)) {
      autosaved_[2] = history_.version(kEditRig);
    } else {
      AddMessages(diag, AutosavePath(rig_path_) + ": the autosave failed");
      ok = false;
    }
  }
  if (library_dirty() && !library_path_.empty() && history_.version(kEditLibrary) != autosaved_[1]) {
    Diagnostics diag;
    if (SaveExpressionLibrary(AutosavePath(library_path_), library_, &diag)) {
      autosaved_[1] = history_.version(kEditLibrary);
    } else {
      AddMessages(diag, AutosavePath(library_path_) + ": the autosave failed");
      ok = false;
    }
  }
  return ok;
}

std::vector<std::string> Session::PendingAutosaves() const {
  std::vector<std::string> out;
  std::error_code ec;
  for (const std::string* p : {&clip_path_, &library_path_})
    if (!p->empty() && std::filesystem::is_regular_file(AutosavePath(*p), ec))
      out.push_back(AutosavePath(*p));
  if (rig_spec_ && !rig_path_.empty() && std::filesystem::is_regular_file(AutosavePath(rig_path_), ec))
    out.push_back(AutosavePath(rig_path_));
  return out;
}

int Session::RecoverAutosaves() {
  int recovered = 0;
  std::error_code ec;
  if (rig_spec_ && !rig_path_.empty() && std::filesystem::is_regular_file(AutosavePath(rig_path_), ec)) {
    const std::string path = AutosavePath(rig_path_);
    RigSpec spec;
    Diagnostics diag;
    bool ok = LoadRigSpec(path, &spec, &diag);
    if (ok && std::filesystem::weakly_canonical(spec.mesh_path, ec) !=
                  std::filesystem::weakly_canonical(rig_spec_->mesh_path, ec)) {
      diag.Error(path, "names the mesh " + spec.mesh_path + ", but the rig's is " + rig_spec_->mesh_path);
      ok = false;
    }
    bool same_muscles = ok && spec.muscles.size() == rig_spec_->muscles.size();
    for (size_t m = 0; same_muscles && m < spec.muscles.size(); ++m)
      same_muscles = spec.muscles[m].name == rig_spec_->muscles[m].name;
    if (ok && !same_muscles) {
      diag.Error(path, "has other muscles than the rig (the pose and the clip name the rig's)");
      ok = false;
    }
    if (ok && spec.thickness.kind == ThicknessSpec::Kind::kImage)
      ok = LoadGrayImage(spec.thickness.image_path, "thickness.path", "thickness image",
                         &spec.thickness.image, &diag);
    if (ok) {
      spec.file = rig_path_;
      *rig_spec_ = std::move(spec);
      history_.Clear();
      history_.MarkChanged(kEditRig);
      RequestRigRebuild();
      ++recovered;
      messages_.push_back({false, path + ": recovered (not saved yet; the rig is being rebuilt)"});
    } else {
      AddMessages(diag, path + ": not recovered");
    }
  }
  if (!library_path_.empty() && std::filesystem::is_regular_file(AutosavePath(library_path_), ec)) {
    std::vector<Expression> library;
    Diagnostics diag;
    if (LoadExpressionLibrary(AutosavePath(library_path_), &library, &diag)) {
      library_ = std::move(library);
      expression_weights.assign(library_.size(), 0.f);
      history_.Clear();
      history_.MarkChanged(kEditLibrary);
      ++recovered;
      messages_.push_back({false, AutosavePath(library_path_) + ": recovered (not saved yet)"});
    } else {
      AddMessages(diag, AutosavePath(library_path_) + ": not recovered");
    }
  }
  if (!clip_path_.empty() && rig_ && std::filesystem::is_regular_file(AutosavePath(clip_path_), ec)) {
    ClipSpec spec;
    Diagnostics diag;
    auto clip = std::make_unique<CompiledClip>();
    if (LoadClip(AutosavePath(clip_path_), &spec, &diag) &&
        BuildClip(spec, rig().muscle_names(), library_, clip.get(), &diag)) {
      clip_spec_ = std::move(spec);
      has_clip_spec_ = true;
      clip_ = std::move(clip);
      timeline_ = ListTimeline(*clip_, rig().muscle_names(), &clip_spec_);
      selection.clear();
      history_.Clear();
      history_.MarkChanged(kEditClip);
      ++recovered;
      messages_.push_back({false, AutosavePath(clip_path_) + ": recovered (not saved yet)"});
    } else {
      AddMessages(diag, AutosavePath(clip_path_) + ": not recovered");
    }
  } else if (has_clip_spec_) {
    Rebuild(kEditLibrary, nullptr);
  }
  return recovered;
}

void Session::DiscardAutosaves() {
  for (const std::string& p : PendingAutosaves()) std::remove(p.c_str());
}

bool Session::ApplySettings(const std::vector<std::string>& sets) {
  if (!rig_) return false;
  std::vector<std::string> rest = sets;
  Diagnostics diag;
  float new_jaw = 0.f;
  std::vector<float> values;
  const bool jaw_ok = TakeJawSetting(rig(), &rest, &new_jaw, &diag);
  const bool bind_ok = BindActivations(rig().muscle_names(), rest, &values, &diag);
  if (!jaw_ok || !bind_ok) {
    AddMessages(diag, "--set: " + std::to_string(diag.ErrorCount()) + " error(s); the pose was not changed");
    return false;
  }
  activations = std::move(values);
  jaw = new_jaw;
  return true;
}

void Session::ResetPose() {
  activations.assign(rig_ ? rig().muscle_count() : 0, 0.f);
  jaw = 0.f;
  std::fill(expression_weights.begin(), expression_weights.end(), 0.f);
}

void Session::ApplyExpressionBlend() {
  if (!rig_) return;
  activations.assign(rig().muscle_count(), 0.f);
  jaw = 0.f;
  for (size_t e = 0; e < library_.size() && e < expression_weights.size(); ++e) {
    const float w = expression_weights[e];
    if (w == 0.f) continue;
    for (const auto& [name, value] : library_[e].activations) {
      if (name == kJawInputName && rig().FindMuscle(name) < 0) {
        jaw = std::min(1.f, jaw + w * value);
      } else if (const int m = rig().FindMuscle(name); m >= 0) {
        activations[size_t(m)] = std::min(1.f, activations[size_t(m)] + w * value);
      }
    }
  }
}

bool Session::SampleClip(float time) {
  if (!rig_ || !clip_) return false;
  activations.resize(rig().muscle_count());
  float sampled_jaw = 0.f;
  ClipSampleJob job;
  job.clip = clip_.get();
  job.time = time;
  job.out_activations = activations;
  job.out_jaw = span<float>(&sampled_jaw, 1);
  if (!job.Run()) return false;
  if (clip_->animates_jaw()) jaw = sampled_jaw;
  return true;
}

bool Session::RunJob(const SkinLayers& run_layers, std::vector<float3>* positions,
                     std::vector<float3>* normals, std::vector<float>* tension,
                     EvaluateContext* ctx, std::vector<float>* fine_amplitudes) {
  EvaluateJob job;
  job.rig = &rig();
  job.context = ctx;
  zeros_.assign(activations.size(), 0.f);
  job.activations = muscles_enabled ? activations : zeros_;
  job.jaw = jaw_enabled ? jaw : 0.f;
  job.out_positions = Floats(*positions);
  if (normals) job.out_normals = Floats(*normals);
  if (tension) job.out_tension = *tension;
  if (fine_amplitudes) job.out_fine_amplitudes = *fine_amplitudes;
  job.layers = run_layers;
  job.limit_folds = limit_folds;
  if (pool_.threads() > 1) {
    job.parallel_for = &ThreadPool::ParallelFor;
    job.parallel_for_user = &pool_;
  }
  return job.Run();
}

bool Session::Evaluate(Overlay overlay) {
  if (!rig_) return false;
  const Rig& r = rig();
  const uint32_t nv = r.vertex_count();
  activations.resize(r.muscle_count(), 0.f);
  positions_.resize(nv);
  normals_.resize(nv);
  const bool wants_tension = overlay == Overlay::kAreaRatio || overlay == Overlay::kCompression;
  if (wants_tension) tension_.resize(2 * size_t(nv));
  auto start = std::chrono::steady_clock::now();
  // Fine scale: the evaluator's amplitudes when the rig has fields; 1 everywhere without
  // (the maps drawn as they are, like mimetic render --fine on a plain mesh).
  const bool fine = fine_active();
  const bool fine_from_job = fine && !r.fine_scale().empty();
  if (fine) fine_amplitudes_.assign(2 * size_t(nv), 1.f);
  else fine_amplitudes_.clear();
  if (!RunJob(layers, &positions_, &normals_, wants_tension ? &tension_ : nullptr, &context_,
              fine_from_job ? &fine_amplitudes_ : nullptr))
    return false;
  evaluate_ms_ = MillisecondsSince(start);

  start = std::chrono::steady_clock::now();
  OverlayInputs in;
  in.vertex_points = r.vertex_points();
  in.rest_positions = rest_positions_;
  in.positions = positions_;
  in.normals = normals_;
  in.tension = tension_;
  in.point_thickness = r.point_thickness();
  if (overlay == Overlay::kWrinkle) {
    SkinLayers unwrinkled = layers;
    unwrinkled.muscle_wrinkles = unwrinkled.curve_wrinkles = false;
    aux_positions_.resize(nv);
    if (!RunJob(unwrinkled, &aux_positions_, nullptr, nullptr, &aux_context_)) return false;
    in.unwrinkled = aux_positions_;
  } else if (overlay == Overlay::kShrinkage) {
    // s is measured on X1 (docs/model.md §5, §7): the points of a frame without skin layers.
    aux_positions_.resize(nv);
    if (!RunJob(SkinLayers{false, false, false}, &aux_positions_, nullptr, nullptr, &aux_context_))
      return false;
    const RigCurveWrinkles& cw = r.curve_wrinkles();
    shrinkage_.assign(cw.probes.size(), 0.f);
    if (!cw.probes.empty()) {
      DirectionalShrinkageJob job;
      job.positions = aux_context_.points();
      job.probes = cw.probes;
      job.end = cw.probes.size();
      job.out_shrinkage = shrinkage_;
      if (!job.Run()) return false;
    }
    PointShrinkage(r.point_count(), cw.points, cw.offsets, shrinkage_, &point_shrinkage_);
    in.point_shrinkage = point_shrinkage_;
  }
  if (overlay == Overlay::kNone) {
    field_ = OverlayField{};
  } else if (!ComputeOverlayValues(overlay, in, &field_)) {
    return false;
  }
  overlay_ms_ = MillisecondsSince(start);
  return true;
}

bool Session::LoadFineMaps(const std::string& dir) {
  Diagnostics diag;
  const std::string closing = dir + ": the fine-scale maps were not loaded";
  if (!rig_) {
    diag.Error(dir, "no rig to draw fine-scale maps on");
    return AddMessages(diag, closing), false;
  }
  if (rig().vertex_uvs().size() != rig().vertex_count()) {
    diag.Error(rig_path_, "the rig's mesh has no texture coordinates to map fine-scale maps with");
    return AddMessages(diag, closing), false;
  }
  Gray16Image maps[2];
  for (int k = 0; k < 2; ++k) {
    const std::string path = dir + "/fine_height_" + std::to_string(k + 1) + ".png";
    if (!LoadGray16Png(path, path, "fine-scale height map", &maps[k], &diag))
      return AddMessages(diag, closing + " (make them with `mimetic texture RIG --out DIR`)"), false;
  }
  if (maps[0].width != maps[1].width || maps[0].height != maps[1].height) {
    diag.Error(dir, "fine_height_1.png is " + std::to_string(maps[0].width) + "x" +
                        std::to_string(maps[0].height) + " but fine_height_2.png " +
                        std::to_string(maps[1].width) + "x" + std::to_string(maps[1].height) +
                        "; the two fields' maps come from one `mimetic texture` run");
    return AddMessages(diag, closing), false;
  }
  fine_height_[0] = std::move(maps[0]);
  fine_height_[1] = std::move(maps[1]);
  fine_dir_ = dir;
  fine_loaded_ = true;
  return true;
}

bool Session::fine_active() const {
  return rig_ && fine_loaded_ && fine_enabled && rig().vertex_uvs().size() == rig().vertex_count();
}

std::vector<std::string> Session::RigLayerNames() const {
  std::vector<std::string> names;
  if (!rig_) return names;
  const Rig& r = rig();
  names.push_back("muscles");
  if (!r.jaw().empty()) names.push_back("jaw");
  if (r.layers().thickness) names.push_back("thickness");
  if (r.layers().muscle_wrinkles) names.push_back("muscle wrinkles");
  if (r.layers().curve_wrinkles) names.push_back("curve wrinkles");
  if (!r.fine_scale().empty()) names.push_back("fine scale");
  return names;
}

std::vector<std::string> Session::ActiveLayerNames() const {
  std::vector<std::string> names;
  if (!rig_) return names;
  const Rig& r = rig();
  if (muscles_enabled) names.push_back("muscles");
  if (!r.jaw().empty() && jaw_enabled && jaw > 0.f) names.push_back("jaw");
  if (r.layers().thickness && layers.thickness) names.push_back("thickness");
  if (r.layers().muscle_wrinkles && layers.muscle_wrinkles) names.push_back("muscle wrinkles");
  if (r.layers().curve_wrinkles && layers.curve_wrinkles) names.push_back("curve wrinkles");
  if (fine_active()) names.push_back("fine scale");
  return names;
}

}  // namespace mimetic::viewer
