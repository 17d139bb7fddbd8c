// core/file_util.h: whole-file reads and atomic writes (offline use).
#pragma once

#include <cstddef>
#include <string>

#include "core/diagnostics.h"

namespace mimetic {

// Size caps per kind of input (docs/errors.md "Size limits"): a file larger than its cap is
// refused before a byte of it is read.
inline constexpr size_t kMiB = size_t{1} << 20;
inline constexpr size_t kMaxJsonFileBytes = 64 * kMiB;    // rig, template, landmarks, expression
inline constexpr size_t kMaxMeshFileBytes = 1024 * kMiB;  // .gltf/.glb/.obj and glTF buffers
inline constexpr size_t kMaxImageFileBytes = 256 * kMiB;  // PNG/JPEG/... images

// Reads a whole file, which must be a regular file of at most `max_bytes` bytes. `what` names
// the kind of file for the messages ("mesh file", "rig file"). Never blocks on a FIFO and never
// reads more than max_bytes + 1 bytes (an endless or growing file stops there). On failure
// records one of (where = `path`)
//   "cannot open: <strerror>"
//   "is not a regular file (it is a directory|FIFO|character device|...; expected a <what>)"
//   "is larger than the <N> MiB limit for a <what> (<size> bytes)"
//   "read error: <strerror>"
// and returns false.
bool ReadFile(const std::string& path, std::string* out, Diagnostics* diag,
              size_t max_bytes = kMaxJsonFileBytes, const std::string& what = "file");

// The same check without reading: "" when `path` is a regular file of at most max_bytes bytes,
// else the message ReadFile would record (without the path).
std::string CheckRegularFile(const std::string& path, size_t max_bytes, const std::string& what);

// Writes `bytes` to `path` atomically: a temporary file `<path>.tmp<pid>` in the same
// directory, flushed, then renamed over `path`. A crash leaves either the old file or the new
// one, and at worst its temporary file, which the next write of the same path removes (any
// `<path>.tmp<pid>` whose process no longer runs).
bool WriteFileAtomic(const std::string& path, const std::string& bytes, Diagnostics* diag);

// Directory part of a path ("" for a bare file name) and path joining that leaves absolute
// paths alone.
std::string DirectoryOf(const std::string& path);
std::string JoinPath(const std::string& dir, const std::string& path);

}  // namespace mimetic
