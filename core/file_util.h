// core/file_util.h: whole-file reads and atomic writes (offline use).
#pragma once

#include <string>

#include "core/diagnostics.h"

namespace mimetic {

// Reads a whole file. On failure records "<path>: cannot open: <reason>" and returns false.
bool ReadFile(const std::string& path, std::string* out, Diagnostics* diag);

// Writes `bytes` to `path` atomically: a temporary file in the same directory, flushed,
// then renamed over `path`. A crash leaves either the old file or the new one.
bool WriteFileAtomic(const std::string& path, const std::string& bytes, Diagnostics* diag);

// Directory part of a path ("" for a bare file name) and path joining that leaves absolute
// paths alone.
std::string DirectoryOf(const std::string& path);
std::string JoinPath(const std::string& dir, const std::string& path);

}  // namespace mimetic
