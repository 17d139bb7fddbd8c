// viewer/core/script.h: mimetic-viewer --script FILE (docs/viewer.md "Scripts"): the edits the
// panels make, one command a line, replayed on a Session without any GL (a screenshot goes
// through a hook the app gives).
//
//   # a comment; blank lines are skipped; "quoted names" may hold spaces
//   set NAME VALUE                  key add CHANNEL TIME VALUE [step|linear|cubic]
//   key delete CHANNEL TIME         key move CHANNEL TIME NEW_TIME NEW_VALUE
//   interp CHANNEL TIME MODE        select CHANNEL TIME | select none
//   selection move DT DV | selection delete | selection interp MODE
//   copy                            paste TIME
//   duration SECONDS|none           time T
//   expr save|overwrite|delete NAME expr rename OLD NEW      expr apply NAME
//   undo                            redo
//   clip new PATH                   load-clip PATH           load-library PATH
//   save-clip [PATH]                save-library [PATH]
//   autosave                        recover                  screenshot PATH
//   muscle NAME PARAM VALUE...      curve NAME PARAM VALUE... (viewer/core/rig_edit.h)
//   direction FIELD VERTEX DX DY DZ MAG | direction FIELD VERTEX delete
//   save-rig [PATH]                 wait (a rig edit's rebuild; implicit after every line)
//
// CHANNEL: muscle:NAME, expression:NAME or jaw (edit.h ParseChannelId); a key is named by its
// channel and time (within edit.h kKeyTimeTolerance).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "viewer/core/session.h"

namespace mimetic::viewer {

struct ScriptHooks {
  // `screenshot PATH`: renders the session's current frame into PATH (false with *error).
  // Unset: the command is an error ("no renderer").
  std::function<bool(const std::string& path, std::string* error)> screenshot;
  // `time T` / `time none`: the playhead moved to T (< 0: the pose no longer follows the clip),
  // so that a window or screenshot shows it there. Unset: nothing else follows.
  std::function<void(float time)> playhead;
};

// Splits a line into words: whitespace-separated, "double quotes" group (with \" and \\), a #
// outside quotes starts a comment. False with *error on an unterminated quote.
bool SplitScriptLine(const std::string& line, std::vector<std::string>* words, std::string* error);

// Runs one line's words on `session` (`time` is the playhead `time T` set, < 0: none; kept
// between lines). False with *error (without the file and line).
bool RunScriptWords(const std::vector<std::string>& words, Session* session,
                    const ScriptHooks& hooks, float* time, std::string* error);

// Runs every line of `text` in order and stops at the first that fails: false with *error =
// "FILE:LINE: message". `file` names the script in the messages.
bool RunScript(const std::string& text, const std::string& file, Session* session,
               const ScriptHooks& hooks, std::string* error);
// Reads FILE and runs it ("FILE: cannot read ..." when it cannot be read).
bool RunScriptFile(const std::string& path, Session* session, const ScriptHooks& hooks,
                   std::string* error);

}  // namespace mimetic::viewer
