#include "tools/cli.h"

#include <cstdlib>

#include <cstdio>

namespace mimetic::tools {

std::string ParsedArgs::Get(const std::string& key, const std::string& fallback) const {
  auto it = values.find(key);
  return it == values.end() || it->second.empty() ? fallback : it->second.back();
}

ParsedArgs ParseArgs(const std::vector<std::string>& args, const std::set<std::string>& valued,
                     const std::set<std::string>& flags) {
  ParsedArgs out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      out.help = true;
      continue;
    }
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string key = a.substr(2), value;
      const size_t eq = key.find('=');
      const bool inline_value = eq != std::string::npos;
      if (inline_value) {
        value = key.substr(eq + 1);
        key = key.substr(0, eq);
      }
      if (flags.count(key) && !inline_value) {
        out.flags.insert(key);
      } else if (valued.count(key)) {
        if (!inline_value) {
          if (i + 1 >= args.size()) {
            out.error = "option --" + key + " needs a value";
            return out;
          }
          value = args[++i];
        }
        out.values[key].push_back(value);
      } else {
        out.error = "unknown option '" + a + "'";
        return out;
      }
    } else {
      out.positional.push_back(a);
    }
  }
  return out;
}

int UsageError(const std::string& command, const std::string& error, const char* usage) {
  std::fprintf(stderr, "mimetic %s: %s\n\n%s", command.c_str(), error.c_str(), usage);
  return 2;
}

bool ParseNumber(const std::string& text, double lo, double hi, double* out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v >= lo && v <= hi)) return false;
  *out = v;
  return true;
}

}  // namespace mimetic::tools
