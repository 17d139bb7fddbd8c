// tools/cli.h: a small argument parser shared by the subcommands.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace mimetic::tools {

// Parses `--flag`, `--key VALUE`, `--key=VALUE` and positionals. Options in `repeatable`
// collect every value. Unknown options and missing values are reported in `error`.
struct ParsedArgs {
  std::vector<std::string> positional;
  std::map<std::string, std::vector<std::string>> values;  // key without dashes
  std::set<std::string> flags;
  std::string error;  // empty when parsing succeeded
  bool help = false;

  bool Has(const std::string& key) const { return values.count(key) || flags.count(key); }
  std::string Get(const std::string& key, const std::string& fallback = "") const;
};

ParsedArgs ParseArgs(const std::vector<std::string>& args, const std::set<std::string>& valued,
                     const std::set<std::string>& flags);

// Parses a whole string as a number in [lo, hi] (no trailing characters; NaN never passes).
bool ParseNumber(const std::string& text, double lo, double hi, double* out);

// Parses a whole string as an integer in [lo, hi]: optional sign and decimal digits only, so
// "2.9", "2e3", "0x10" and " 2" are refused (a count flag never rounds).
bool ParseInteger(const std::string& text, long long lo, long long hi, long long* out);

// The exit codes (docs/errors.md): 0 done; 1 an input file (or writing an output) failed, with
// messages naming the file and where in it; 2 the command line is wrong (unknown flag, bad
// value, missing argument, an output name whose extension the command cannot write), found
// before any file is read or written.
inline constexpr int kExitInput = 1;
inline constexpr int kExitUsage = 2;

// "" when `path` ends in one of `extensions` (lower case, with the dot; compared
// case-insensitively), else "--<flag> PATH: expected a .a or .b file name" for UsageError.
std::string CheckOutputExtension(const std::string& flag, const std::string& path,
                                 const std::vector<std::string>& extensions);

// True when `a` and `b` name the same existing file (same device and inode), or the same path
// once made absolute and normal; for refusing to overwrite an input with an output.
bool SameFile(const std::string& a, const std::string& b);

// Prints "mimetic <cmd>: <error>\n<usage>" to stderr and returns 2.
int UsageError(const std::string& command, const std::string& error, const char* usage);

// The default ARKit map: assets/arkit/default.arkit.json found from the rig's folder upwards
// (the rig sits in assets/head of a source tree), else that path relative to the working
// directory.
std::string DefaultArkitMap(const std::string& rig_path);

// A progress bar on stderr, drawn only when stderr is a terminal and `enabled` (not --quiet):
// "[####    ] done/total <unit>", ending the line at done == total.
class Progress {
 public:
  Progress(long long total, bool enabled, const char* unit = "frames");
  void Update(long long done);
  void Abort();  // ends the line early (an error follows)

 private:
  long long total_;
  bool on_;
  const char* unit_;
};

}  // namespace mimetic::tools
