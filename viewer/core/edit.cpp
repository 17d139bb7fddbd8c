// viewer/core/edit.cpp: see edit.h.
#include "viewer/core/edit.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include "expressions/runtime/clip.h"

namespace mimetic::viewer {
namespace {

std::string Num(float f) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  return std::string(buf, res.ptr);
}

bool NeedClip(const EditTarget& t, std::string* error) {
  if (*t.has_clip) return true;
  *error = "no clip is open for editing (load a .clip.json, or start a new clip)";
  return false;
}

// The keys' commands keep the clip's channels as they were before Apply; Revert puts them back.
class ClipKeysCommand : public Command {
 public:
  unsigned Touches() const override { return kEditClip; }
  bool Apply(const EditTarget& t, std::string* error) override {
    if (!NeedClip(t, error)) return false;
    std::vector<ClipChannelSpec> edited = t.clip->channels;
    if (!Edit(&edited, error)) return false;
    before_ = std::move(t.clip->channels);
    t.clip->channels = std::move(edited);
    return true;
  }
  void Revert(const EditTarget& t) override { t.clip->channels = before_; }

 protected:
  virtual bool Edit(std::vector<ClipChannelSpec>* channels, std::string* error) = 0;

  // The checked refs, sorted and without repeats.
  static bool CheckRefs(const std::vector<ClipChannelSpec>& channels, std::vector<KeyRef>* refs,
                        std::string* error) {
    if (refs->empty()) {
      *error = "no keys selected";
      return false;
    }
    std::sort(refs->begin(), refs->end());
    refs->erase(std::unique(refs->begin(), refs->end()), refs->end());
    for (const KeyRef& r : *refs)
      if (r.channel >= channels.size() || r.key >= channels[r.channel].keys.size()) {
        *error = "no key " + std::to_string(r.key) + " on channel " + std::to_string(r.channel);
        return false;
      }
    return true;
  }

  // Inserts `key` into `c`'s keys in time order; a key within the tolerance takes its value.
  static void InsertKey(ClipChannelSpec* c, const ClipKeySpec& key) {
    for (ClipKeySpec& k : c->keys)
      if (std::fabs(k.t - key.t) <= kKeyTimeTolerance) {
        k.v = key.v;
        k.interp = key.interp;
        k.tangent = key.tangent;
        return;
      }
    const auto at = std::upper_bound(c->keys.begin(), c->keys.end(), key.t,
                                     [](float t, const ClipKeySpec& k) { return t < k.t; });
    c->keys.insert(at, key);
  }

  static ClipChannelSpec* ChannelFor(std::vector<ClipChannelSpec>* channels, const ChannelId& id) {
    for (ClipChannelSpec& c : *channels)
      if (c.kind == id.kind && c.target == id.target) return &c;
    ClipChannelSpec c;
    c.kind = id.kind;
    c.target = id.target;
    channels->push_back(std::move(c));
    return &channels->back();
  }

 private:
  std::vector<ClipChannelSpec> before_;
};

class AddKey : public ClipKeysCommand {
 public:
  AddKey(ChannelId id, float t, float v, KeyInterp interp) : id_(std::move(id)), t_(t), v_(v), interp_(interp) {}
  std::string Describe() const override {
    return "key add " + ChannelIdText(id_) + " " + Num(t_) + " " + Num(v_);
  }

 protected:
  bool Edit(std::vector<ClipChannelSpec>* channels, std::string* error) override {
    if (id_.target.empty()) {
      *error = "the channel names no target";
      return false;
    }
    if (!std::isfinite(t_) || t_ < 0.f) {
      *error = "time " + Num(t_) + " s; expected a time >= 0";
      return false;
    }
    if (!(v_ >= 0.f && v_ <= 1.f)) {
      *error = "value " + Num(v_) + "; expected a value in [0, 1]";
      return false;
    }
    ClipKeySpec key;
    key.t = t_;
    key.v = v_;
    key.interp = interp_;
    InsertKey(ChannelFor(channels, id_), key);
    return true;
  }

 private:
  ChannelId id_;
  float t_, v_;
  KeyInterp interp_;
};

class DeleteKeys : public ClipKeysCommand {
 public:
  explicit DeleteKeys(std::vector<KeyRef> keys) : keys_(std::move(keys)) {}
  std::string Describe() const override { return "delete " + std::to_string(keys_.size()) + " key(s)"; }

 protected:
  bool Edit(std::vector<ClipChannelSpec>* channels, std::string* error) override {
    if (!CheckRefs(*channels, &keys_, error)) return false;
    for (auto r = keys_.rbegin(); r != keys_.rend(); ++r) {
      auto& keys = (*channels)[r->channel].keys;
      keys.erase(keys.begin() + r->key);
    }
    channels->erase(std::remove_if(channels->begin(), channels->end(),
                                   [](const ClipChannelSpec& c) { return c.keys.empty(); }),
                    channels->end());
    return true;
  }

 private:
  std::vector<KeyRef> keys_;
};

class MoveKeys : public ClipKeysCommand {
 public:
  MoveKeys(std::vector<KeyRef> keys, float dt, float dv) : keys_(std::move(keys)), dt_(dt), dv_(dv) {}
  MoveKeys(KeyRef key, float t, float v) : keys_{key}, absolute_(true), t_(t), v_(v) {}
  std::string Describe() const override {
    if (absolute_) return "key move to " + Num(t_) + " s, " + Num(v_);
    return "move " + std::to_string(keys_.size()) + " key(s) by " + Num(dt_) + " s, " + Num(dv_);
  }

 protected:
  bool Edit(std::vector<ClipChannelSpec>* channels, std::string* error) override {
    if (!CheckRefs(*channels, &keys_, error)) return false;
    if (!std::isfinite(dt_) || !std::isfinite(dv_) || !std::isfinite(t_) || !std::isfinite(v_)) {
      *error = "the move is not finite";
      return false;
    }
    for (const KeyRef& r : keys_) {
      ClipKeySpec& k = (*channels)[r.channel].keys[r.key];
      k.t = absolute_ ? t_ : k.t + dt_;
      k.v = std::clamp(absolute_ ? v_ : k.v + dv_, 0.f, 1.f);
      if (k.t < 0.f) {
        *error = "a key would move to " + Num(k.t) + " s; expected a time >= 0";
        return false;
      }
    }
    for (const KeyRef& r : keys_) {
      const auto& keys = (*channels)[r.channel].keys;
      for (size_t j = 0; j < keys.size(); ++j) {
        if (j == r.key) continue;
        const bool ordered = j < r.key ? keys[j].t < keys[r.key].t : keys[j].t > keys[r.key].t;
        if (!ordered || std::fabs(keys[j].t - keys[r.key].t) <= kKeyTimeTolerance) {
          *error = "channel " + std::to_string(r.channel) + "'s key would move to " +
                   Num(keys[r.key].t) + " s, reaching its key at " + Num(keys[j].t) +
                   " s; expected the keys to stay in time order";
          return false;
        }
      }
    }
    return true;
  }

 private:
  std::vector<KeyRef> keys_;
  float dt_ = 0.f, dv_ = 0.f;
  bool absolute_ = false;
  float t_ = 0.f, v_ = 0.f;
};

class SetInterp : public ClipKeysCommand {
 public:
  SetInterp(std::vector<KeyRef> keys, KeyInterp interp) : keys_(std::move(keys)), interp_(interp) {}
  std::string Describe() const override {
    return std::string("interp ") + InterpName(interp_) + " on " + std::to_string(keys_.size()) + " key(s)";
  }

 protected:
  bool Edit(std::vector<ClipChannelSpec>* channels, std::string* error) override {
    if (!CheckRefs(*channels, &keys_, error)) return false;
    for (const KeyRef& r : keys_) (*channels)[r.channel].keys[r.key].interp = interp_;
    return true;
  }

 private:
  std::vector<KeyRef> keys_;
  KeyInterp interp_;
};

class PasteKeys : public ClipKeysCommand {
 public:
  PasteKeys(KeyClipboard clipboard, float t) : clipboard_(std::move(clipboard)), t_(t) {}
  std::string Describe() const override { return "paste at " + Num(t_) + " s"; }

 protected:
  bool Edit(std::vector<ClipChannelSpec>* channels, std::string* error) override {
    if (clipboard_.empty()) {
      *error = "nothing was copied";
      return false;
    }
    if (!std::isfinite(t_) || t_ < 0.f) {
      *error = "time " + Num(t_) + " s; expected a time >= 0";
      return false;
    }
    for (const KeyClipboard::Channel& c : clipboard_.channels) {
      ClipChannelSpec* channel = ChannelFor(channels, c.id);
      for (ClipKeySpec k : c.keys) {
        k.t += t_;
        InsertKey(channel, k);
      }
    }
    return true;
  }

 private:
  KeyClipboard clipboard_;
  float t_;
};

class SetDuration : public Command {
 public:
  explicit SetDuration(float d) : duration_(d) {}
  std::string Describe() const override { return "duration " + Num(duration_); }
  unsigned Touches() const override { return kEditClip; }
  bool Apply(const EditTarget& t, std::string* error) override {
    if (!NeedClip(t, error)) return false;
    before_ = t.clip->duration;
    t.clip->duration = duration_ < 0.f ? -1.f : duration_;
    return true;
  }
  void Revert(const EditTarget& t) override { t.clip->duration = before_; }

 private:
  float duration_, before_ = -1.f;
};

class SetPose : public Command {
 public:
  // `muscles` empty: the whole pose from `values` and `jaw`; `jaw_only`: the jaw.
  SetPose(std::vector<uint32_t> muscles, std::vector<float> values, float jaw, bool whole, bool jaw_only)
      : muscles_(std::move(muscles)), values_(std::move(values)), jaw_(jaw), whole_(whole), jaw_only_(jaw_only) {}
  std::string Describe() const override {
    if (jaw_only_) return "set jaw " + Num(jaw_);
    if (whole_) return "set pose";
    return "set " + std::to_string(muscles_.size()) + " muscle(s) to " + Num(values_.empty() ? 0.f : values_[0]);
  }
  unsigned Touches() const override { return kEditPose; }
  bool Apply(const EditTarget& t, std::string* error) override {
    std::vector<float>& a = *t.activations;
    if (whole_ && values_.size() != a.size()) {
      *error = "the pose has " + std::to_string(values_.size()) + " activations; the rig has " +
               std::to_string(a.size()) + " muscles";
      return false;
    }
    for (uint32_t m : muscles_)
      if (m >= a.size()) {
        *error = "no muscle " + std::to_string(m);
        return false;
      }
    for (float v : values_)
      if (!(v >= 0.f && v <= 1.f)) {
        *error = "activation " + Num(v) + "; expected a value in [0, 1]";
        return false;
      }
    if ((jaw_only_ || whole_) && !(jaw_ >= 0.f && jaw_ <= 1.f)) {
      *error = "jaw " + Num(jaw_) + "; expected a value in [0, 1]";
      return false;
    }
    before_ = a;
    before_jaw_ = *t.jaw;
    if (whole_) a = values_;
    else
      for (uint32_t m : muscles_) a[m] = values_[0];
    if (whole_ || jaw_only_) *t.jaw = jaw_;
    return true;
  }
  void Revert(const EditTarget& t) override {
    *t.activations = before_;
    *t.jaw = before_jaw_;
  }

 private:
  std::vector<uint32_t> muscles_;
  std::vector<float> values_;
  float jaw_;
  bool whole_, jaw_only_;
  std::vector<float> before_;
  float before_jaw_ = 0.f;
};

int FindExpression(const std::vector<Expression>& library, const std::string& name) {
  for (size_t i = 0; i < library.size(); ++i)
    if (library[i].name == name) return int(i);
  return -1;
}

class SaveExpression : public Command {
 public:
  SaveExpression(std::string name, bool overwrite) : name_(std::move(name)), overwrite_(overwrite) {}
  std::string Describe() const override {
    return std::string(overwrite_ ? "expr overwrite " : "expr save ") + name_;
  }
  unsigned Touches() const override { return kEditLibrary; }
  bool Apply(const EditTarget& t, std::string* error) override {
    if (name_.empty()) {
      *error = "the expression's name is empty";
      return false;
    }
    const int at = FindExpression(*t.library, name_);
    if (!overwrite_ && at >= 0) {
      *error = "the library already has an expression '" + name_ + "' (overwrite it instead)";
      return false;
    }
    if (overwrite_ && at < 0) {
      *error = "the library has no expression '" + name_ + "'";
      return false;
    }
    Expression e = PoseExpression(name_, *t.muscle_names, *t.activations, *t.jaw);
    if (overwrite_) {
      index_ = size_t(at);
      before_ = (*t.library)[index_].activations;
      (*t.library)[index_].activations = std::move(e.activations);
    } else {
      t.library->push_back(std::move(e));
    }
    return true;
  }
  void Revert(const EditTarget& t) override {
    if (overwrite_) (*t.library)[index_].activations = before_;
    else t.library->pop_back();
  }

 private:
  std::string name_;
  bool overwrite_;
  size_t index_ = 0;
  std::vector<std::pair<std::string, float>> before_;
};

class RenameExpression : public Command {
 public:
  RenameExpression(std::string from, std::string to) : from_(std::move(from)), to_(std::move(to)) {}
  std::string Describe() const override { return "expr rename " + from_ + " " + to_; }
  unsigned Touches() const override { return kEditLibrary | kEditClip; }
  bool Apply(const EditTarget& t, std::string* error) override {
    const int at = FindExpression(*t.library, from_);
    if (at < 0) {
      *error = "the library has no expression '" + from_ + "'";
      return false;
    }
    if (to_.empty()) {
      *error = "the new name is empty";
      return false;
    }
    if (FindExpression(*t.library, to_) >= 0) {
      *error = "the library already has an expression '" + to_ + "'";
      return false;
    }
    index_ = size_t(at);
    (*t.library)[index_].name = to_;
    channels_.clear();
    if (*t.has_clip)
      for (size_t c = 0; c < t.clip->channels.size(); ++c) {
        ClipChannelSpec& ch = t.clip->channels[c];
        if (ch.kind == ClipChannelKind::kExpression && ch.target == from_) {
          ch.target = to_;
          channels_.push_back(c);
        }
      }
    return true;
  }
  void Revert(const EditTarget& t) override {
    (*t.library)[index_].name = from_;
    for (size_t c : channels_) t.clip->channels[c].target = from_;
  }

 private:
  std::string from_, to_;
  size_t index_ = 0;
  std::vector<size_t> channels_;
};

class DeleteExpression : public Command {
 public:
  explicit DeleteExpression(std::string name) : name_(std::move(name)) {}
  std::string Describe() const override { return "expr delete " + name_; }
  unsigned Touches() const override { return kEditLibrary; }
  bool Apply(const EditTarget& t, std::string* error) override {
    const int at = FindExpression(*t.library, name_);
    if (at < 0) {
      *error = "the library has no expression '" + name_ + "'";
      return false;
    }
    if (*t.has_clip)
      for (size_t c = 0; c < t.clip->channels.size(); ++c)
        if (t.clip->channels[c].kind == ClipChannelKind::kExpression &&
            t.clip->channels[c].target == name_) {
          *error = "the clip's channels[" + std::to_string(c) + "] animates '" + name_ +
                   "'; delete that channel's keys first";
          return false;
        }
    index_ = size_t(at);
    removed_ = std::move((*t.library)[index_]);
    t.library->erase(t.library->begin() + at);
    return true;
  }
  void Revert(const EditTarget& t) override {
    t.library->insert(t.library->begin() + std::ptrdiff_t(index_), removed_);
  }

 private:
  std::string name_;
  size_t index_ = 0;
  Expression removed_;
};

}  // namespace

bool ParseChannelId(const std::string& text, ChannelId* out, std::string* error) {
  if (text == kJawInputName) {
    *out = {ClipChannelKind::kMuscle, kJawInputName};
    return true;
  }
  for (const auto& [prefix, kind] : {std::pair<std::string, ClipChannelKind>{"muscle:", ClipChannelKind::kMuscle},
                                     {"expression:", ClipChannelKind::kExpression}}) {
    if (text.compare(0, prefix.size(), prefix) == 0 && text.size() > prefix.size()) {
      *out = {kind, text.substr(prefix.size())};
      return true;
    }
  }
  *error = "'" + text + "' is not a channel; expected muscle:NAME, expression:NAME or jaw";
  return false;
}

std::string ChannelIdText(const ChannelId& id) {
  if (id.kind == ClipChannelKind::kMuscle && id.target == kJawInputName) return kJawInputName;
  return (id.kind == ClipChannelKind::kExpression ? "expression:" : "muscle:") + id.target;
}

int FindChannel(const ClipSpec& clip, const ChannelId& id) {
  for (size_t c = 0; c < clip.channels.size(); ++c)
    if (clip.channels[c].kind == id.kind && clip.channels[c].target == id.target) return int(c);
  return -1;
}

int FindKey(const ClipSpec& clip, size_t c, float t) {
  if (c >= clip.channels.size()) return -1;
  const auto& keys = clip.channels[c].keys;
  for (size_t k = 0; k < keys.size(); ++k)
    if (std::fabs(keys[k].t - t) <= kKeyTimeTolerance) return int(k);
  return -1;
}

bool ParseInterp(const std::string& text, KeyInterp* out) {
  for (KeyInterp i : {KeyInterp::kStep, KeyInterp::kLinear, KeyInterp::kCubic})
    if (text == InterpName(i)) return *out = i, true;
  return false;
}

const char* InterpName(KeyInterp interp) {
  switch (interp) {
    case KeyInterp::kStep: return "step";
    case KeyInterp::kLinear: return "linear";
    case KeyInterp::kCubic: return "cubic";
  }
  return "linear";
}

KeyClipboard CopyKeys(const ClipSpec& clip, const std::vector<KeyRef>& selection) {
  KeyClipboard out;
  std::vector<KeyRef> refs = selection;
  std::sort(refs.begin(), refs.end());
  refs.erase(std::unique(refs.begin(), refs.end()), refs.end());
  float earliest = INFINITY;
  for (const KeyRef& r : refs) {
    if (r.channel >= clip.channels.size() || r.key >= clip.channels[r.channel].keys.size()) continue;
    const ClipChannelSpec& c = clip.channels[r.channel];
    if (out.channels.empty() || !(out.channels.back().id == ChannelId{c.kind, c.target}))
      out.channels.push_back({{c.kind, c.target}, {}});
    out.channels.back().keys.push_back(c.keys[r.key]);
    earliest = std::min(earliest, c.keys[r.key].t);
  }
  for (KeyClipboard::Channel& c : out.channels)
    for (ClipKeySpec& k : c.keys) k.t -= earliest;
  return out;
}

CommandPtr MakeSetMuscles(std::vector<uint32_t> muscles, float value) {
  return std::make_unique<SetPose>(std::move(muscles), std::vector<float>{value}, 0.f, false, false);
}
CommandPtr MakeSetJaw(float value) {
  return std::make_unique<SetPose>(std::vector<uint32_t>{}, std::vector<float>{}, value, false, true);
}
CommandPtr MakeSetPose(std::vector<float> activations, float jaw) {
  return std::make_unique<SetPose>(std::vector<uint32_t>{}, std::move(activations), jaw, true, false);
}
CommandPtr MakeAddKey(ChannelId id, float t, float v, KeyInterp interp) {
  return std::make_unique<AddKey>(std::move(id), t, v, interp);
}
CommandPtr MakeDeleteKeys(std::vector<KeyRef> keys) { return std::make_unique<DeleteKeys>(std::move(keys)); }
CommandPtr MakeMoveKeys(std::vector<KeyRef> keys, float dt, float dv) {
  return std::make_unique<MoveKeys>(std::move(keys), dt, dv);
}
CommandPtr MakeSetKey(KeyRef key, float t, float v) { return std::make_unique<MoveKeys>(key, t, v); }
CommandPtr MakeSetInterp(std::vector<KeyRef> keys, KeyInterp interp) {
  return std::make_unique<SetInterp>(std::move(keys), interp);
}
CommandPtr MakePasteKeys(KeyClipboard clipboard, float t) {
  return std::make_unique<PasteKeys>(std::move(clipboard), t);
}
CommandPtr MakeSetDuration(float duration) { return std::make_unique<SetDuration>(duration); }

Expression PoseExpression(const std::string& name, const std::vector<std::string>& muscle_names,
                          const std::vector<float>& activations, float jaw) {
  Expression e;
  e.name = name;
  for (size_t m = 0; m < activations.size() && m < muscle_names.size(); ++m)
    if (activations[m] != 0.f) e.activations.push_back({muscle_names[m], activations[m]});
  if (jaw != 0.f) e.activations.push_back({kJawInputName, jaw});
  // By name: the library reader gives an expression's activations in name order, so a saved
  // library reads back exactly as it was.
  std::sort(e.activations.begin(), e.activations.end());
  return e;
}

CommandPtr MakeSaveExpression(std::string name) {
  return std::make_unique<SaveExpression>(std::move(name), false);
}
CommandPtr MakeOverwriteExpression(std::string name) {
  return std::make_unique<SaveExpression>(std::move(name), true);
}
CommandPtr MakeRenameExpression(std::string from, std::string to) {
  return std::make_unique<RenameExpression>(std::move(from), std::move(to));
}
CommandPtr MakeDeleteExpression(std::string name) {
  return std::make_unique<DeleteExpression>(std::move(name));
}

bool EditHistory::Do(CommandPtr command, const EditTarget& t, const Validator& validate,
                     std::string* error) {
  if (!command->Apply(t, error)) return false;
  const unsigned touched = command->Touches();
  if (validate && !validate(touched, error)) {
    command->Revert(t);
    validate(touched, nullptr);  // back to the state before (rebuilds what the check built)
    return false;
  }
  Entry e;
  e.command = std::move(command);
  for (int s = 0; s < kSlots; ++s) {
    e.before[s] = version_[s];
    if (touched & (1u << s)) version_[s] = ++next_version_;
    e.after[s] = version_[s];
  }
  undo_.push_back(std::move(e));
  redo_.clear();
  return true;
}

bool EditHistory::Undo(const EditTarget& t, unsigned* touched) {
  if (undo_.empty()) return false;
  Entry e = std::move(undo_.back());
  undo_.pop_back();
  e.command->Revert(t);
  for (int s = 0; s < kSlots; ++s) version_[s] = e.before[s];
  if (touched) *touched = e.command->Touches();
  redo_.push_back(std::move(e));
  return true;
}

bool EditHistory::Redo(const EditTarget& t, const Validator& validate, unsigned* touched,
                       std::string* error) {
  if (redo_.empty()) return false;
  Entry e = std::move(redo_.back());
  redo_.pop_back();
  std::string why;
  bool ok = e.command->Apply(t, &why);
  if (ok && validate && !validate(e.command->Touches(), &why)) {
    e.command->Revert(t);
    validate(e.command->Touches(), nullptr);
    ok = false;
  }
  if (!ok) {
    if (error) *error = why;
    redo_.clear();
    return false;
  }
  for (int s = 0; s < kSlots; ++s) version_[s] = e.after[s];
  if (touched) *touched = e.command->Touches();
  undo_.push_back(std::move(e));
  return true;
}

void EditHistory::Clear() {
  undo_.clear();
  redo_.clear();
}

}  // namespace mimetic::viewer
