#include "test_support.h"

#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mimetic::test {

std::string SourceDir() { return MIMETIC_SOURCE_DIR; }

bool Sanitized() {
#ifdef MIMETIC_TEST_SANITIZED
  return true;
#else
  return false;
#endif
}

std::string SharedDir() {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::weakly_canonical(MIMETIC_SHARED_DIR, ec);
  if (ec || !std::filesystem::is_directory(p)) return "";
  return p.string();
}

std::string ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string TempDir() {
  char tmpl[] = "/tmp/mimetic-test-XXXXXX";
  const char* dir = ::mkdtemp(tmpl);
  return dir ? std::string(dir) : std::string("/tmp");
}

static std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

ToolResult RunTool(const std::vector<std::string>& args) {
  return RunCommand(Quote(MIMETIC_TOOL_PATH), args);
}

ToolResult RunCommand(const std::string& command, const std::vector<std::string>& args) {
  std::string cmd = command;
  for (const std::string& a : args) cmd += " " + Quote(a);
  cmd += " 2>&1";
  ToolResult result;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) result.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string ShellQuote(const std::string& s) { return Quote(s); }

}  // namespace mimetic::test
