// io/json_reader.cpp: the declarative JSON reader (io/json_reader.h): guard, parse, generic
// check against field tables, schema. Nothing throws out of Reader::Parse and Reader::Check
// (nlohmann::json exceptions are caught at the boundary).
#include "io/json_reader.h"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <map>
#include <set>
#include <system_error>

#include <nlohmann/json.hpp>

#include "core/file_util.h"

namespace mimetic::json_reader {
namespace {

// 1e308 stands for a literal that overflowed a double (ReplaceOverflowingNumbers).
constexpr double kOverflowSentinel = 1e308;

bool IsIntegral(const Json& v) {
  if (v.is_number_integer() || v.is_number_unsigned()) return true;
  if (!v.is_number_float()) return false;
  const double d = v.get<double>();
  return std::isfinite(d) && d == std::floor(d);
}

// The exact value of a number (long double holds every int64 and uint64).
long double Exact(const Json& v) {
  if (v.is_number_unsigned()) return static_cast<long double>(v.get<uint64_t>());
  if (v.is_number_integer()) return static_cast<long double>(v.get<int64_t>());
  return static_cast<long double>(v.get<double>());
}

std::string ShortestDouble(double d) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, d);
  return res.ec == std::errc() ? std::string(buf, res.ptr) : std::to_string(d);
}

// ---------------------------------------------------------------------------------------------
// Before parsing: nesting depth, and number literals that overflow a double.
//
// nlohmann::json refuses such literals (out_of_range.406) and stops parsing, so `1e999` would be
// reported without its JSON path. Each is replaced by `1e308` (or `-1e308`), padded with spaces
// to the same length so that the line and column of any later parse error stay the same; the
// check then reports it, with its path, as a number that overflows to infinity.

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?
bool IsJsonNumber(std::string_view s) {
  size_t i = 0;
  if (i < s.size() && s[i] == '-') ++i;
  if (i >= s.size() || !IsDigit(s[i])) return false;
  if (s[i] == '0') {
    ++i;
  } else {
    while (i < s.size() && IsDigit(s[i])) ++i;
  }
  if (i < s.size() && s[i] == '.') {
    ++i;
    if (i >= s.size() || !IsDigit(s[i])) return false;
    while (i < s.size() && IsDigit(s[i])) ++i;
  }
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (i >= s.size() || !IsDigit(s[i])) return false;
    while (i < s.size() && IsDigit(s[i])) ++i;
  }
  return i == s.size();
}

// True when the (valid JSON) number literal is too large in magnitude for a double.
bool OverflowsDouble(std::string_view s) {
  double value = 0.0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), value);
  if (res.ec != std::errc::result_out_of_range) return !std::isfinite(value) && res.ec == std::errc();
  // Out of range is overflow or underflow: decide by the decimal order of magnitude.
  size_t i = s[0] == '-' ? 1 : 0;
  long long int_digits = 0, first_nonzero = -1, pos = 0;
  bool in_fraction = false;
  for (; i < s.size() && s[i] != 'e' && s[i] != 'E'; ++i) {
    if (s[i] == '.') {
      in_fraction = true;
      continue;
    }
    if (!in_fraction) ++int_digits;
    if (s[i] != '0' && first_nonzero < 0) first_nonzero = pos;
    ++pos;
  }
  if (first_nonzero < 0) return false;  // zero
  long long exponent = 0;
  bool negative = false;
  if (i < s.size()) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
    for (; i < s.size(); ++i) exponent = std::min(exponent * 10 + (s[i] - '0'), 1000000000LL);
  }
  if (negative) exponent = -exponent;
  // value = 0.d1d2... * 10^(int_digits - first_nonzero + exponent)
  return int_digits - first_nonzero + exponent > 0;
}

// Line and column (1-based) of byte offset `byte` (0-based).
void LineColumn(std::string_view text, size_t byte, size_t* line, size_t* column) {
  *line = 1;
  *column = 1;
  for (size_t i = 0; i < std::min(byte, text.size()); ++i) {
    if (text[i] == '\n') {
      ++*line;
      *column = 1;
    } else {
      ++*column;
    }
  }
}

std::string At(std::string_view text, size_t byte) {
  size_t line = 0, column = 0;
  LineColumn(text, byte, &line, &column);
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Replaces overflowing literals in `text`; returns the byte offset where nesting first exceeds
// `max_depth`, or npos.
size_t Prepare(std::string* text, int max_depth) {
  std::string& out = *text;
  bool in_string = false;
  int depth = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const char c = out[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
      continue;
    }
    if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
      continue;
    }
    if (c == ']' || c == '}') {
      --depth;
      continue;
    }
    if (c != '-' && !IsDigit(c)) continue;
    size_t j = i;
    while (j < out.size() && (IsDigit(out[j]) || out[j] == '-' || out[j] == '+' || out[j] == '.' ||
                              out[j] == 'e' || out[j] == 'E'))
      ++j;
    const std::string_view literal(out.data() + i, j - i);
    if (IsJsonNumber(literal) && OverflowsDouble(literal)) {
      // The shortest overflowing literal is 5 characters ("9e308"), 6 with a minus sign.
      const std::string repl = literal[0] == '-' ? "-1e308" : "1e308";
      if (repl.size() <= literal.size())
        out.replace(i, literal.size(), repl + std::string(literal.size() - repl.size(), ' '));
    }
    i = j - 1;
  }
  return std::string::npos;
}

// The byte offset where nesting first exceeds `max_depth`, or npos (strings skipped).
size_t TooDeepAt(std::string_view text, int max_depth) {
  bool in_string = false;
  int depth = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string_view::npos;
}

// What the text's top-level value is, from its first character (for a document not parsed).
std::string FirstValueType(std::string_view text) {
  const size_t i = text.find_first_not_of(" \t\r\n");
  if (i == std::string_view::npos) return "nothing";
  switch (text[i]) {
    case '{': return "object";
    case '[': return "array";
    case '"': return "string";
    case 't':
    case 'f': return "boolean";
    case 'n': return "null";
    default: return "number";
  }
}

// `s` with invalid UTF-8 replaced by U+FFFD (parse errors quote the bytes last read).
std::string ValidUtf8(const std::string& s) {
  try {
    return Json::parse(Json(s).dump(-1, ' ', false, Json::error_handler_t::replace))
        .get<std::string>();
  } catch (const std::exception&) {
    return "(unprintable)";
  }
}

// The part of nlohmann's parse error message after its position ("syntax error while ...").
std::string ParseErrorDetail(const std::string& what) {
  const size_t column = what.find("column ");
  if (column != std::string::npos) {
    const size_t colon = what.find(": ", column);
    if (colon != std::string::npos) return ValidUtf8(what.substr(colon + 2));
  }
  const size_t colon = what.find("parse error: ");
  if (colon != std::string::npos) return ValidUtf8(what.substr(colon + 13));
  return ValidUtf8(what);
}

// Duplicate object keys (nlohmann keeps the last one silently): found with a parser callback
// that tracks the JSON path of the value being parsed.
class DuplicateKeyTracker {
 public:
  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start: Push(false); break;
      case Json::parse_event_t::array_start: Push(true); break;
      case Json::parse_event_t::key:
        if (!stack_.empty() && parsed.is_string()) {
          Frame& top = stack_.back();
          top.key = parsed.get<std::string>();
          if (!top.keys.insert(top.key).second) duplicates.push_back(Path());
        }
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        if (!stack_.empty()) stack_.pop_back();
        ElementDone();
        break;
      case Json::parse_event_t::value: ElementDone(); break;
    }
    return true;
  }

  std::vector<std::string> duplicates;  // JSON paths of repeated keys

 private:
  struct Frame {
    bool is_array = false;
    size_t index = 0;
    std::string key;
    std::set<std::string> keys;
  };
  void Push(bool is_array) {
    stack_.emplace_back();
    stack_.back().is_array = is_array;
  }
  void ElementDone() {
    if (!stack_.empty() && stack_.back().is_array) ++stack_.back().index;
  }
  std::string Path() const {
    std::string p;
    for (const Frame& f : stack_) p = f.is_array ? Index(p, f.index) : Key(p, f.key);
    return p;
  }
  std::vector<Frame> stack_;
};

const Field* FindField(const std::vector<Field>& fields, const std::string& key) {
  for (const Field& f : fields)
    if (f.key == key) return &f;
  return nullptr;
}

// The variant of `o` chosen by `v`'s discriminator, or null.
const Object* ChosenVariant(const Object& o, const Json& v, const Reader& reader) {
  if (o.variant_key.empty() || !v.is_object()) return nullptr;
  const auto it = v.find(o.variant_key);
  if (it == v.end() || !it->is_string() || !reader.IsGood(&*it)) return nullptr;
  for (const Object::Variant& var : o.variants)
    if (var.value == it->get_ref<const std::string&>()) return var.object;
  return nullptr;
}

// Every key allowed in `o` (with `chosen`, or all variants when null), in declaration order.
std::vector<std::string> AllowedKeys(const Object& o, const Object* chosen) {
  std::vector<std::string> keys;
  auto add = [&keys](const Object& obj) {
    for (const Field& f : obj.fields)
      if (std::find(keys.begin(), keys.end(), f.key) == keys.end()) keys.push_back(f.key);
  };
  add(o);
  if (chosen) {
    add(*chosen);
  } else {
    for (const Object::Variant& var : o.variants) add(*var.object);
  }
  return keys;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Text helpers.

std::string Key(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string Index(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string Quoted(const std::string& s) {
  constexpr size_t kMax = 60;
  const std::string text = s.size() > kMax ? s.substr(0, kMax) : s;
  std::string out = Json(text).dump(-1, ' ', false, Json::error_handler_t::replace);
  if (s.size() > kMax) out.insert(out.size() - 1, "...");
  return out;
}

std::string TypeName(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return "boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "number";
    case Json::value_t::string: return "string";
    case Json::value_t::array: return "array";
    case Json::value_t::object: return "object";
    case Json::value_t::binary: return "binary";
    case Json::value_t::discarded: return "nothing";
  }
  return "unknown";
}

std::string Describe(const Json& v) {
  if (v.is_number()) {
    if (v.is_number_float() && std::fabs(v.get<double>()) >= kOverflowSentinel)
      return "a number that overflows to infinity";
    return v.dump();
  }
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    return s.empty() ? "empty string" : Quoted(s);
  }
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_array()) return "array of " + std::to_string(v.size()) + " elements";
  return TypeName(v);
}

std::string FormatFloat(float f) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  return res.ec == std::errc() ? std::string(buf, res.ptr) : std::to_string(f);
}

double ShortestDecimal(float f) {
  if (!std::isfinite(f)) return static_cast<double>(f);
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  if (res.ec != std::errc()) return static_cast<double>(f);
  double d = 0.0;
  const auto back = std::from_chars(buf, res.ptr, d);
  if (back.ec != std::errc() || static_cast<float>(d) != f) return static_cast<double>(f);
  return d;
}

std::string JoinList(const std::vector<std::string>& items, bool quote) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) out += ", ";
    out += quote ? Quoted(items[i]) : items[i];
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Declarations.

bool Range::Contains(long double v) const {
  if (min_open ? !(v > min) : !(v >= min)) return false;
  if (max_open ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string Range::Text() const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max)
    return std::string(min_open ? "(" : "[") + ShortestDouble(min) + ", " + ShortestDouble(max) +
           (max_open ? ")" : "]");
  if (has_min) return std::string(min_open ? "> " : ">= ") + ShortestDouble(min);
  if (has_max) return std::string(max_open ? "< " : "<= ") + ShortestDouble(max);
  return "";
}

Field& Field::Version(int supported, bool stops) {
  version = supported;
  newer_version_stops = stops;
  range = Range{};
  return Min(supported).Max(supported);
}

std::string Field::Expect() const {
  if (!expect.empty()) return expect;
  switch (type) {
    case Type::kAny: return "a value";
    case Type::kBool: return "boolean (true or false)";
    case Type::kInteger:
    case Type::kNumber: {
      Range r = range;
      if (type == Type::kInteger) {  // the bounds of an int are implied
        if (r.min <= INT_MIN) r.min = -INFINITY;
        if (r.max >= INT_MAX) r.max = INFINITY;
      }
      const std::string noun = type == Type::kInteger ? "an integer" : "a finite number";
      const std::string text = r.Text();
      if (text.empty()) return noun;
      if (text[0] == '(' || text[0] == '[')
        return (type == Type::kInteger ? "an integer in " : "a number in ") + text;
      return noun + " " + text;
    }
    case Type::kString: return non_empty ? "non-empty string" : "string";
    case Type::kEnum:
      return choices.size() == 1 ? Quoted(choices[0]) : "one of " + JoinList(choices, true);
    case Type::kArray: {
      const bool numbers = !element.empty() && element[0].type == Type::kNumber;
      if (count) return "array of " + std::to_string(count) + (numbers ? " numbers" : " elements");
      return std::string(non_empty ? "non-empty array" : "array") + (numbers ? " of numbers" : "");
    }
    case Type::kObject: return "object";
  }
  return "a value";
}

namespace {
Field Make(std::string key, Type type, std::string expect) {
  Field f;
  f.key = std::move(key);
  f.type = type;
  f.expect = std::move(expect);
  return f;
}
}  // namespace

Field Any(std::string key) { return Make(std::move(key), Type::kAny, ""); }
Field Bool(std::string key, std::string expect) {
  return Make(std::move(key), Type::kBool, std::move(expect));
}
Field Integer(std::string key, std::string expect) {
  Field f = Make(std::move(key), Type::kInteger, std::move(expect));
  return f.Min(INT_MIN).Max(INT_MAX);
}
Field Number(std::string key, std::string expect) {
  return Make(std::move(key), Type::kNumber, std::move(expect));
}
Field String(std::string key, std::string expect) {
  return Make(std::move(key), Type::kString, std::move(expect));
}
Field Enum(std::string key, std::vector<std::string> choices, std::string expect) {
  Field f = Make(std::move(key), Type::kEnum, std::move(expect));
  f.choices = std::move(choices);
  return f;
}
Field Array(std::string key, Field element, std::string expect) {
  Field f = Make(std::move(key), Type::kArray, std::move(expect));
  f.element.push_back(std::move(element));
  return f;
}
Field Numbers(std::string key, size_t n, std::string expect) {
  return Array(std::move(key), Number(""), std::move(expect)).Count(n);
}
Field ObjectOf(std::string key, const Object& object, std::string expect) {
  Field f = Make(std::move(key), Type::kObject, std::move(expect));
  f.object = &object;
  return f;
}
Field AnyObject(std::string key, std::string expect) {
  return Make(std::move(key), Type::kObject, std::move(expect));
}

// ---------------------------------------------------------------------------------------------
// The reader.

Reader::Reader(const Format& format, Diagnostics* diag, std::string where)
    : format_(format), diag_(diag), where_(std::move(where)), errors_before_(diag->ErrorCount()) {}

Reader::~Reader() { delete root_; }

const Json& Reader::root() const {
  static const Json kNull;
  return root_ ? *root_ : kNull;
}

std::string Reader::Where(const std::string& path) const {
  if (where_.empty()) return path;
  return path.empty() ? where_ : where_ + ": " + path;
}

void Reader::Error(const std::string& path, const std::string& what) const {
  diag_->Error(Where(path), what);
}

void Reader::Expected(const std::string& path, const std::string& expect,
                      const Json& value) const {
  const std::string got = Describe(value);
  if (!format_.wording.is_first) {
    Error(path, "expected " + expect + ", got " + got);
  } else {
    Error(path, std::string(path.empty() ? "top level is " : "is ") + got + "; expected " + expect);
  }
}

void Reader::Fail(const Json& v, const std::string& path, const std::string& what) {
  bad_.insert(&v);
  for (const Json* s : stack_) bad_.insert(s);
  if (mute_ == 0) Error(path, what);
}

bool Reader::Parse(std::string_view text) {
  try {
    const Field& root = format_.root;
    auto refuse = [&](const std::string& why) {
      Error("", why);
      // The top-level value's type is known from its first character.
      const std::string got = FirstValueType(text);
      if (root.type == Type::kObject && got != "object" && got != "nothing") {
        const std::string expect = root.Expect();
        Error("", format_.wording.is_first ? "top level is " + got + "; expected " + expect
                                           : "expected " + expect + ", got " + got);
      }
      return false;
    };
    if (text.size() > format_.max_bytes)
      return refuse("the text is " + std::to_string(text.size()) + " bytes; expected at most " +
                    std::to_string(format_.max_bytes) + " bytes (" + format_.name + " file)");
    std::string prepared(text);
    const size_t too_deep = Prepare(&prepared, format_.max_depth);
    if (too_deep != std::string::npos)
      return refuse("nested deeper than " + std::to_string(format_.max_depth) + " levels at " +
                    At(text, too_deep) + "; expected at most " +
                    std::to_string(format_.max_depth) + " levels of arrays and objects");
    DuplicateKeyTracker tracker;
    Json parsed;
    try {
      Json::parser_callback_t callback = [&tracker](int depth, Json::parse_event_t event,
                                                    Json& value) {
        return tracker(depth, event, value);
      };
      parsed = Json::parse(prepared, callback, /*allow_exceptions=*/true,
                           /*ignore_comments=*/false);
    } catch (const Json::parse_error& e) {
      Error("", "invalid JSON at " + At(prepared, e.byte > 0 ? e.byte - 1 : 0) + ": " +
                    ParseErrorDetail(e.what()) + " (not valid JSON; expected a " + format_.name +
                    " file)");
      return false;
    }
    for (const std::string& p : tracker.duplicates)
      Error(p, "duplicate key; expected each key once per object");
    root_ = new Json(std::move(parsed));
    return true;
  } catch (const std::exception& e) {
    Error("", std::string("not valid JSON: ") + e.what());
  }
  return false;
}

View Reader::Check() {
  if (!root_) return View();
  stack_.clear();
  CheckValue(*root_, "", format_.root);
  return View::Make(this, root_, format_.root.object, "");
}

void Reader::TypeError(const Json& v, const std::string& path, const Field& f) {
  const std::string expect = f.type_expect.empty() ? f.Expect() : f.type_expect;
  // A wrong value of the right kind is shown by value (6.5 for an integer, "yes" for a boolean,
  // a string that is not a choice); otherwise by its type, unless the wording shows values.
  const bool by_value = format_.wording.value_in_type_errors || f.type == Type::kBool ||
                        f.type == Type::kEnum || (f.type == Type::kInteger && v.is_number());
  const std::string got = by_value || v.is_array() ? Describe(v) : TypeName(v);
  if (!format_.wording.is_first)
    Fail(v, path, "expected " + expect + ", got " + got);
  else
    Fail(v, path, std::string(path.empty() ? "top level is " : "is ") + got + "; expected " + expect);
}

void Reader::CheckValue(const Json& v, const std::string& path, const Field& f) {
  if (stopped_) return;
  stack_.push_back(&v);
  auto range_error = [&](const std::string& got) {
    if (!format_.wording.is_first)
      Fail(v, path, "expected " + f.Expect() + ", got " + got);
    else
      Fail(v, path, "is " + got + "; expected " + f.Expect());
  };
  switch (f.type) {
    case Type::kAny: break;
    case Type::kBool:
      if (!v.is_boolean()) TypeError(v, path, f);
      break;
    case Type::kString:
      if (!v.is_string()) TypeError(v, path, f);
      else if (f.non_empty && v.get_ref<const std::string&>().empty()) range_error("empty string");
      break;
    case Type::kEnum: {
      const bool known = v.is_string() && std::find(f.choices.begin(), f.choices.end(),
                                                    v.get<std::string>()) != f.choices.end();
      if (known) break;
      if (v.is_string() && !f.unknown_choice.empty()) {
        std::string what = f.unknown_choice;
        const size_t at = what.find("{}");
        if (at != std::string::npos) what.replace(at, 2, Describe(v));
        Fail(v, path, what);
      } else {
        TypeError(v, path, f);
      }
      break;
    }
    case Type::kInteger:
      if (!v.is_number() || !IsIntegral(v)) {
        TypeError(v, path, f);
      } else if (f.version > 0) {
        CheckVersion(v, path, f);
      } else if (!f.cross_field && !f.range.Contains(Exact(v))) {
        range_error(Describe(v));
      }
      break;
    case Type::kNumber: CheckNumber(v, path, f); break;
    case Type::kArray: CheckArray(v, path, f); break;
    case Type::kObject:
      if (!v.is_object()) TypeError(v, path, f);
      else if (f.object) CheckObject(v, path, *f.object);
      break;
  }
  stack_.pop_back();
}

void Reader::CheckNumber(const Json& v, const std::string& path, const Field& f) {
  if (!v.is_number()) return TypeError(v, path, f);
  const double d = v.get<double>();
  const float x = static_cast<float>(d);
  std::string got;
  if (std::fabs(d) >= kOverflowSentinel) got = Describe(v);
  else if (!std::isfinite(x)) got = "a number too large for a float (it overflows to infinity)";
  else if (!f.cross_field && !f.range.Contains(x)) got = Describe(v);
  else return;
  if (!format_.wording.is_first) Fail(v, path, "expected " + f.Expect() + ", got " + got);
  else Fail(v, path, "is " + got + "; expected " + f.Expect());
}

bool Reader::CheckVersion(const Json& v, const std::string& path, const Field& f) {
  const long double x = Exact(v);
  if (x == f.version) return true;
  if (x > f.version && x <= 1e9) {
    const std::string n = std::to_string(f.version);
    Fail(v, path, "unsupported version " + v.dump() + ": this build reads version " + n +
                      " (it supports version " + n + " only)");
    if (f.newer_version_stops) stopped_ = true;
    return false;
  }
  if (!format_.wording.is_first) Fail(v, path, "expected " + f.Expect() + ", got " + Describe(v));
  else Fail(v, path, "is " + Describe(v) + "; expected " + f.Expect());
  return false;
}

void Reader::CheckArray(const Json& v, const std::string& path, const Field& f) {
  if (!v.is_array()) return TypeError(v, path, f);
  if ((f.count && v.size() != f.count) || (f.non_empty && v.empty())) {
    if (!format_.wording.is_first)
      Fail(v, path, "expected " + f.Expect() + ", got " + Describe(v));
    else
      Fail(v, path, "has " + std::to_string(v.size()) + " entries; expected " + f.Expect());
    return;
  }
  if (f.element.empty()) return;
  const Field& e = f.element[0];
  size_t bad = 0;
  for (size_t i = 0; i < v.size() && !stopped_; ++i) {
    if (bad >= kMaxElementErrors) ++mute_;
    CheckValue(v[i], Index(path, i), e);
    if (bad >= kMaxElementErrors) --mute_;
    if (!IsGood(&v[i])) ++bad;
  }
  if (bad > kMaxElementErrors) {
    Error(path, std::to_string(bad - kMaxElementErrors) +
                    " more invalid elements not listed; expected each " + e.Expect());
  }
}

void Reader::Missing(const Json& object, const std::string& path, const Field& f) {
  Fail(object, Key(path, f.key), "missing required key; expected " + f.Expect() +
                                     (f.about.empty() ? "" : " (" + f.about + ")"));
}

void Reader::CheckObject(const Json& v, const std::string& path, const Object& o) {
  // The version first: a newer file may have keys and rules this build does not know.
  for (const Field& f : o.fields) {
    if (f.version == 0) continue;
    const auto it = v.find(f.key);
    if (it != v.end()) CheckValue(*it, Key(path, f.key), f);
    else if (f.required) Missing(v, path, f);
    if (stopped_) return;
  }
  // The variant, then the keys it allows.
  if (!o.variant_key.empty()) {
    const auto it = v.find(o.variant_key);
    const Field* f = FindField(o.fields, o.variant_key);
    if (it != v.end() && f) CheckValue(*it, Key(path, o.variant_key), *f);
  }
  const Object* chosen = ChosenVariant(o, v, *this);
  const std::vector<std::string> allowed = AllowedKeys(o, chosen);
  const std::string& owner = chosen ? chosen->owner : o.owner;
  for (auto it = v.begin(); it != v.end(); ++it) {
    if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end()) continue;
    const KeyNote* note = nullptr;
    for (const Object* obj : {&o, chosen})
      if (obj)
        for (const KeyNote& n : obj->notes)
          if (n.key == it.key()) note = &n;
    const std::string where = Key(path, it.key());
    if (note && note->replaces) {
      Fail(v, where, note->text);
      continue;
    }
    const std::string extra = note ? " " + note->text : "";
    if (format_.wording.unknown_key_in_owner) {
      Fail(v, where, "unknown key in " + owner + extra + "; expected one of: " +
                         JoinList(allowed, false));
    } else {
      Fail(v, where, "unknown key " + Quoted(it.key()) + extra + "; allowed keys" +
                         (owner.empty() ? std::string() : " for " + owner) + ": " +
                         JoinList(allowed, false));
    }
  }
  // The fields, in declaration order.
  auto check_fields = [&](const Object& obj) {
    for (const Field& f : obj.fields) {
      if (stopped_) return;
      if (f.version > 0 || (&obj == &o && f.key == o.variant_key)) continue;
      const auto it = v.find(f.key);
      if (it != v.end()) {
        CheckValue(*it, Key(path, f.key), f);
      } else if (f.required) {
        Missing(v, path, f);
      }
    }
  };
  if (!o.variant_key.empty() && !v.contains(o.variant_key)) {
    if (const Field* f = FindField(o.fields, o.variant_key); f && f->required) Missing(v, path, *f);
  }
  check_fields(o);
  if (chosen) check_fields(*chosen);
}

// ---------------------------------------------------------------------------------------------
// Views.

std::string View::Path(const std::string& key) const { return Key(path_, key); }

const Field* View::FieldOf(const std::string& key) const {
  const Field* f = object_ ? FindField(object_->fields, key) : nullptr;
  if (!f && chosen_) f = FindField(chosen_->fields, key);
  return f;
}

const Json* View::Raw(const std::string& key) const {
  if (!value_ || !value_->is_object()) return nullptr;
  const auto it = value_->find(key);
  return it == value_->end() ? nullptr : &*it;
}

const Json* View::Get(const std::string& key) const {
  const Json* v = Raw(key);
  return v && reader_->IsGood(v) && FieldOf(key) ? v : nullptr;
}

bool View::Read(const std::string& key, bool* out) const {
  const Json* v = Get(key);
  if (!v || !v->is_boolean()) return false;
  *out = v->get<bool>();
  return true;
}

bool View::Read(const std::string& key, int64_t* out) const {
  const Json* v = Get(key);
  if (!v || !v->is_number() || !IsIntegral(*v)) return false;
  const long double x = Exact(*v);
  if (!(x >= static_cast<long double>(INT64_MIN) && x < 9223372036854775808.0L)) return false;
  *out = v->is_number_float() ? static_cast<int64_t>(v->get<double>())
         : v->is_number_unsigned() ? static_cast<int64_t>(v->get<uint64_t>())
                                   : v->get<int64_t>();
  return true;
}

bool View::Read(const std::string& key, int* out) const {
  int64_t x = 0;
  if (!Read(key, &x) || x < INT_MIN || x > INT_MAX) return false;
  *out = static_cast<int>(x);
  return true;
}

bool View::Read(const std::string& key, double* out) const {
  const Json* v = Get(key);
  if (!v || !v->is_number()) return false;
  *out = v->get<double>();
  return true;
}

bool View::Read(const std::string& key, float* out) const {
  double d = 0.0;
  if (!Read(key, &d)) return false;
  *out = static_cast<float>(d);
  return true;
}

bool View::Read(const std::string& key, std::string* out) const {
  const Json* v = Get(key);
  if (!v || !v->is_string()) return false;
  *out = v->get<std::string>();
  return true;
}

namespace {
// `n` floats from a checked array of numbers.
bool ReadFloats(const Json* v, size_t n, float* out) {
  if (!v || !v->is_array() || v->size() != n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (!(*v)[i].is_number()) return false;
    out[i] = static_cast<float>((*v)[i].get<double>());
  }
  return true;
}
}  // namespace

bool View::Read(const std::string& key, float2* out) const {
  float c[2];
  if (!ReadFloats(Get(key), 2, c)) return false;
  *out = {c[0], c[1]};
  return true;
}

bool View::Read(const std::string& key, float3* out) const {
  float c[3];
  if (!ReadFloats(Get(key), 3, c)) return false;
  *out = {c[0], c[1], c[2]};
  return true;
}

namespace {
template <typename Point, size_t N>
bool ReadPoints(const Json* v, std::vector<Point>* out) {
  if (!v || !v->is_array()) return false;
  std::vector<Point> points(v->size());
  for (size_t i = 0; i < v->size(); ++i) {
    float c[3] = {0.f, 0.f, 0.f};
    if (!ReadFloats(&(*v)[i], N, c)) return false;
    if constexpr (N == 2) points[i] = {c[0], c[1]};
    else points[i] = {c[0], c[1], c[2]};
  }
  *out = std::move(points);
  return true;
}
}  // namespace

bool View::Read(const std::string& key, std::vector<float2>* out) const {
  return ReadPoints<float2, 2>(Get(key), out);
}

bool View::Read(const std::string& key, std::vector<float3>* out) const {
  return ReadPoints<float3, 3>(Get(key), out);
}

bool View::Choice(const std::string& key, size_t* out) const {
  const Json* v = Get(key);
  const Field* f = FieldOf(key);
  if (!v || !f || !v->is_string()) return false;
  for (size_t i = 0; i < f->choices.size(); ++i) {
    if (f->choices[i] == v->get_ref<const std::string&>()) {
      *out = i;
      return true;
    }
  }
  return false;
}

bool View::CheckBound(const std::string& key, const std::string& name, const float* bound,
                      bool upper) const {
  float x = 0.f;
  const Field* f = FieldOf(key);
  if (!f || !Read(key, &x)) return true;
  const bool in_range = f->range.Contains(x) && (!bound || (upper ? x < *bound : x > *bound));
  if (in_range) return true;
  std::string expect = f->Expect();
  const size_t at = expect.find(name);
  if (bound && at != std::string::npos) expect.insert(at + name.size(), " = " + FormatFloat(*bound));
  reader_->Expected(Path(key), expect, *Raw(key));
  return false;
}

View View::Member(const std::string& key) const {
  const Field* f = FieldOf(key);
  return View::Make(reader_, Raw(key), f ? f->object : nullptr, Path(key));
}

size_t View::Size(const std::string& key) const {
  const Json* v = Raw(key);
  const Field* f = FieldOf(key);
  return v && f && f->type == Type::kArray && v->is_array() ? v->size() : 0;
}

View View::Element(const std::string& key, size_t i) const {
  const Json* v = Raw(key);
  const Field* f = FieldOf(key);
  if (!v || !f || f->element.empty() || !v->is_array() || i >= v->size())
    return View::Make(reader_, nullptr, nullptr, Index(Path(key), i));
  return View::Make(reader_, &(*v)[i], f->element[0].object, Index(Path(key), i));
}

View View::Make(const Reader* reader, const Json* v, const Object* o, std::string path) {
  View view;
  view.reader_ = reader;
  view.value_ = v;
  view.object_ = o;
  view.path_ = std::move(path);
  view.chosen_ = v && o && reader ? ChosenVariant(*o, *v, *reader) : nullptr;
  if (view.chosen_) view.variant_ = (*v)[o->variant_key].get<std::string>();
  view.good_ = reader && v && reader->IsGood(v);
  return view;
}

std::string CheckJsonText(std::string_view text, size_t max_bytes, int max_depth) {
  if (text.size() > max_bytes)
    return "the JSON text is " + std::to_string(text.size()) + " bytes; expected at most " +
           std::to_string(max_bytes) + " bytes (" + std::to_string(max_bytes >> 20) + " MiB)";
  const size_t too_deep = TooDeepAt(text, max_depth);
  if (too_deep != std::string_view::npos)
    return "nested deeper than " + std::to_string(max_depth) + " levels at " + At(text, too_deep) +
           "; expected at most " + std::to_string(max_depth) + " levels of arrays and objects";
  return "";
}

// ---------------------------------------------------------------------------------------------
// Boundaries of the formats' Parse and Load functions.

bool NoThrow(Diagnostics* diag, const std::string& what, const std::function<bool()>& parse) {
  try {
    return parse();
  } catch (const std::exception& e) {
    diag->Error("", what + ": " + e.what());
  } catch (...) {
    diag->Error("", what + ": unknown error");
  }
  return false;
}

bool ParseFile(const std::string& path, Diagnostics* diag,
               const std::function<bool(const std::string& text, Diagnostics* local)>& parse) {
  Diagnostics fallback;
  if (!diag) diag = &fallback;
  std::string text;
  if (!ReadFile(path, &text, diag, kMaxJsonFileBytes, "JSON file")) return false;
  Diagnostics local;
  const bool ok = NoThrow(&local, "cannot read " + path, [&] { return parse(text, &local); });
  diag->Append(local, path);
  return ok;
}

// ---------------------------------------------------------------------------------------------
// Schema (draft-07).

namespace {

Json FieldSchema(const Field& f);

Json ObjectSchema(const Object& o) {
  Json s = Json::object();
  s["type"] = "object";
  if (!o.description.empty()) s["description"] = o.description;
  auto add = [](const Object& obj, Json* props, Json* required) {
    for (const Field& f : obj.fields) {
      (*props)[f.key] = FieldSchema(f);
      if (f.required) required->push_back(f.key);
    }
  };
  Json props = Json::object(), required = Json::array();
  add(o, &props, &required);
  if (!required.empty()) s["required"] = required;
  if (o.variants.empty()) s["additionalProperties"] = false;
  s["properties"] = props;
  if (o.variants.empty()) return s;
  Json all = Json::array();
  for (const Object::Variant& var : o.variants) {
    Json then = Json::object();
    if (!var.object->description.empty()) then["description"] = var.object->description;
    Json vprops = Json::object(), vrequired = required;
    for (const Field& f : o.fields) vprops[f.key] = Json::object();  // declared above
    add(*var.object, &vprops, &vrequired);
    then["required"] = vrequired;
    then["additionalProperties"] = false;
    then["properties"] = vprops;
    Json cond = {{"properties", {{o.variant_key, {{"const", var.value}}}}},
                 {"required", {o.variant_key}}};
    all.push_back({{"if", cond}, {"then", then}});
  }
  s["allOf"] = all;
  return s;
}

void RangeSchema(const Range& r, bool is_float, Json* s) {
  constexpr double kFloatMax = 3.4028234663852886e+38;
  double min = r.min, max = r.max;
  bool min_open = r.min_open, max_open = r.max_open;
  if (is_float && !(min > -kFloatMax)) min = -kFloatMax, min_open = false;
  if (is_float && !(max < kFloatMax)) max = kFloatMax, max_open = false;
  if (std::isfinite(min)) (*s)[min_open ? "exclusiveMinimum" : "minimum"] = min;
  if (std::isfinite(max)) (*s)[max_open ? "exclusiveMaximum" : "maximum"] = max;
}

Json FieldSchema(const Field& f) {
  Json s = Json::object();
  switch (f.type) {
    case Type::kAny: break;
    case Type::kBool: s["type"] = "boolean"; break;
    case Type::kInteger:
      s["type"] = "integer";
      if (f.version > 0) s["const"] = f.version;
      else RangeSchema(f.range, false, &s);
      break;
    case Type::kNumber:
      s["type"] = "number";
      RangeSchema(f.range, true, &s);
      break;
    case Type::kString:
      s["type"] = "string";
      if (f.non_empty) s["minLength"] = 1;
      break;
    case Type::kEnum:
      if (f.choices.size() == 1) s["const"] = f.choices[0];
      else s["enum"] = f.choices;
      break;
    case Type::kArray:
      s["type"] = "array";
      if (f.count) s["minItems"] = f.count, s["maxItems"] = f.count;
      else if (f.non_empty) s["minItems"] = 1;
      if (!f.element.empty()) s["items"] = FieldSchema(f.element[0]);
      break;
    case Type::kObject:
      if (f.object) s = ObjectSchema(*f.object);
      else s["type"] = "object";
      break;
  }
  if (!f.about.empty()) s["description"] = f.about;
  return s;
}

}  // namespace

Json Schema(const Format& format) {
  Json s = Json::object();
  s["$schema"] = "http://json-schema.org/draft-07/schema#";
  int version = 0;
  if (format.root.object)
    for (const Field& f : format.root.object->fields) version = std::max(version, f.version);
  s["$id"] = "urn:mimetic:schema:" + format.name + ":" + std::to_string(version);
  if (!format.title.empty()) s["title"] = format.title;
  s.update(FieldSchema(format.root));
  return s;
}

}  // namespace mimetic::json_reader
