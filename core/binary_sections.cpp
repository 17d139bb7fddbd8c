// core/binary_sections.cpp: the compiled formats' container (core/binary_sections.h).
#include "core/binary_sections.h"

#include <algorithm>
#include <cstdio>
#include <optional>

#include <sys/stat.h>

namespace mimetic::binary {
namespace {

const SectionDesc* FindSection(const Format& f, uint32_t id) {
  for (size_t i = 0; i < f.section_count; ++i)
    if (f.sections[i].id == id) return &f.sections[i];
  return nullptr;
}

size_t Align8(size_t n) { return (n + 7) & ~size_t{7}; }

}  // namespace

namespace {
constexpr uint64_t kBasis = 0xcbf29ce484222325ull, kPrime = 0x100000001b3ull;
inline uint64_t Step(uint64_t h, uint64_t w) { return (std::rotl(h, 23) ^ w) * kPrime; }
}  // namespace

// FNV-1a's offset basis and prime over 64-bit little-endian words (8x fewer serial steps than
// bytes), the state rotated before each word so that high input bits reach the low bits; word
// 3 (bytes [24, 32), the checksum) counts as 0 and the tail is zero padded. Four lanes break
// the one serial multiply chain into four the core runs side by side.
Checksummer::Checksummer(int lanes)
    : h_{kBasis, kBasis ^ 1, kBasis ^ 2, kBasis ^ 3}, lanes_(lanes == 4 ? 4 : 1) {}

void Checksummer::Update(const uint8_t* p, size_t n) {
  bytes_ += n;
  size_t i = 0;
  // The header's words one by one (word 3, the checksum field, as 0).
  for (; words_ < 4 && i + 8 <= n; i += 8, ++words_)
    h_[lanes_ == 4 ? words_ : 0] = Step(h_[lanes_ == 4 ? words_ : 0], words_ == 3 ? 0 : LoadU64(p + i));
  if (lanes_ == 4) {
    for (; i + 32 <= n; i += 32, words_ += 4) {  // words_ % 4 == 0 here
      h_[0] = Step(h_[0], LoadU64(p + i));
      h_[1] = Step(h_[1], LoadU64(p + i + 8));
      h_[2] = Step(h_[2], LoadU64(p + i + 16));
      h_[3] = Step(h_[3], LoadU64(p + i + 24));
    }
    for (; i + 8 <= n; i += 8, ++words_) h_[words_ % 4] = Step(h_[words_ % 4], LoadU64(p + i));
  } else {
    uint64_t h = h_[0];
    for (; i + 8 <= n; i += 8, ++words_) h = Step(h, LoadU64(p + i));
    h_[0] = h;
  }
  if (i < n) {  // the file's last partial word
    uint8_t tail[8] = {};
    std::memcpy(tail, p + i, n - i);
    tail_ = LoadU64(tail);
    has_tail_ = true;
  }
}

uint64_t Checksummer::Finish() {
  if (bytes_ < kHeaderBytes) return 0;
  if (has_tail_) {
    uint64_t& h = h_[lanes_ == 4 ? words_ % 4 : 0];
    h = Step(h, tail_);
  }
  if (lanes_ != 4) return h_[0];
  uint64_t out = kBasis;
  for (uint64_t lane : h_) out = Step(out, lane);
  return out;
}

uint64_t Checksum(span<const uint8_t> file, int lanes) {
  Checksummer sum(lanes);
  sum.Update(file.data(), file.size());
  return sum.Finish();
}

int ChecksumLanes(const Format& format, span<const uint8_t> file) {
  if (file.size() < kHeaderBytes || format.four_lane_major == 0) return 1;
  return LoadU16(file.data() + 4) >= format.four_lane_major ? 4 : 1;
}

// ---- writer -------------------------------------------------------------------------------

OutSection& SectionWriter::Begin(uint32_t id, uint64_t count) {
  const SectionDesc* d = FindSection(format_, id);
  OutSection s;
  s.id = id;
  s.element_size = d ? d->element_size : 0;
  s.count = count;
  sections_.push_back(std::move(s));
  return sections_.back();
}

void SectionWriter::U8s(uint32_t id, const std::vector<uint8_t>& v) {
  OutSection& s = Begin(id, v.size());
  s.payload.assign(v.begin(), v.end());
}

void SectionWriter::U32s(uint32_t id, const std::vector<uint32_t>& v) {
  Payload p(&Begin(id, v.size()));
  for (uint32_t x : v) p.U32(x);
}

void SectionWriter::F32s(uint32_t id, const std::vector<float>& v) {
  Payload p(&Begin(id, v.size()));
  for (float x : v) p.F32(x);
}

void SectionWriter::Strings(uint32_t id, const std::vector<std::string>& v) {
  Payload p(&Begin(id, v.size()));
  uint32_t at = 0;
  p.U32(0);
  for (const std::string& s : v) p.U32(at += uint32_t(s.size()));
  for (const std::string& s : v) p.Bytes(s);
}

std::string SectionWriter::Finish() const {
  const size_t table_end = kHeaderBytes + kSectionEntryBytes * sections_.size();
  size_t at = table_end;
  std::vector<size_t> offsets;
  for (const OutSection& s : sections_) {
    at = Align8(at);
    offsets.push_back(at);
    at += s.payload.size();
  }
  std::string out(at, '\0');
  uint8_t* b = reinterpret_cast<uint8_t*>(out.data());
  for (size_t i = 0; i < sections_.size(); ++i) {
    uint8_t* e = b + kHeaderBytes + kSectionEntryBytes * i;
    StoreU32(e, sections_[i].id);
    StoreU32(e + 4, sections_[i].element_size);
    StoreU64(e + 8, offsets[i]);
    StoreU64(e + 16, sections_[i].payload.size());
    StoreU64(e + 24, sections_[i].count);
    if (!sections_[i].payload.empty())
      std::memcpy(b + offsets[i], sections_[i].payload.data(), sections_[i].payload.size());
  }
  std::memcpy(b, format_.tag, 4);
  StoreU16(b + 4, format_.major);
  StoreU16(b + 6, format_.minor);
  StoreU32(b + 8, 0);  // flags
  StoreU32(b + 12, uint32_t(sections_.size()));
  StoreU64(b + 16, out.size());
  StoreU32(b + 32, uint32_t(kHeaderBytes));
  StoreU32(b + 36, 0);  // reserved
  const span<const uint8_t> file(b, out.size());
  StoreU64(b + 24, Checksum(file, ChecksumLanes(format_, file)));
  return out;
}

// ---- reader -------------------------------------------------------------------------------

std::string SectionWhere(const SectionDesc& d, uint64_t offset) {
  return "section '" + std::string(d.name) + "' (id " + std::to_string(d.id) + ") at byte " +
         std::to_string(offset);
}

bool ReadSections(span<const uint8_t> bytes, const Format& format, std::vector<InSection>* known,
                  std::string* error, const uint64_t* computed_checksum) {
  const uint64_t size = bytes.size();
  const uint8_t* b = bytes.data();
  const std::string tag(format.tag, 4);
  auto fail = [&](const std::string& where, const std::string& what) {
    *error = where + ": " + what;
    return false;
  };
  if (size < kHeaderBytes)
    return fail("header", "the file is " + std::to_string(size) + " bytes; a " +
                              format.extension + " header is " + std::to_string(kHeaderBytes) +
                              " (truncated)");
  if (std::memcmp(b, format.tag, 4) != 0)
    return fail("header at byte 0",
                "the tag is not \"" + tag + "\" (not a " + format.what + ")");
  const uint16_t major = LoadU16(b + 4), minor = LoadU16(b + 6);
  const std::string version = std::to_string(major) + "." + std::to_string(minor);
  if (major > format.major)
    return fail("header at byte 4",
                "format version " + version + " is newer than this reader's " +
                    std::to_string(format.major) + "." + std::to_string(format.minor) +
                    " (a newer major version); " + format.rebuild);
  if (major == 0) return fail("header at byte 4", "format version " + version + " is not valid");
  const uint32_t flags = LoadU32(b + 8);
  if (flags != 0)
    return fail("header at byte 8", "flags are " + std::to_string(flags) + "; format " +
                                        std::to_string(format.major) +
                                        " defines none (expected 0)");
  if (LoadU32(b + 32) != kHeaderBytes || LoadU32(b + 36) != 0)
    return fail("header at byte 32", "header size " + std::to_string(LoadU32(b + 32)) +
                                         " / reserved " + std::to_string(LoadU32(b + 36)) +
                                         "; expected " + std::to_string(kHeaderBytes) + " / 0");
  const uint64_t section_count = LoadU32(b + 12);
  if (section_count > (size - kHeaderBytes) / kSectionEntryBytes)
    return fail("section table at byte " + std::to_string(kHeaderBytes),
                std::to_string(section_count) + " entries of " +
                    std::to_string(kSectionEntryBytes) +
                    " bytes extend past the end of the file (" + std::to_string(size) +
                    " bytes; truncated or corrupt)");
  const uint64_t table_end = kHeaderBytes + kSectionEntryBytes * section_count;

  // Every entry's bounds and counts before any payload is read.
  known->assign(format.section_count, InSection{});
  uint64_t prev_end = table_end;
  for (uint64_t i = 0; i < section_count; ++i) {
    const uint64_t at = kHeaderBytes + kSectionEntryBytes * i;
    const uint8_t* e = b + at;
    const uint32_t id = LoadU32(e), element_size = LoadU32(e + 4);
    const uint64_t offset = LoadU64(e + 8), bytes_size = LoadU64(e + 16), count = LoadU64(e + 24);
    const SectionDesc* d = FindSection(format, id);
    const std::string where =
        d ? SectionWhere(*d, offset)
          : "section table entry " + std::to_string(i) + " (unknown id " + std::to_string(id) +
                ") at byte " + std::to_string(at);
    if (offset < prev_end || offset % 8 != 0)
      return fail(where, "offset " + std::to_string(offset) +
                             " overlaps the table or the section before it, or is not a "
                             "multiple of 8 (expected at least " + std::to_string(prev_end) + ")");
    if (offset > size || bytes_size > size - offset)
      return fail(where, "its " + std::to_string(bytes_size) +
                             " bytes extend past the end of the file (" + std::to_string(size) +
                             " bytes; truncated or corrupt)");
    prev_end = offset + bytes_size;
    if (!d) continue;  // a newer minor version's section: skipped
    const size_t k = size_t(d - format.sections);
    if ((*known)[k].desc) return fail(where, "appears twice in the section table");
    if (element_size != d->element_size)
      return fail(where, "element size " + std::to_string(element_size) + "; expected " +
                             std::to_string(d->element_size));
    if (d->fixed_count && count != d->fixed_count)
      return fail(where, std::to_string(count) + " elements; expected " +
                             std::to_string(d->fixed_count));
    if (element_size > 0) {
      if (count > bytes_size / element_size || count * element_size != bytes_size)
        return fail(where, std::to_string(count) + " elements of " +
                               std::to_string(element_size) + " bytes do not make its " +
                               std::to_string(bytes_size) + " bytes");
    } else if (count >= bytes_size / 4) {  // a string table: count + 1 offsets at least
      return fail(where, std::to_string(count) + " strings need " +
                             "more than its " + std::to_string(bytes_size) + " bytes");
    }
    (*known)[k] = {d, offset, bytes_size, count, b + offset};
  }
  if (LoadU64(b + 16) != size)
    return fail("header at byte 16", "total size " + std::to_string(LoadU64(b + 16)) +
                                         " bytes; the file has " + std::to_string(size) +
                                         " (truncated or corrupt)");
  const uint64_t stored = LoadU64(b + 24);
  const uint64_t computed =
      computed_checksum ? *computed_checksum : Checksum(bytes, ChecksumLanes(format, bytes));
  if (stored != computed) {
    char hex[80];
    std::snprintf(hex, sizeof hex, "stored %016llx, computed %016llx",
                  (unsigned long long)stored, (unsigned long long)computed);
    return fail("header at byte 24",
                std::string("checksum mismatch (") + hex + "): the file is corrupt");
  }
  for (size_t k = 0; k < format.section_count; ++k) {
    const SectionDesc& d = format.sections[k];
    if (d.required && !(*known)[k].desc)
      return fail("section '" + std::string(d.name) + "' (id " + std::to_string(d.id) + ")",
                  "missing from the section table");
  }
  // Absent optional sections read as empty.
  for (size_t k = 0; k < format.section_count; ++k)
    if (!(*known)[k].desc) (*known)[k] = {&format.sections[k], 0, 0, 0, nullptr};
  return true;
}

const InSection& SectionReader::Of(uint32_t id) const {
  for (size_t i = 0; i < format_.section_count; ++i)
    if (format_.sections[i].id == id) return known_[i];
  return known_[0];  // not reached: callers ask for their format's ids
}

bool SectionReader::Fail(const InSection& s, const std::string& what) const {
  *error_ = SectionWhere(*s.desc, s.offset) + ": " + what;
  return false;
}

void SectionReader::U32s(const InSection& s, uint64_t first, uint64_t n,
                         std::vector<uint32_t>* out) const {
  const uint8_t* p = s.data + 4 * first;
  if (CopyIfNative(p, n, out)) return;
  out->resize(size_t(n));
  for (uint64_t i = 0; i < n; ++i) (*out)[size_t(i)] = LoadU32(p + 4 * i);
}

void SectionReader::F32s(const InSection& s, uint64_t first, uint64_t n,
                         std::vector<float>* out) const {
  const uint8_t* p = s.data + 4 * first;
  if (CopyIfNative(p, n, out)) return;
  out->resize(size_t(n));
  for (uint64_t i = 0; i < n; ++i) (*out)[size_t(i)] = LoadF32(p + 4 * i);
}

void SectionReader::U32s(uint32_t id, std::vector<uint32_t>* out) const {
  const InSection& s = Of(id);
  U32s(s, 0, s.count, out);
}

void SectionReader::F32s(uint32_t id, std::vector<float>* out) const {
  const InSection& s = Of(id);
  F32s(s, 0, s.count, out);
}

void SectionReader::U8s(uint32_t id, std::vector<uint8_t>* out) const {
  const InSection& s = Of(id);
  if (s.data) out->assign(s.data, s.data + s.count);
  else out->clear();
}

bool SectionReader::Strings(uint32_t id, std::vector<std::string>* out) const {
  const InSection& s = Of(id);
  if (!s.data) return true;  // optional and absent
  const uint64_t table = 4 * (s.count + 1);  // the table check made sure it fits
  const uint64_t chars = s.size - table;
  const uint8_t* c = s.data + table;
  out->clear();
  out->reserve(size_t(s.count));
  uint32_t prev = LoadU32(s.data);
  if (prev != 0) return Fail(s, "string offset 0 is " + std::to_string(prev) + "; expected 0");
  for (uint64_t i = 0; i < s.count; ++i) {
    const uint32_t next = LoadU32(s.data + 4 * (i + 1));
    if (next < prev || next > chars)
      return Fail(s, "string " + std::to_string(i) + " ends at " + std::to_string(next) +
                         ", outside [" + std::to_string(prev) + ", " + std::to_string(chars) +
                         "]");
    out->emplace_back(reinterpret_cast<const char*>(c + prev), next - prev);
    prev = next;
  }
  if (prev != chars)
    return Fail(s, "the strings hold " + std::to_string(prev) + " bytes; the section has " +
                       std::to_string(chars) + " after its offsets");
  return true;
}

namespace {

// The checks and the read of ReadFileBytes; `allocate(n)` gives the n-byte buffer to fill.
// `on_piece(end)` is called as the bytes [.., end) arrive, piece_bytes at a time.
template <class Allocate, class OnPiece>
bool ReadFileInto(const std::string& path, const char* what, size_t max_bytes,
                  const Allocate& allocate, size_t piece_bytes, const OnPiece& on_piece,
                  std::string* error) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    *error = "cannot open: no such file or not readable";
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    *error = std::string("is not a regular file (expected a ") + what + ")";
    return false;
  }
  if (uint64_t(st.st_size) > max_bytes) {
    *error = "is larger than the " + std::to_string(max_bytes >> 20) + " MiB limit for a " +
             what + " (" + std::to_string(st.st_size) + " bytes)";
    return false;
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    *error = "cannot open";
    return false;
  }
  const size_t size = size_t(st.st_size);
  uint8_t* data = allocate(size);
  size_t got = 0;
  while (got < size) {
    const size_t want = std::min(size - got, piece_bytes);
    const size_t n = std::fread(data + got, 1, want, f);
    if (n == 0) break;
    got += n;
    if (got < size && (got % 32) != 0) continue;  // pieces of whole 32-byte blocks but the last
    on_piece(got);
  }
  if (got < size) on_piece(got);  // (a short read; refused below)
  const bool more = std::fgetc(f) != EOF;  // the file grew since stat
  const bool bad = std::ferror(f) != 0;
  std::fclose(f);
  if (bad || got != size || more) {
    *error = "read error (the file changed while it was read)";
    return false;
  }
  return true;
}

}  // namespace

bool ReadFileBytes(const std::string& path, const char* what, size_t max_bytes, std::string* out,
                   std::string* error) {
  return ReadFileInto(path, what, max_bytes, [&](size_t n) {
    out->assign(n, '\0');
    return reinterpret_cast<uint8_t*>(out->data());
  }, ~size_t{0}, [](size_t) {}, error);
}

bool ReadFileBuffer(const std::string& path, const char* what, size_t max_bytes,
                    std::unique_ptr<uint8_t[]>* out, size_t* size, std::string* error) {
  *size = 0;
  const bool ok = ReadFileInto(path, what, max_bytes, [&](size_t n) {
    out->reset(new uint8_t[n ? n : 1]);  // default-initialised: not zero-filled
    *size = n;
    return out->get();
  }, ~size_t{0}, [](size_t) {}, error);
  if (!ok) *size = 0;
  return ok;
}

bool ReadFileBuffer(const std::string& path, const Format& format, size_t max_bytes,
                    std::unique_ptr<uint8_t[]>* out, size_t* size, uint64_t* checksum,
                    std::string* error) {
  *size = 0;
  std::optional<Checksummer> sum;
  size_t done = 0;
  const bool ok = ReadFileInto(path, format.what, max_bytes, [&](size_t n) {
    out->reset(new uint8_t[n ? n : 1]);  // default-initialised: not zero-filled
    *size = n;
    return out->get();
  }, size_t{1} << 20, [&](size_t end) {
    if (!sum) sum.emplace(ChecksumLanes(format, span<const uint8_t>(out->get(), end)));
    sum->Update(out->get() + done, end - done);
    done = end;
  }, error);
  if (!ok) *size = 0;
  *checksum = sum ? sum->Finish() : 0;
  return ok;
}

}  // namespace mimetic::binary
