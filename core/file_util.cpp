#include "core/file_util.h"
#include "core/file_util_hook.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

namespace mimetic {
namespace {

const char* FileKind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a plain file";
}

std::string Article(const std::string& what) {
  if (what.empty()) return "a file";
  const char c = what[0];
  const bool vowel = c == 'a' || c == 'e' || c == 'i' || c == 'o' || c == 'u';
  return (vowel ? "an " : "a ") + what;
}

std::string NotRegular(mode_t mode, const std::string& what) {
  return std::string("is not a regular file (it is ") + FileKind(mode) + "; expected " +
         Article(what) + ")";
}

std::string TooLarge(size_t size, size_t max_bytes, const std::string& what, bool at_least) {
  return "is larger than the " + std::to_string(max_bytes / kMiB) + " MiB limit for " +
         Article(what) + " (" + (at_least ? "more than " : "") + std::to_string(size) +
         " bytes)";
}

// Removes `<path>.tmp<pid>` files left by processes that no longer run.
void RemoveStaleTemporaries(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  const std::string prefix =
      (slash == std::string::npos ? path : path.substr(slash + 1)) + ".tmp";
  std::error_code ec;
  std::filesystem::directory_iterator it(dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::strtol(digits.c_str(), nullptr, 10);
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // still running
    std::remove((dir + "/" + name).c_str());
  }
}

}  // namespace

std::string CheckRegularFile(const std::string& path, size_t max_bytes, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::string("cannot open: ") + std::strerror(errno);
  if (!S_ISREG(st.st_mode)) return NotRegular(st.st_mode, what);
  if (static_cast<unsigned long long>(st.st_size) > max_bytes)
    return TooLarge(static_cast<size_t>(st.st_size), max_bytes, what, false);
  return "";
}

bool ReadFile(const std::string& path, std::string* out, Diagnostics* diag, size_t max_bytes,
              const std::string& what) {
  // O_NONBLOCK: opening a FIFO without a writer would otherwise block forever.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    diag->Error(path, std::string("cannot open: ") + std::strerror(errno));
    return false;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    diag->Error(path, std::string("cannot open: ") + std::strerror(errno));
    ::close(fd);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    diag->Error(path, NotRegular(st.st_mode, what));
    ::close(fd);
    return false;
  }
  if (static_cast<unsigned long long>(st.st_size) > max_bytes) {
    diag->Error(path, TooLarge(static_cast<size_t>(st.st_size), max_bytes, what, false));
    ::close(fd);
    return false;
  }
  // Regular files do not block; clear O_NONBLOCK anyway so a short read means end of file.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string data;
  data.resize(static_cast<size_t>(st.st_size) + 1);  // +1: notices a file that grew
  size_t have = 0;
  while (true) {
    if (have == data.size()) {
      if (data.size() > max_bytes) break;
      data.resize(std::min(max_bytes + 1, data.size() * 2 + 4096));
    }
    const ssize_t n = ::read(fd, &data[have], data.size() - have);
    if (n < 0) {
      if (errno == EINTR) continue;
      diag->Error(path, std::string("read error: ") + std::strerror(errno));
      ::close(fd);
      return false;
    }
    if (n == 0) break;
    have += static_cast<size_t>(n);
  }
  ::close(fd);
  if (have > max_bytes) {
    diag->Error(path, TooLarge(max_bytes, max_bytes, what, true));
    return false;
  }
  data.resize(have);
  *out = std::move(data);
  return true;
}

namespace {
WriteFileAtomicHook g_before_rename = nullptr;
}  // namespace

void SetWriteFileAtomicHook(WriteFileAtomicHook hook) { g_before_rename = hook; }

bool WriteFileAtomic(const std::string& path, const std::string& bytes, Diagnostics* diag) {
  RemoveStaleTemporaries(path);
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
  if (g_before_rename) g_before_rename(tmp, path);  // tests: a crash between write and rename
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
