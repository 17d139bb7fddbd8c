#include "tools/cli.h"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

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

bool ParseInteger(const std::string& text, long long lo, long long hi, long long* out) {
  size_t i = 0;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
  if (i == text.size() || text.size() - i > 18) return false;
  for (size_t k = i; k < text.size(); ++k)
    if (!std::isdigit(static_cast<unsigned char>(text[k]))) return false;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), nullptr, 10);
  if (errno == ERANGE || v < lo || v > hi) return false;
  *out = v;
  return true;
}

std::string CheckOutputExtension(const std::string& flag, const std::string& path,
                                 const std::vector<std::string>& extensions) {
  std::string lower = path;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const size_t slash = lower.find_last_of('/');
  const std::string name = slash == std::string::npos ? lower : lower.substr(slash + 1);
  for (const std::string& e : extensions)
    if (name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0)
      return "";
  std::string list;
  for (size_t i = 0; i < extensions.size(); ++i)
    list += (i == 0 ? "" : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
  return "--" + flag + " " + path + ": expected a " + list + " file name";
}

bool SameFile(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  std::error_code ec1, ec2;
  const auto pa = std::filesystem::weakly_canonical(a, ec1);
  const auto pb = std::filesystem::weakly_canonical(b, ec2);
  return !ec1 && !ec2 && pa == pb;
}

std::string DefaultArkitMap(const std::string& rig_path) {
  std::error_code ec;
  std::filesystem::path dir = std::filesystem::absolute(rig_path, ec).parent_path();
  for (int i = 0; i < 4 && !dir.empty(); ++i, dir = dir.parent_path()) {
    for (const char* rel : {"arkit/default.arkit.json", "assets/arkit/default.arkit.json"}) {
      const std::filesystem::path p = dir / rel;
      if (std::filesystem::is_regular_file(p, ec)) return p.string();
    }
    if (dir == dir.parent_path()) break;
  }
  return "assets/arkit/default.arkit.json";
}

Progress::Progress(long long total, bool enabled, const char* unit)
    : total_(total), on_(enabled && isatty(fileno(stderr)) != 0), unit_(unit) {}

void Progress::Update(long long done) {
  if (!on_) return;
  const int width = 40, filled = int(width * done / (total_ > 0 ? total_ : 1));
  std::fprintf(stderr, "\r[%s%s] %lld/%lld %s", std::string(size_t(filled), '#').c_str(),
               std::string(size_t(width - filled), ' ').c_str(), done, total_, unit_);
  if (done == total_) std::fputc('\n', stderr);
  std::fflush(stderr);
}

void Progress::Abort() {
  if (on_) std::fputc('\n', stderr);
}

}  // namespace mimetic::tools
