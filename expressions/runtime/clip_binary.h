// expressions/runtime/clip_binary.h: the compiled clip, `.mclip` (docs/mclip-format.md).
//
// A versioned little-endian binary of a CompiledClip (a clip already resolved against one
// rig's muscles and its expressions), written by `mimetic build CLIP --rig RIG` and read by the
// runtime alone: no JSON. The container (header, section table, checksum) is the .mrig's
// (core/binary_sections.h) with its own tag. The reader checks the tag, the version, every
// size, the checksum, then every index, offset, enum and float the sampler relies on
// (docs/mclip-format.md "Reading and its checks") before the clip is handed out, so that
// ClipSampleJob runs on what it loaded without per-frame checks. Errors are values: a message
// naming what is wrong and where (section name, byte offset, element); nothing here throws or
// aborts on any input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/span.h"
#include "expressions/runtime/clip.h"

namespace mimetic {

inline constexpr char kClipBinaryTag[4] = {'M', 'C', 'L', 'P'};
inline constexpr uint16_t kClipBinaryMajor = 1;  // a reader refuses a newer major version
inline constexpr uint16_t kClipBinaryMinor = 0;  // a newer minor may add sections (skipped)
// The file helper refuses a larger file before reading it.
inline constexpr size_t kMaxClipBinaryFileBytes = size_t{1} << 28;

// The bytes of `clip` (deterministic: the same clip gives the same bytes). An unbuilt clip
// gives a file the reader refuses.
std::string WriteClipBinary(const CompiledClip& clip);

// True when `bytes` starts with the tag (how the tools tell a .mclip from a clip's JSON).
bool HasClipBinaryTag(span<const uint8_t> bytes);

// Parses and checks `bytes` into *out (built on success, untouched on failure). On failure
// returns false and sets *error (when not null) to "<where>: <what>", e.g.
// "section 'channel_targets' (id 5) at byte 312: channel 2 (a muscle channel) targets muscle
// 40; the clip has 32 muscles".
bool ReadClipBinary(span<const uint8_t> bytes, CompiledClip* out, std::string* error);

// Reads the file (a regular file of at most kMaxClipBinaryFileBytes) and ReadClipBinary;
// messages are prefixed with the path.
bool LoadClipBinaryFile(const std::string& path, CompiledClip* out, std::string* error);

}  // namespace mimetic
