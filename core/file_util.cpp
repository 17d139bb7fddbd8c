#include "core/file_util.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <unistd.h>

namespace mimetic {

bool ReadFile(const std::string& path, std::string* out, Diagnostics* diag) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    diag->Error(path, std::string("cannot open: ") + std::strerror(errno));
    return false;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) {
    diag->Error(path, "read error");
    return false;
  }
  *out = ss.str();
  return true;
}

bool WriteFileAtomic(const std::string& path, const std::string& bytes, Diagnostics* diag) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    diag->Error(path, std::string("cannot write: ") + std::strerror(errno));
    return false;
  }
  const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const bool flushed = std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!wrote || !flushed || !closed) {
    diag->Error(path, std::string("cannot write: ") + std::strerror(errno));
    std::remove(tmp.c_str());
    return false;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    diag->Error(path, std::string("cannot rename temporary file: ") + std::strerror(errno));
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return "";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string JoinPath(const std::string& dir, const std::string& path) {
  if (path.empty() || path[0] == '/' || dir.empty()) return path;
  if (dir.back() == '/') return dir + path;
  return dir + "/" + path;
}

}  // namespace mimetic
