// viewer/core/edit.h: the viewer's edits as command objects (docs/viewer.md "Authoring"), without
// any GL. Every change the panels or a --script make to what can be saved (the clip being
// edited, the expression library) or to the pose is a Command with Apply and Revert on an
// EditTarget; EditHistory keeps the undo and redo stacks and, per document, a version number
// and the version last saved (the dirty flag).
//
// A command that cannot apply (an unknown channel, a key that would pass its neighbour, a name
// already used) changes nothing and says why; the rules of the saved formats (CheckClipSpec,
// the clip building against the rig and library) are checked by the caller's validator after
// Apply (EditHistory::Do), which reverts the command when they fail.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "expressions/offline/clip_spec.h"
#include "io/expression_file.h"
#include "rig/offline/rig_spec.h"

namespace mimetic::viewer {

// What a command changes (bit flags of Command::Touches).
// kEditRig: the rig's spec (viewer/core/rig_edit.h), rebuilt off the UI thread after a change.
enum EditDoc : unsigned { kEditPose = 1u, kEditClip = 2u, kEditLibrary = 4u, kEditRig = 8u };

// The state the commands edit (owned by the Session).
struct EditTarget {
  bool* has_clip = nullptr;  // a clip spec is being edited (a .clip.json or a new clip)
  ClipSpec* clip = nullptr;
  std::vector<Expression>* library = nullptr;
  std::vector<float>* activations = nullptr;  // one per muscle, rig order
  float* jaw = nullptr;
  const std::vector<std::string>* muscle_names = nullptr;  // the rig's
  RigSpec* rig_spec = nullptr;  // the editable spec of the rig (nullptr: a compiled rig)
};

// A clip channel by what it animates: "muscle:NAME", "expression:NAME" or "jaw" (a muscle
// channel whose target is "jaw", expressions/runtime/clip.h kJawInputName).
struct ChannelId {
  ClipChannelKind kind = ClipChannelKind::kMuscle;
  std::string target;
  bool operator==(const ChannelId& o) const { return kind == o.kind && target == o.target; }
};
// Parses the text form; false with *error on anything else.
bool ParseChannelId(const std::string& text, ChannelId* out, std::string* error);
std::string ChannelIdText(const ChannelId& id);
// The index of the channel of `clip` with this id; -1 when there is none.
int FindChannel(const ClipSpec& clip, const ChannelId& id);
// The index of the key of channel `c` at time `t` (within kKeyTimeTolerance); -1 when none.
inline constexpr float kKeyTimeTolerance = 1e-4f;
int FindKey(const ClipSpec& clip, size_t c, float t);
// Interpolation names as in the clip file: "step", "linear", "cubic".
bool ParseInterp(const std::string& text, KeyInterp* out);
const char* InterpName(KeyInterp interp);

struct KeyRef {
  uint32_t channel = 0, key = 0;
  bool operator==(const KeyRef& o) const { return channel == o.channel && key == o.key; }
  bool operator<(const KeyRef& o) const {
    return channel != o.channel ? channel < o.channel : key < o.key;
  }
};

// Copied keys: per channel, the keys with times relative to the earliest copied key.
struct KeyClipboard {
  struct Channel {
    ChannelId id;
    std::vector<ClipKeySpec> keys;
  };
  std::vector<Channel> channels;
  bool empty() const { return channels.empty(); }
};
// The keys of `selection` (refs that do not exist are skipped).
KeyClipboard CopyKeys(const ClipSpec& clip, const std::vector<KeyRef>& selection);

class Command {
 public:
  virtual ~Command() = default;
  // One line saying what it does ("key add muscle:zygomatic 0.5 0.3"): the Edit menu's
  // "Undo ..." and the messages.
  virtual std::string Describe() const = 0;
  virtual unsigned Touches() const = 0;  // EditDoc bits
  // Makes the change; false with *error (and nothing changed) when it cannot.
  virtual bool Apply(const EditTarget& t, std::string* error) = 0;
  // Undoes the last successful Apply exactly (bit for bit).
  virtual void Revert(const EditTarget& t) = 0;
};
using CommandPtr = std::unique_ptr<Command>;

// --- The pose. ---------------------------------------------------------------------------
// Muscles `muscles` (rig indices) set to `value`.
CommandPtr MakeSetMuscles(std::vector<uint32_t> muscles, float value);
CommandPtr MakeSetJaw(float value);
// The whole pose (an expression blend, a slider drag: the panels keep the pose they started
// from and issue this once when the drag ends).
CommandPtr MakeSetPose(std::vector<float> activations, float jaw);

// --- Keys of the clip (the clip must be open for editing). --------------------------------
// A key at (t, v) on channel `id` (the channel is added at the end when the clip has none):
// a key already at t (kKeyTimeTolerance) takes the new value instead.
CommandPtr MakeAddKey(ChannelId id, float t, float v, KeyInterp interp = KeyInterp::kLinear);
// Deletes the keys; a channel left without keys is removed.
CommandPtr MakeDeleteKeys(std::vector<KeyRef> keys);
// Moves the keys by dt seconds and dv in value (values clamped to [0, 1]); refused when a key
// would go before 0 or reach a key of its channel that is not moved with it.
CommandPtr MakeMoveKeys(std::vector<KeyRef> keys, float dt, float dv);
// One key to (t, v) exactly (v clamped to [0, 1]), the same rules.
CommandPtr MakeSetKey(KeyRef key, float t, float v);
CommandPtr MakeSetInterp(std::vector<KeyRef> keys, KeyInterp interp);
// The clipboard's keys with its earliest key at `t` (channels added as needed; keys already
// at a pasted time are replaced).
CommandPtr MakePasteKeys(KeyClipboard clipboard, float t);
// The clip's duration (< 0: none, the last key's time).
CommandPtr MakeSetDuration(float duration);

// --- The expression library. -----------------------------------------------------------
// The pose as an expression: the muscles with a non-zero activation, and "jaw" when the jaw is
// open, by name (the order the library reader gives back).
Expression PoseExpression(const std::string& name, const std::vector<std::string>& muscle_names,
                          const std::vector<float>& activations, float jaw);
// Appends the current pose as expression `name` (refused when the name is empty or used).
CommandPtr MakeSaveExpression(std::string name);
// Replaces the activations of expression `name` with the current pose.
CommandPtr MakeOverwriteExpression(std::string name);
// Renames it, and the clip's expression channels that name it.
CommandPtr MakeRenameExpression(std::string from, std::string to);
// Deletes it (refused while a clip channel names it).
CommandPtr MakeDeleteExpression(std::string name);

// The undo and redo stacks, and the documents' versions.
class EditHistory {
 public:
  // Checks the documents after a command applied (the touched bits): false with *error to
  // have the command reverted.
  using Validator = std::function<bool(unsigned touched, std::string* error)>;

  // Applies `command`; on success pushes it on the undo stack and clears the redo stack. On
  // failure (Apply or the validator) nothing changed: false with *error.
  bool Do(CommandPtr command, const EditTarget& t, const Validator& validate, std::string* error);
  // Reverts the last command / applies the last undone one again; false when there is none
  // (or, for Redo, when it no longer applies: *error, and the redo stack is cleared).
  // `touched` gets the command's EditDoc bits.
  bool Undo(const EditTarget& t, unsigned* touched);
  bool Redo(const EditTarget& t, const Validator& validate, unsigned* touched, std::string* error);
  bool CanUndo() const { return !undo_.empty(); }
  bool CanRedo() const { return !redo_.empty(); }
  std::string UndoText() const { return undo_.empty() ? "" : undo_.back().command->Describe(); }
  std::string RedoText() const { return redo_.empty() ? "" : redo_.back().command->Describe(); }
  size_t undo_size() const { return undo_.size(); }

  // Dirty: the document's version differs from the version last saved (or loaded).
  bool dirty(EditDoc doc) const { return version_[Slot(doc)] != saved_[Slot(doc)]; }
  void MarkSaved(EditDoc doc) { saved_[Slot(doc)] = version_[Slot(doc)]; }
  uint64_t version(EditDoc doc) const { return version_[Slot(doc)]; }
  // A change made outside the commands (a recovered autosave): a new version, not saved.
  void MarkChanged(EditDoc doc) { version_[Slot(doc)] = ++next_version_; }
  // Forgets every command (a file was loaded: the commands' indices and names no longer
  // apply); each document stays as dirty as it was (MarkSaved the one loaded).
  void Clear();

 private:
  static constexpr int kSlots = 4;  // one per EditDoc bit
  struct Entry {
    CommandPtr command;
    uint64_t before[kSlots] = {0, 0, 0, 0}, after[kSlots] = {0, 0, 0, 0};
  };
  static int Slot(EditDoc doc) {
    return doc == kEditPose ? 0 : doc == kEditClip ? 1 : doc == kEditLibrary ? 2 : 3;
  }
  std::vector<Entry> undo_, redo_;
  uint64_t version_[kSlots] = {0, 0, 0, 0}, saved_[kSlots] = {0, 0, 0, 0};
  uint64_t next_version_ = 0;
};

}  // namespace mimetic::viewer
