// core/binary_sections.h: the container the compiled formats share (.mrig, docs/mrig-format.md;
// .mclip, docs/mclip-format.md): a 40-byte little-endian header (tag, version, flags, section
// count, total size, checksum, header size), a table of 32-byte section entries (id, element
// size, offset, size, count) and 8-byte aligned payloads. This file writes that container and
// reads it back with every bounds, size and count check done before a payload byte is read;
// what a section means is the format's (rig/runtime/rig_binary.cpp,
// expressions/runtime/clip_binary.cpp). Runtime code: the C++ standard library only, no
// exceptions; errors are values ("WHERE: WHAT").
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "core/span.h"

namespace mimetic::binary {

inline constexpr size_t kHeaderBytes = 40;
inline constexpr size_t kSectionEntryBytes = 32;

// One section a format knows. element_size 0: a string table (u32 offsets[count + 1], then the
// characters).
struct SectionDesc {
  uint32_t id;
  const char* name;
  uint32_t element_size;
  uint64_t fixed_count;  // 0: any count
  bool required;
};

// One format: its tag, version and sections, and the words its messages use.
struct Format {
  char tag[4];                 // e.g. {'M', 'R', 'I', 'G'}
  uint16_t major, minor;       // a reader refuses a newer major version
  const char* extension;       // ".mrig" (messages: "a .mrig header is 40 bytes")
  const char* what;            // "compiled rig" (messages: "not a compiled rig")
  const char* rebuild;         // what to do about a newer major version
  const SectionDesc* sections;
  size_t section_count;
  // The first major version whose checksum runs over four lanes (Checksum below; a changed
  // checksum is a new major version, as older readers cannot check it); 0: every version has
  // the one-lane checksum.
  uint16_t four_lane_major = 0;
};

// ---- little-endian scalars ----------------------------------------------------------------

inline uint32_t LoadU32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
inline uint16_t LoadU16(const uint8_t* p) { return uint16_t(p[0] | p[1] << 8); }
inline uint64_t LoadU64(const uint8_t* p) {
  if constexpr (std::endian::native == std::endian::little) {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
  }
  return LoadU32(p) | uint64_t(LoadU32(p + 4)) << 32;
}
inline float LoadF32(const uint8_t* p) { return std::bit_cast<float>(LoadU32(p)); }

inline void StoreU32(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v), p[1] = uint8_t(v >> 8), p[2] = uint8_t(v >> 16), p[3] = uint8_t(v >> 24);
}
inline void StoreU16(uint8_t* p, uint16_t v) { p[0] = uint8_t(v), p[1] = uint8_t(v >> 8); }
inline void StoreU64(uint8_t* p, uint64_t v) {
  StoreU32(p, uint32_t(v));
  StoreU32(p + 4, uint32_t(v >> 32));
}

// The checksum of the formats: over the file's 64-bit little-endian words (the tail zero
// padded; word 3, the checksum field [24, 32), as 0), h = (rotl(h, 23) ^ word) * 0x100000001b3
// from h = 0xcbf29ce484222325. 0 for a file shorter than the header. With lanes = 4 (.mrig 2.0
// on): word i goes into lane i % 4, lane l starting from 0xcbf29ce484222325 ^ l with the same
// step, and the result is the same step over the four lanes' values in order from
// 0xcbf29ce484222325: four independent multiply chains, about 4x faster on one core.
uint64_t Checksum(span<const uint8_t> file, int lanes = 1);
// Checksum over a file given in pieces (the same value as Checksum(file, lanes)), so that a
// reader can check each piece while it is still in cache: Update with consecutive pieces, each
// but the last a multiple of 32 bytes long, then Finish. The first piece must hold the header.
class Checksummer {
 public:
  explicit Checksummer(int lanes);
  void Update(const uint8_t* p, size_t n);
  uint64_t Finish();  // the checksum; 0 when fewer bytes than a header were given

 private:
  uint64_t h_[4];
  uint64_t words_ = 0;  // words consumed
  uint64_t bytes_ = 0;
  uint64_t tail_ = 0;   // the last piece's partial word, zero padded
  bool has_tail_ = false;
  int lanes_;
};

// The lanes a file of `format` is checked with: 4 when the format has a four_lane_major and the
// file's header says a major version >= it, else 1 (also for a file shorter than the header).
int ChecksumLanes(const Format& format, span<const uint8_t> file);

// ---- writing ------------------------------------------------------------------------------

struct OutSection {
  uint32_t id = 0;
  uint32_t element_size = 0;
  uint64_t count = 0;
  std::vector<uint8_t> payload;
};

// Appends little-endian values to one section's payload.
class Payload {
 public:
  explicit Payload(OutSection* s) : s_(s) {}
  void U8(uint8_t v) { s_->payload.push_back(v); }
  void U32(uint32_t v) {
    const size_t n = s_->payload.size();
    s_->payload.resize(n + 4);
    StoreU32(&s_->payload[n], v);
  }
  void F32(float v) { U32(std::bit_cast<uint32_t>(v)); }
  void Bytes(const std::string& s) { s_->payload.insert(s_->payload.end(), s.begin(), s.end()); }

 private:
  OutSection* s_;
};

// Collects sections (each id must be one of the format's) and lays out the file.
class SectionWriter {
 public:
  explicit SectionWriter(const Format& format) : format_(format) {}
  // A new section of `count` elements; fill its payload with Payload(&Begin(...)).
  OutSection& Begin(uint32_t id, uint64_t count);
  void U8s(uint32_t id, const std::vector<uint8_t>& v);
  void U32s(uint32_t id, const std::vector<uint32_t>& v);
  void F32s(uint32_t id, const std::vector<float>& v);
  void Strings(uint32_t id, const std::vector<std::string>& v);
  // The file: header, section table, then each payload at an 8-byte boundary (zero padding),
  // in the order the sections were begun. Deterministic.
  std::string Finish() const;

 private:
  const Format& format_;
  std::vector<OutSection> sections_;
};

// ---- reading ------------------------------------------------------------------------------

// Reads element i of a file's array of T (32-bit words, host byte order) by memcpy, so that a
// vector is filled straight from the bytes (no zero-filled resize before the copy: that pass
// and its page faults were a tenth of the sample head's load, docs/performance.md).
template <class T>
struct WordLoader {
  using iterator_category = std::random_access_iterator_tag;
  using value_type = T;
  using difference_type = std::ptrdiff_t;
  using pointer = const T*;
  using reference = T;
  const uint8_t* p;
  T operator*() const {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
  }
  WordLoader& operator++() { p += sizeof(T); return *this; }
  WordLoader operator++(int) { WordLoader old = *this; p += sizeof(T); return old; }
  WordLoader& operator--() { p -= sizeof(T); return *this; }
  WordLoader operator--(int) { WordLoader old = *this; p -= sizeof(T); return old; }
  WordLoader& operator+=(difference_type n) { p += n * difference_type(sizeof(T)); return *this; }
  WordLoader& operator-=(difference_type n) { p -= n * difference_type(sizeof(T)); return *this; }
  friend WordLoader operator+(WordLoader a, difference_type n) { return a += n; }
  friend WordLoader operator+(difference_type n, WordLoader a) { return a += n; }
  friend WordLoader operator-(WordLoader a, difference_type n) { return a -= n; }
  T operator[](difference_type n) const { return *(*this + n); }
  friend bool operator<(WordLoader a, WordLoader b) { return a.p < b.p; }
  friend difference_type operator-(WordLoader a, WordLoader b) {
    return (a.p - b.p) / difference_type(sizeof(T));
  }
  friend bool operator==(WordLoader a, WordLoader b) { return a.p == b.p; }
  friend bool operator!=(WordLoader a, WordLoader b) { return a.p != b.p; }
};

// On a little-endian host a file's array of 32-bit words is the vector's bytes: `n` elements
// copied from `p` (false on a big-endian host: decode element by element instead).
template <class T>
bool CopyIfNative(const uint8_t* p, uint64_t n, std::vector<T>* out) {
  static_assert(sizeof(T) % 4 == 0, "arrays of 32-bit words");
  if constexpr (std::endian::native != std::endian::little) return false;
  out->assign(WordLoader<T>{p}, WordLoader<T>{p + size_t(n) * sizeof(T)});
  return true;
}

struct InSection {
  const SectionDesc* desc = nullptr;
  uint64_t offset = 0, size = 0, count = 0;
  const uint8_t* data = nullptr;  // null: an optional section the file does not have
};

// "section 'NAME' (id N) at byte OFFSET"
std::string SectionWhere(const SectionDesc& d, uint64_t offset);

// Checks, in this order: the header (size, tag, major version, flags, header size), that the
// section table fits, every entry (after the table and the entry before it, 8-aligned, inside
// the file; for a known id its element size, fixed count, count x element size = size, not
// twice; unknown ids are skipped), the total size, the checksum, the required sections. On
// success (*known)[k] describes format.sections[k] (absent optional sections with data null,
// count 0). On failure *error is "WHERE: WHAT".
bool ReadSections(span<const uint8_t> bytes, const Format& format, std::vector<InSection>* known,
                  std::string* error, const uint64_t* computed_checksum = nullptr);
// computed_checksum: the file's checksum as the caller computed it while reading (ReadFileBuffer
// with a format), instead of one more pass over the bytes; null: computed here.

// Decodes the sections ReadSections checked (their bounds are known good).
class SectionReader {
 public:
  SectionReader(const Format& format, const std::vector<InSection>& known, std::string* error)
      : format_(format), known_(known), error_(error) {}

  const InSection& Of(uint32_t id) const;
  // Sets the error "section 'NAME' (id N) at byte OFFSET: what"; returns false.
  bool Fail(const InSection& s, const std::string& what) const;
  // Elements [first, first + n) of a section of 4-byte (1-byte) elements.
  void U32s(const InSection& s, uint64_t first, uint64_t n, std::vector<uint32_t>* out) const;
  void F32s(const InSection& s, uint64_t first, uint64_t n, std::vector<float>* out) const;
  void U32s(uint32_t id, std::vector<uint32_t>* out) const;
  void F32s(uint32_t id, std::vector<float>* out) const;
  void U8s(uint32_t id, std::vector<uint8_t>* out) const;
  // A string table (an absent optional one leaves *out alone); false on a malformed table.
  bool Strings(uint32_t id, std::vector<std::string>* out) const;

 private:
  const Format& format_;
  const std::vector<InSection>& known_;
  std::string* error_;
};

// Reads a whole regular file of at most `max_bytes` bytes into *out; on failure sets *error
// (`what` names what was expected: "compiled rig").
bool ReadFileBytes(const std::string& path, const char* what, size_t max_bytes, std::string* out,
                   std::string* error);
// The same checks and read as ReadFileBytes into a new buffer that is not zero-filled first
// (one pass over 33 MB fewer for the sample head's .mrig): *out holds *size bytes.
bool ReadFileBuffer(const std::string& path, const char* what, size_t max_bytes,
                    std::unique_ptr<uint8_t[]>* out, size_t* size, std::string* error);
// The same, read in 1 MiB pieces and each checksummed while in cache with the lanes the file's
// header asks of `format` (*checksum: as Checksum(file, ChecksumLanes(format, file))).
bool ReadFileBuffer(const std::string& path, const Format& format, size_t max_bytes,
                    std::unique_ptr<uint8_t[]>* out, size_t* size, uint64_t* checksum,
                    std::string* error);

}  // namespace mimetic::binary
