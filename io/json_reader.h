// io/json_reader.h: one declarative reader for every JSON file format (rig, template,
// landmarks; later expressions, clips, ARKit maps).
//
// Each object kind of a format is declared once, as a table of fields: key, type, range,
// required or optional, and the expectation text of its messages. The reader parses the text
// (with a size and nesting guard), then checks the document against the tables generically:
// wrong type, out of range, missing required key, unknown key, duplicate key, numbers that do
// not fit a float. Every problem is recorded in `Diagnostics` with its JSON path
// (`muscles[3].insertion: expected array of 3 numbers, got string`); the check never stops at
// the first. Rules between fields (min <= max, unique names, phi_c < zone angle) are small
// hand-written functions run on the checked document afterwards (View::CheckBound for a bound
// given by another field). An object kind with variants (a linear or a sheet muscle) chooses
// more fields by the value of a discriminator key. The JSON Schema of a format
// is generated from the same tables (Schema), so the two cannot drift.
//
// Declaring a format (docs/rig-format.md, "The reader"):
//
//   using namespace json_reader;
//   const Object kPoint = {"a point", {
//       Number("depth").Min(0).Required().About("mm under the skin"),
//       Numbers("offset", 2, "[dx, dy], two finite numbers"),
//       Enum("side", {"left", "right"})}};
//   const Object kTop = {"a point file", {
//       Enum("format", {"my-points"}).Required(), Integer("version").Version(1).Required(),
//       Array("points", ObjectOf("", kPoint), "array of points").Required()}};
//   const Format kFormat = {"my-points", ObjectOf("", kTop, "an object {\"format\": ...}")};
//
//   Reader r(kFormat, diag);
//   if (!r.Parse(text)) return false;          // invalid JSON, too deep, too large
//   const View top = r.Check();                  // every generic problem recorded
//   if (r.stopped()) return false;               // a newer version: nothing more to say
//   for (size_t i = 0; i < top.Size("points"); ++i) {
//     const View p = top.Element("points", i);   // p.ok(): nothing wrong in points[i]
//     float depth = 0.f;
//     p.Read("depth", &depth);                   // false when absent or invalid
//   }
//   return !r.failed();
//
// Numbers: every kNumber must be finite and fit a 32-bit float. Integers (one rule for all
// formats, as in JSON Schema): a number with an integral value, so 6 and 6.0 are the integer
// 6 and 6.5 is not an integer. Literals that overflow a double (1e400) are reported with their
// path as numbers that overflow to infinity.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/diagnostics.h"
#include "core/math.h"

namespace mimetic::json_reader {

using Json = nlohmann::json;

// Checked before nlohmann parses the text (its parser and the document's destructor recurse).
inline constexpr size_t kDefaultMaxBytes = size_t{64} << 20;  // 64 MiB
inline constexpr int kDefaultMaxDepth = 64;                    // nested arrays and objects
// A huge array of bad elements is reported element by element up to this many, then summed up.
inline constexpr size_t kMaxElementErrors = 20;

// The guard Reader::Parse applies before any parser sees a text, for JSON handed to another
// parser (tinygltf's glTF JSON): "" when `text` has at most `max_bytes` bytes and nests at most
// `max_depth` levels of arrays and objects; otherwise why not ("nested deeper than 64 levels
// at line 1, column 65; expected at most 64 levels of arrays and objects").
std::string CheckJsonText(std::string_view text, size_t max_bytes = kDefaultMaxBytes,
                          int max_depth = kDefaultMaxDepth);

enum class Type { kAny, kBool, kInteger, kNumber, kString, kEnum, kArray, kObject };

// An interval for kNumber and kInteger; open or closed at each end; infinite = no bound.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;
  bool Contains(long double v) const;
  // "(0, 1]", ">= 0", "> 0", "<= 1" ("" when unbounded).
  std::string Text() const;
};

struct Object;

// One key of an object (or the element of an array: key ""). Made by the functions below and
// refined with the chained setters: Number("width").Above(0).Required().About("mesh units").
struct Field {
  std::string key;
  Type type = Type::kAny;
  // What was expected, after "expected " in messages ("a finite number > 0"); "" = made from
  // the type and range (Expect()).
  std::string expect;
  // Meaning and units ("Ws, mesh units"): added to "missing required key" messages and to the
  // schema's description.
  std::string about;
  // What to expect when the type is wrong, where it differs from `expect`.
  std::string type_expect;
  bool required = false;
  // The range also depends on another field, so the format's code checks it (with a message
  // naming the other value); the generic check verifies the type only. `range` is the part
  // that holds regardless (the schema's bound).
  bool cross_field = false;
  int version = 0;              // > 0: the format's version (Version())
  bool newer_version_stops = true;
  Range range;                  // kNumber, kInteger
  bool non_empty = false;       // kString, kArray
  size_t count = 0;             // kArray: exact length; 0 = any
  std::vector<std::string> choices;  // kEnum
  std::string unknown_choice;   // kEnum: message for another string; "{}" stands for it
  std::vector<Field> element;   // kArray: one entry, the element's field
  const Object* object = nullptr;  // kObject: its table; null = any object, checked by hand

  Field& Required() { required = true; return *this; }
  Field& About(std::string text) { about = std::move(text); return *this; }
  Field& TypeText(std::string text) { type_expect = std::move(text); return *this; }
  Field& CrossField() { cross_field = true; return *this; }
  Field& Min(double v) { range.min = v; range.min_open = false; return *this; }
  Field& Above(double v) { range.min = v; range.min_open = true; return *this; }
  Field& Max(double v) { range.max = v; range.max_open = false; return *this; }
  Field& Below(double v) { range.max = v; range.max_open = true; return *this; }
  Field& NonEmpty() { non_empty = true; return *this; }
  Field& Count(size_t n) { count = n; return *this; }
  Field& UnknownChoice(std::string text) { unknown_choice = std::move(text); return *this; }
  // The format's version field: `supported` reads; a newer integer gets "unsupported version
  // N: this build reads version `supported`", and the rest of the file is not checked when
  // `stops` (a newer file may have keys and rules this build does not know).
  Field& Version(int supported, bool stops = true);

  // The expectation text of messages: `expect`, or one made from type and range.
  std::string Expect() const;
};

Field Any(std::string key);  // present or absent; the format's code checks it
Field Bool(std::string key, std::string expect = "");
Field Integer(std::string key, std::string expect = "");  // read into an int unless widened
Field Number(std::string key, std::string expect = "");
Field String(std::string key, std::string expect = "");
Field Enum(std::string key, std::vector<std::string> choices, std::string expect = "");
Field Array(std::string key, Field element, std::string expect = "");
// An array of exactly `n` finite numbers (coordinates).
Field Numbers(std::string key, size_t n, std::string expect = "");
Field ObjectOf(std::string key, const Object& object, std::string expect = "");
Field AnyObject(std::string key, std::string expect = "");

// An unknown key that is a known mistake: `text` is added to the unknown-key message, or
// replaces it (`replaces`).
struct KeyNote {
  std::string key{};
  std::string text{};
  bool replaces = false;
};

// The table of one object kind. With variants, the value of the enum field `variant_key`
// chooses more fields (a linear or a sheet muscle); while it is missing or invalid, the keys
// of all variants are allowed and only `fields` are checked.
struct Object {
  struct Variant {
    std::string value;
    const Object* object;
  };
  std::string owner{};         // names the object in unknown-key messages: "a linear muscle"
  std::vector<Field> fields{};
  std::string variant_key{};
  std::vector<Variant> variants{};
  std::vector<KeyNote> notes{};
  std::string description{};   // for the schema
};

// The wording of the generic messages. The formats predate the reader and their tests pin
// their wording; new formats use the default.
struct Wording {
  bool is_first = false;              // "is G; expected E" instead of "expected E, got G"
  bool value_in_type_errors = false;  // "got \"thick\"" instead of "got string"
  bool unknown_key_in_owner = false;  // "unknown key in OWNER; expected one of: a, b"
                                      // instead of "unknown key \"k\"; allowed keys for OWNER: a, b"
};

struct Format {
  std::string name{};   // "mimetic-rig": names the format in messages and the schema
  Field root{};         // ObjectOf("", top, "...")
  Wording wording{};
  std::string title{};  // schema title
  size_t max_bytes = kDefaultMaxBytes;
  int max_depth = kDefaultMaxDepth;
};

class Reader;

// A checked object of the document (or an invalid / absent one: ok() false, no members).
class View {
 public:
  View() = default;
  bool ok() const { return reader_ && value_ && good_; }
  bool present() const { return value_ != nullptr; }
  const std::string& path() const { return path_; }
  const Json* value() const { return value_; }
  // The chosen variant's value ("linear"), "" when none.
  const std::string& variant() const { return variant_; }

  std::string Path(const std::string& key) const;
  // A member as written (null when absent); as checked (null when absent or invalid).
  const Json* Raw(const std::string& key) const;
  const Json* Get(const std::string& key) const;
  bool Has(const std::string& key) const { return Raw(key) != nullptr; }
  // The declaration of a member (null when not declared for this object).
  const Field* FieldOf(const std::string& key) const;

  // Each returns false (leaving *out alone) when the member is absent or invalid.
  bool Read(const std::string& key, bool* out) const;
  bool Read(const std::string& key, int* out) const;
  bool Read(const std::string& key, int64_t* out) const;
  bool Read(const std::string& key, float* out) const;
  bool Read(const std::string& key, double* out) const;
  bool Read(const std::string& key, std::string* out) const;
  bool Read(const std::string& key, float2* out) const;
  bool Read(const std::string& key, float3* out) const;
  // Arrays of points ([[x, y], ...] and [[x, y, z], ...]).
  bool Read(const std::string& key, std::vector<float2>* out) const;
  bool Read(const std::string& key, std::vector<float3>* out) const;
  // The index of an enum member's value in its choices.
  bool Choice(const std::string& key, size_t* out) const;

  // A rule between fields for a number member: it must lie in its declared range and below
  // (`upper`) or above `*bound` when `bound` is given (the other field was read). The message
  // is the field's expectation with `name` followed by its value: "expected a number in [0,
  // zone_angle_deg = 40) (degrees), got 45". False when reported; true when fine or absent.
  bool CheckBound(const std::string& key, const std::string& name, const float* bound,
                  bool upper = true) const;

  // A member object, and the elements of a member array (of objects or values).
  View Member(const std::string& key) const;
  size_t Size(const std::string& key) const;
  View Element(const std::string& key, size_t i) const;

 private:
  friend class Reader;
  static View Make(const Reader* reader, const Json* v, const Object* o, std::string path);
  const Reader* reader_ = nullptr;
  const Json* value_ = nullptr;
  const Object* object_ = nullptr;
  const Object* chosen_ = nullptr;
  std::string variant_;
  std::string path_;
  bool good_ = false;
};

// Reads one document of a format. Not copyable (views point into it).
class Reader {
 public:
  // `where` prefixes every location ("lm.json" -> "lm.json: points[3]"); "" = none.
  Reader(const Format& format, Diagnostics* diag, std::string where = "");
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  // Size and nesting guard, overflowing literals, duplicate keys, then nlohmann's parser.
  // False (with the reason recorded) when there is no document to check.
  bool Parse(std::string_view text);
  // The generic check of the whole document against the format's tables.
  View Check();
  // True when a newer version stopped the check (Field::Version): nothing more to say.
  bool stopped() const { return stopped_; }
  // True when any error was recorded since construction.
  bool failed() const { return diag_->ErrorCount() != errors_before_; }

  // Records a problem found by a format's own check.
  void Error(const std::string& path, const std::string& what) const;
  // "expected E, got G" (or "is G; expected E") for `value`.
  void Expected(const std::string& path, const std::string& expect, const Json& value) const;

  const Json& root() const;
  const Format& format() const { return format_; }
  bool IsGood(const Json* v) const { return v && !bad_.count(v); }

 private:
  friend class View;
  void CheckValue(const Json& v, const std::string& path, const Field& f);
  void CheckObject(const Json& v, const std::string& path, const Object& o);
  void CheckArray(const Json& v, const std::string& path, const Field& f);
  void CheckNumber(const Json& v, const std::string& path, const Field& f);
  bool CheckVersion(const Json& v, const std::string& path, const Field& f);
  void TypeError(const Json& v, const std::string& path, const Field& f);
  void Missing(const Json& object, const std::string& path, const Field& f);
  void Fail(const Json& v, const std::string& path, const std::string& what);
  std::string Where(const std::string& path) const;

  const Format& format_;
  Diagnostics* diag_;
  std::string where_;
  size_t errors_before_;
  Json* root_ = nullptr;
  std::vector<const Json*> stack_;      // values being checked, outermost first
  std::unordered_set<const Json*> bad_;  // values with a problem at or below them
  int mute_ = 0;                        // > 0: problems are marked, not reported
  bool stopped_ = false;
};

// Messages' pieces, for the formats' own checks.
std::string Key(const std::string& path, const std::string& key);  // "a.b"
std::string Index(const std::string& path, size_t i);              // "a[3]"
std::string Quoted(const std::string& s);  // JSON string literal, escaped, at most 60 bytes
// What a value is, for "got ...": numbers and strings by value, containers by type and size.
// Never recursive: an array prints as "array of N elements".
std::string Describe(const Json& v);
std::string TypeName(const Json& v);  // "null", "boolean", "number", "string", "array", "object"
std::string FormatFloat(float f);     // the shortest text that reads back as `f`
// The shortest decimal (as a double) that reads back as `f`, for writing JSON: 0.1f is written
// "0.1", not "0.10000000149011612". Falls back to the exact double value of `f`.
double ShortestDecimal(float f);
std::string JoinList(const std::vector<std::string>& items, bool quote);

// The boundary of a format's Parse function: runs `parse`; an exception (none is expected, the
// reader does not throw) becomes the error "<what>: <its text>" instead of escaping.
bool NoThrow(Diagnostics* diag, const std::string& what, const std::function<bool()>& parse);
// A format's Load function: reads the file at `path` and runs `parse` on its text; the messages
// of `parse` are added to `diag` prefixed with `path`. `diag` may be null.
bool ParseFile(const std::string& path, Diagnostics* diag,
               const std::function<bool(const std::string& text, Diagnostics* local)>& parse);

// The JSON Schema (draft-07) of a format, made from its tables.
Json Schema(const Format& format);

}  // namespace mimetic::json_reader
