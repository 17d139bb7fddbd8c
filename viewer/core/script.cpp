// viewer/core/script.cpp: see script.h.
#include "viewer/core/script.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "core/diagnostics.h"
#include "core/file_util.h"
#include "viewer/core/rig_edit.h"

namespace mimetic::viewer {
namespace {

bool Number(const std::string& word, const char* what, float* out, std::string* error) {
  errno = 0;
  char* end = nullptr;
  const float v = std::strtof(word.c_str(), &end);
  if (word.empty() || end != word.c_str() + word.size() || errno == ERANGE || !std::isfinite(v)) {
    *error = "'" + word + "' is not a number; expected " + what;
    return false;
  }
  *out = v;
  return true;
}

bool Arity(const std::vector<std::string>& w, size_t lo, size_t hi, const char* usage,
           std::string* error) {
  if (w.size() >= lo && w.size() <= hi) return true;
  *error = std::string("expected: ") + usage;
  return false;
}

// The key of CHANNEL at TIME (w[i], w[i + 1]).
bool Key(const Session& s, const std::vector<std::string>& w, size_t i, KeyRef* out,
         std::string* error) {
  ChannelId id;
  float t = 0.f;
  if (!ParseChannelId(w[i], &id, error) || !Number(w[i + 1], "a time in seconds", &t, error))
    return false;
  if (!s.has_clip_spec()) {
    *error = "no clip is open for editing (load-clip PATH or clip new PATH)";
    return false;
  }
  const int c = FindChannel(s.clip_spec(), id);
  if (c < 0) {
    *error = "the clip has no channel " + w[i];
    return false;
  }
  const int k = FindKey(s.clip_spec(), size_t(c), t);
  if (k < 0) {
    *error = "channel " + w[i] + " has no key at " + w[i + 1] + " s";
    return false;
  }
  *out = {uint32_t(c), uint32_t(k)};
  return true;
}

bool Interp(const std::string& word, KeyInterp* out, std::string* error) {
  if (ParseInterp(word, out)) return true;
  *error = "'" + word + "' is not an interpolation; expected step, linear or cubic";
  return false;
}

// The session's messages added since `before`, as one line (a failed load or save).
std::string NewMessages(const Session& s, size_t before, const std::string& fallback) {
  std::string out;
  for (size_t i = before; i < s.messages().size(); ++i)
    if (s.messages()[i].error) out += (out.empty() ? "" : "; ") + s.messages()[i].text;
  return out.empty() ? fallback : out;
}

}  // namespace

bool SplitScriptLine(const std::string& line, std::vector<std::string>* words, std::string* error) {
  words->clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i >= line.size() || line[i] == '#') break;
    std::string word;
    if (line[i] == '"') {
      ++i;
      bool closed = false;
      while (i < line.size()) {
        if (line[i] == '\\' && i + 1 < line.size()) {
          word += line[i + 1];
          i += 2;
        } else if (line[i] == '"') {
          closed = true;
          ++i;
          break;
        } else {
          word += line[i++];
        }
      }
      if (!closed) {
        *error = "a quote is not closed";
        return false;
      }
    } else {
      while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) word += line[i++];
    }
    words->push_back(std::move(word));
  }
  return true;
}

bool RunScriptWords(const std::vector<std::string>& w, Session* s, const ScriptHooks& hooks,
                    float* time, std::string* error) {
  if (w.empty()) return true;
  const std::string& op = w[0];
  const std::string sub = w.size() > 1 ? w[1] : "";
  const size_t before = s->messages().size();
  float a = 0.f, b = 0.f;
  KeyRef key;
  KeyInterp interp = KeyInterp::kLinear;
  if (op == "set") {
    if (!Arity(w, 3, 3, "set NAME VALUE", error) || !Number(w[2], "a value in [0, 1]", &a, error))
      return false;
    return s->SetByName(w[1], a, error);
  }
  if (op == "key" && sub == "add") {
    if (!Arity(w, 5, 6, "key add CHANNEL TIME VALUE [step|linear|cubic]", error)) return false;
    ChannelId id;
    if (!ParseChannelId(w[2], &id, error) || !Number(w[3], "a time in seconds", &a, error) ||
        !Number(w[4], "a value in [0, 1]", &b, error) || (w.size() == 6 && !Interp(w[5], &interp, error)))
      return false;
    if (!s->has_clip_spec()) {
      *error = "no clip is open for editing (load-clip PATH or clip new PATH)";
      return false;
    }
    return s->Edit(MakeAddKey(id, a, b, interp), error);
  }
  if (op == "key" && sub == "delete") {
    if (!Arity(w, 4, 4, "key delete CHANNEL TIME", error) || !Key(*s, w, 2, &key, error)) return false;
    return s->Edit(MakeDeleteKeys({key}), error);
  }
  if (op == "key" && sub == "move") {
    if (!Arity(w, 6, 6, "key move CHANNEL TIME NEW_TIME NEW_VALUE", error) || !Key(*s, w, 2, &key, error) ||
        !Number(w[4], "a time in seconds", &a, error) || !Number(w[5], "a value in [0, 1]", &b, error))
      return false;
    return s->Edit(MakeSetKey(key, a, b), error);
  }
  if (op == "key") {
    *error = "'key " + sub + "': expected key add, key delete or key move";
    return false;
  }
  if (op == "interp") {
    if (!Arity(w, 4, 4, "interp CHANNEL TIME step|linear|cubic", error) || !Key(*s, w, 1, &key, error) ||
        !Interp(w[3], &interp, error))
      return false;
    return s->Edit(MakeSetInterp({key}, interp), error);
  }
  if (op == "select") {
    if (w.size() == 2 && sub == "none") {
      s->selection.clear();
      return true;
    }
    if (!Arity(w, 3, 3, "select CHANNEL TIME | select none", error) || !Key(*s, w, 1, &key, error))
      return false;
    s->selection.push_back(key);
    return true;
  }
  if (op == "selection") {
    if (sub == "move") {
      if (!Arity(w, 4, 4, "selection move DT DV", error) || !Number(w[2], "seconds", &a, error) ||
          !Number(w[3], "a value change", &b, error))
        return false;
      return s->Edit(MakeMoveKeys(s->selection, a, b), error);
    }
    if (sub == "delete") {
      if (!Arity(w, 2, 2, "selection delete", error)) return false;
      if (!s->Edit(MakeDeleteKeys(s->selection), error)) return false;
      s->selection.clear();
      return true;
    }
    if (sub == "interp") {
      if (!Arity(w, 3, 3, "selection interp step|linear|cubic", error) || !Interp(w[2], &interp, error))
        return false;
      return s->Edit(MakeSetInterp(s->selection, interp), error);
    }
    *error = "expected selection move DT DV, selection delete or selection interp MODE";
    return false;
  }
  if (op == "copy") {
    if (!Arity(w, 1, 1, "copy", error)) return false;
    if (s->selection.empty()) {
      *error = "no keys selected (select CHANNEL TIME)";
      return false;
    }
    s->clipboard = CopyKeys(s->clip_spec(), s->selection);
    return true;
  }
  if (op == "paste") {
    if (!Arity(w, 2, 2, "paste TIME", error) || !Number(w[1], "a time in seconds", &a, error)) return false;
    if (!s->Edit(MakePasteKeys(s->clipboard, a), error)) return false;
    s->selection.clear();
    return true;
  }
  if (op == "duration") {
    if (!Arity(w, 2, 2, "duration SECONDS|none", error)) return false;
    if (sub == "none") a = -1.f;
    else if (!Number(sub, "seconds or none", &a, error)) return false;
    return s->Edit(MakeSetDuration(a), error);
  }
  if (op == "time") {
    if (!Arity(w, 2, 2, "time T|none", error)) return false;
    if (sub == "none") {
      *time = -1.f;
      if (hooks.playhead) hooks.playhead(-1.f);
      return true;
    }
    if (!Number(sub, "a time in seconds or none", &a, error)) return false;
    if (!s->has_clip()) {
      *error = "no clip to sample";
      return false;
    }
    *time = a;
    if (hooks.playhead) hooks.playhead(a);
    return s->SampleClip(a);
  }
  if (op == "expr") {
    if (sub == "rename") {
      if (!Arity(w, 4, 4, "expr rename OLD NEW", error)) return false;
      return s->Edit(MakeRenameExpression(w[2], w[3]), error);
    }
    if (!Arity(w, 3, 3, "expr save|overwrite|delete|apply NAME", error)) return false;
    if (sub == "save") return s->Edit(MakeSaveExpression(w[2]), error);
    if (sub == "overwrite") return s->Edit(MakeOverwriteExpression(w[2]), error);
    if (sub == "delete") return s->Edit(MakeDeleteExpression(w[2]), error);
    if (sub == "apply") {
      size_t e = 0;
      while (e < s->library().size() && s->library()[e].name != w[2]) ++e;
      if (e == s->library().size()) {
        *error = "the library has no expression '" + w[2] + "'";
        return false;
      }
      // The pose the blend gives with this expression alone, as one command.
      const std::vector<float> weights = s->expression_weights, old = s->activations;
      const float old_jaw = s->jaw;
      std::fill(s->expression_weights.begin(), s->expression_weights.end(), 0.f);
      s->expression_weights[e] = 1.f;
      s->ApplyExpressionBlend();
      std::vector<float> pose = s->activations;
      const float pose_jaw = s->jaw;
      s->activations = old;
      s->jaw = old_jaw;
      s->expression_weights = weights;
      return s->Edit(MakeSetPose(std::move(pose), pose_jaw), error);
    }
    *error = "'expr " + sub + "': expected expr save, overwrite, rename, delete or apply";
    return false;
  }
  if (op == "undo" || op == "redo") {
    if (!Arity(w, 1, 1, op == "undo" ? "undo" : "redo", error)) return false;
    if (op == "undo" ? s->Undo() : s->Redo(error)) return true;
    if (error->empty()) *error = "nothing to " + op;
    return false;
  }
  if (op == "clip" && sub == "new") {
    if (!Arity(w, 3, 3, "clip new PATH", error)) return false;
    if (s->NewClip(w[2])) return true;
    *error = NewMessages(*s, before, "the clip was not made");
    return false;
  }
  if (op == "load-clip" || op == "load-library") {
    if (!Arity(w, 2, 2, op == "load-clip" ? "load-clip PATH" : "load-library PATH", error)) return false;
    if (op == "load-clip" ? s->LoadClipFile(sub) : s->LoadLibraryFile(sub)) return true;
    *error = NewMessages(*s, before, sub + ": not loaded");
    return false;
  }
  if (op == "save-clip" || op == "save-library") {
    if (!Arity(w, 1, 2, op == "save-clip" ? "save-clip [PATH]" : "save-library [PATH]", error))
      return false;
    return op == "save-clip" ? s->SaveClipFile(sub, error) : s->SaveLibraryFile(sub, error);
  }
  if (op == "autosave") {
    if (!Arity(w, 1, 1, "autosave", error)) return false;
    if (s->Autosave()) return true;
    *error = NewMessages(*s, before, "the autosave failed");
    return false;
  }
  if (op == "recover") {
    if (!Arity(w, 1, 1, "recover", error)) return false;
    if (s->RecoverAutosaves() > 0) return true;
    *error = NewMessages(*s, before, "no autosave to recover");
    return false;
  }
  if (op == "muscle" || op == "curve") {
    if (!Arity(w, 4, 7, op == "muscle" ? "muscle NAME PARAM VALUE..." : "curve NAME PARAM VALUE...",
               error))
      return false;
    if (!s->rig_spec()) {
      *error = op + " " + sub + ": no editable rig is loaded (a .rig.json, not a compiled .mrig)";
      return false;
    }
    const std::vector<std::string> args(w.begin() + 3, w.end());
    CommandPtr command = op == "muscle" ? MakeMuscleEdit(*s->rig_spec(), sub, w[2], args, error)
                                        : MakeCurveEdit(*s->rig_spec(), sub, w[2], args, error);
    return command && s->Edit(std::move(command), error);
  }
  if (op == "direction") {
    if (!Arity(w, 4, 7, "direction FIELD VERTEX DX DY DZ MAG | direction FIELD VERTEX delete", error))
      return false;
    if (!s->rig_spec()) {
      *error = "direction: no editable rig is loaded (a .rig.json, not a compiled .mrig)";
      return false;
    }
    errno = 0;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(w[2].c_str(), &end, 10);
    if (w[2].empty() || w[2][0] == '-' || end != w[2].c_str() + w[2].size() || errno == ERANGE ||
        v > 0xffffffffull) {
      *error = "direction " + sub + ": vertex: '" + w[2] + "' is not a vertex number";
      return false;
    }
    const std::vector<std::string> args(w.begin() + 3, w.end());
    CommandPtr command =
        MakeDirectionEdit(*s->rig_spec(), s->mesh_vertex_count(), sub, uint32_t(v), args, error);
    return command && s->Edit(std::move(command), error);
  }
  if (op == "save-rig") {
    if (!Arity(w, 1, 2, "save-rig [PATH]", error)) return false;
    return s->SaveRigFile(sub, error);
  }
  if (op == "wait") {
    if (!Arity(w, 1, 1, "wait", error)) return false;
    if (s->WaitRigRebuild()) return true;
    *error = NewMessages(*s, before, "the edited rig did not build");
    return false;
  }
  if (op == "screenshot") {
    if (!Arity(w, 2, 2, "screenshot PATH", error)) return false;
    if (s->rig_stale()) s->WaitRigRebuild();  // running, or done and not yet taken
    if (!hooks.screenshot) {
      *error = "screenshot: no renderer here";
      return false;
    }
    return hooks.screenshot(sub, error);
  }
  *error = "unknown command '" + op + "' (docs/viewer.md \"Scripts\")";
  return false;
}

bool RunScript(const std::string& text, const std::string& file, Session* s,
               const ScriptHooks& hooks, std::string* error) {
  float time = -1.f;
  size_t line_no = 0, start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    ++line_no;
    std::vector<std::string> words;
    std::string why;
    const size_t before = s->messages().size();
    const uint64_t requested = s->rig_requested();
    bool ok = SplitScriptLine(line, &words, &why) && RunScriptWords(words, s, hooks, &time, &why);
    // A rig edit's rebuild finishes before the next line (the line fails when it does not build).
    // Asked by generation, not by rig_rebuilding(): a build refused at once may be over, and
    // its result not yet taken, by the time the line returns.
    if (ok && s->rig_requested() != requested && !s->WaitRigRebuild()) {
      ok = false;
      why = NewMessages(*s, before, "the edited rig did not build");
    }
    // The pose follows the playhead after every edit, as the window does.
    if (ok && time >= 0.f && s->has_clip()) s->SampleClip(time);
    if (!ok) {
      *error = file + ":" + std::to_string(line_no) + ": " + (why.empty() ? "failed" : why);
      return false;
    }
    if (end == text.size()) break;
    start = end + 1;
  }
  return true;
}

bool RunScriptFile(const std::string& path, Session* s, const ScriptHooks& hooks,
                   std::string* error) {
  std::string text;
  Diagnostics diag;
  if (!ReadFile(path, &text, &diag, kMaxJsonFileBytes, "script")) {
    *error = diag.Format();
    while (!error->empty() && error->back() == '\n') error->pop_back();
    return false;
  }
  return RunScript(text, path, s, hooks, error);
}

}  // namespace mimetic::viewer
