// rig/runtime/rig_binary.h: the compiled rig, `.mrig` (docs/mrig-format.md).
//
// A versioned little-endian binary of a RigData (what the builder authored, after refinement),
// written by `mimetic build` and read by the runtime alone: no JSON, glTF, OpenMesh or stb
// code. The reader checks the tag, the version, every size, the checksum and every section's
// bounds and element counts before it reads a byte of it, then hands the data to Rig::Build,
// which checks every index. Errors are values: a message naming what is wrong and where
// (section name, byte offset); nothing here throws or aborts on any input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/span.h"
#include "rig/runtime/rig.h"

namespace mimetic {

inline constexpr char kRigBinaryTag[4] = {'M', 'R', 'I', 'G'};
inline constexpr uint16_t kRigBinaryMajor = 2;  // a reader refuses a newer major version
inline constexpr uint16_t kRigBinaryMinor = 2;  // a newer minor may add sections (skipped); 2.1: eyes, 2.2: wrinkle gates
inline constexpr size_t kRigBinaryHeaderBytes = 40;
inline constexpr size_t kRigBinarySectionEntryBytes = 32;
// The file helper refuses a larger file before reading it.
inline constexpr size_t kMaxRigBinaryFileBytes = size_t{1} << 30;

// What a tool wants to say about a compiled rig beyond the RigData (optional sections).
struct RigBinaryInfo {
  std::string units;               // the rig file's "units" ("" when not known)
  uint32_t source_vertex_count = 0;  // vertices of the source mesh file (0 when not known)
};

// The bytes of `data` (deterministic: the same data gives the same bytes). `info` may be null.
std::string WriteRigBinary(const RigData& data, const RigBinaryInfo* info = nullptr);

// True when `bytes` starts with the tag (what LoadRig uses to tell a .mrig from JSON).
bool HasRigBinaryTag(span<const uint8_t> bytes);

// Parses and checks `bytes` into *out (no Rig::Build). On failure returns false and sets
// *error to "<where>: <what>" (e.g. "section 'triangles' (id 2) at byte 1234: ...").
bool ReadRigBinaryData(span<const uint8_t> bytes, RigData* out, RigBinaryInfo* info,
                       std::string* error);

// ReadRigBinaryData, then Rig::Build (which checks every index). `info` may be null.
bool ReadRigBinary(span<const uint8_t> bytes, Rig* out, RigBinaryInfo* info, std::string* error);

// Reads a whole regular file of at most `max_bytes` bytes into *out; on failure sets *error.
bool ReadRigBinaryFile(const std::string& path, std::string* out, std::string* error,
                       size_t max_bytes = kMaxRigBinaryFileBytes);

// ReadRigBinaryFile + ReadRigBinary; messages are prefixed with the path.
bool LoadRigBinaryFile(const std::string& path, Rig* out, RigBinaryInfo* info,
                       std::string* error);

// FNV-1a 64 of `bytes`.
uint64_t Fnv1a64(span<const uint8_t> bytes);
// The format's checksum (docs/mrig-format.md): over the file's 64-bit little-endian words (the
// tail zero padded; word 3, the checksum field [24, 32), as 0), h = (rotl(h, 23) ^ word) *
// 0x100000001b3 from h = 0xcbf29ce484222325 (FNV-1a's constants, word-wise), so that a flipped
// header byte is caught too; from version 2.0 in four interleaved lanes (binary::Checksum),
// chosen by the file's own version. 0 for a file shorter than the header.
uint64_t RigBinaryChecksum(span<const uint8_t> file);

}  // namespace mimetic
