// tests/test_support.h: paths and a CLI runner shared by the tests.
#pragma once

#include <string>
#include <vector>

namespace mimetic::test {

// Repository root (for tests/data and assets).
std::string SourceDir();
// ../shared beside the repository, or "" when it is absent (tests then GTEST_SKIP with a message).
std::string SharedDir();
// True in the sanitizer build (MIMETIC_SANITIZE): slow sweeps sample fewer cases there.
bool Sanitized();
// A fresh, empty temporary directory for this test (removed by nothing; under /tmp).
std::string TempDir();

struct ToolResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};
// Runs the built `mimetic` tool with `args` (each quoted for the shell).
ToolResult RunTool(const std::vector<std::string>& args);
// Runs `command` (shell text, already quoted) with `args` appended, each quoted.
ToolResult RunCommand(const std::string& command, const std::vector<std::string>& args);
// `s` quoted for the shell.
std::string ShellQuote(const std::string& s);

// The bytes of the file at `path` (empty when it cannot be read).
std::string ReadFileBytes(const std::string& path);

}  // namespace mimetic::test
