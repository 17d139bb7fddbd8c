// core/file_util_hook.h: a test hook of WriteFileAtomic (core/file_util.h), kept out of that
// header so that only the tests and the viewer's fault injection see it.
#pragma once

#include <string>

namespace mimetic {

// Called by WriteFileAtomic after the temporary file is written, flushed and closed and before
// it is renamed over `path` (nullptr: none, the default). Tests set one that ends the process
// (_exit) to check that a save killed there leaves the old file as it was.
using WriteFileAtomicHook = void (*)(const std::string& tmp, const std::string& path);
void SetWriteFileAtomicHook(WriteFileAtomicHook hook);

}  // namespace mimetic
