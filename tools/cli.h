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

// Prints "mimetic <cmd>: <error>\n<usage>" to stderr and returns 2.
int UsageError(const std::string& command, const std::string& error, const char* usage);

}  // namespace mimetic::tools
