// tests/io/json_reader_test.cpp: the declarative JSON reader (io/json_reader.h): each field
// type, each kind of error with its message, the guard, views, the schema; and one integer
// rule for every format (rig file and template agree).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/json_reader.h"
#include "io/landmarks_file.h"
#include "io/rig_file.h"
#include "io/template_file.h"

namespace mimetic {
namespace {

using namespace json_reader;

// A small format with one field of each type.
const Object kInner = {"an inner object", {
    Number("w").Above(0).Required().About("mm"),
    Numbers("p", 3)}};
const Object kA = {"variant a", {Number("x").Min(0).Max(1)}};
const Object kB = {"variant b", {String("y").NonEmpty().Required()}};
const Object kTop = {
    .owner = "a test file",
    .fields = {
        Enum("format", {"test"}).Required(),
        Integer("version", "integer 1").Version(1).Required(),
        Bool("flag"),
        Integer("count").Min(1),
        Number("ratio").Above(0).Below(1),
        Number("any"),
        String("name").NonEmpty(),
        Enum("colour", {"red", "green"}),
        Enum("size", {"s", "m"}).UnknownChoice("unknown size {}; sizes: s, m"),
        Array("list", Number("").Min(0), "array of numbers >= 0"),
        ObjectOf("inner", kInner, "object {\"w\": ...}"),
        Array("inners", ObjectOf("", kInner, "object (an inner)"), "array of inners"),
        AnyObject("free")},
    .notes = {{"colour_name", "(did you mean \"colour\"?)"},
              {"old", "\"old\" was removed in version 1; expected \"name\"", true}}};
const Object kVariantTop = {
    .owner = "a variant file",
    .fields = {Enum("kind", {"a", "b"}).Required()},
    .variant_key = "kind",
    .variants = {{"a", &kA}, {"b", &kB}}};

Format Fmt(const Object& top, Wording wording = {}) {
  return {.name = "test", .root = ObjectOf("", top, "an object {\"format\": \"test\"}"),
          .wording = wording};
}
const Format kFormat = Fmt(kTop);

std::string Doc(const std::string& members) {
  return R"({"format": "test", "version": 1)" + (members.empty() ? "" : ", " + members) + "}";
}

// The diagnostics of reading `text` (Parse + Check), one "where: what" per line.
std::string Read(const Format& format, const std::string& text, size_t* errors = nullptr) {
  Diagnostics diag;
  Reader r(format, &diag);
  if (r.Parse(text)) r.Check();
  if (errors) *errors = diag.ErrorCount();
  std::string out;
  for (const Diagnostic& d : diag.items()) out += d.where + ": " + d.what + "\n";
  return out;
}
std::string Read(const std::string& text, size_t* errors = nullptr) {
  return Read(kFormat, text, errors);
}

TEST(JsonReader, AValidDocumentHasNoMessages) {
  EXPECT_EQ(Read(Doc("")), "");
  EXPECT_EQ(Read(Doc(R"("flag": true, "count": 6, "ratio": 0.5, "any": -1e30, "name": "n",
                      "colour": "red", "size": "m", "list": [0, 2.5], "inner": {"w": 1,
                      "p": [1, 2, 3]}, "inners": [], "free": {"anything": [1]})")),
            "");
}

TEST(JsonReader, EachTypeReportsAWrongValueWithPathExpectationAndValue) {
  struct Case {
    std::string members;
    std::string message;  // the whole diagnostics
  };
  const std::vector<Case> cases = {
      {R"("flag": "yes")", "flag: expected boolean (true or false), got \"yes\"\n"},
      {R"("flag": 0)", "flag: expected boolean (true or false), got 0\n"},
      {R"("count": 0)", "count: expected an integer >= 1, got 0\n"},
      {R"("count": 6.5)", "count: expected an integer >= 1, got 6.5\n"},
      {R"("count": "6")", "count: expected an integer >= 1, got string\n"},
      // INT_MAX + 1 = 2147483648 does not fit the int it is read into.
      {R"("count": 2147483648)", "count: expected an integer >= 1, got 2147483648\n"},
      {R"("ratio": 0)", "ratio: expected a number in (0, 1), got 0\n"},
      {R"("ratio": 1)", "ratio: expected a number in (0, 1), got 1\n"},
      {R"("ratio": null)", "ratio: expected a number in (0, 1), got null\n"},
      // FLT_MAX = 3.4028235e38: 1e39 is a double but not a float.
      {R"("any": 1e39)",
       "any: expected a finite number, got a number too large for a float (it overflows to "
       "infinity)\n"},
      {R"("any": -1e400)", "any: expected a finite number, got a number that overflows to infinity\n"},
      {R"("name": "")", "name: expected non-empty string, got empty string\n"},
      {R"("name": 3)", "name: expected non-empty string, got number\n"},
      {R"("colour": "blue")", "colour: expected one of \"red\", \"green\", got \"blue\"\n"},
      {R"("colour": 1)", "colour: expected one of \"red\", \"green\", got 1\n"},
      {R"("size": "xl")", "size: unknown size \"xl\"; sizes: s, m\n"},
      {R"("list": {})", "list: expected array of numbers >= 0, got object\n"},
      {R"("list": [1, -1, "x"])",
       "list[1]: expected a finite number >= 0, got -1\n"
       "list[2]: expected a finite number >= 0, got string\n"},
      {R"("inner": [])", "inner: expected object {\"w\": ...}, got array of 0 elements\n"},
      {R"("inner": {"w": 0})", "inner.w: expected a finite number > 0, got 0\n"},
      {R"("inner": {})", "inner.w: missing required key; expected a finite number > 0 (mm)\n"},
      {R"("inner": {"w": 1, "p": [1, 2]})",
       "inner.p: expected array of 3 numbers, got array of 2 elements\n"},
      {R"("inner": {"w": 1, "p": [1, true, 3]})",
       "inner.p[1]: expected a finite number, got boolean\n"},
      {R"("inners": [{"w": 1}, 7, {"w": -2}])",
       "inners[1]: expected object (an inner), got number\n"
       "inners[2].w: expected a finite number > 0, got -2\n"},
      {R"("free": 1)", "free: expected object, got number\n"},
      {R"("extra": 1)",
       "extra: unknown key \"extra\"; allowed keys for a test file: format, version, flag, count, "
       "ratio, any, name, colour, size, list, inner, inners, free\n"},
      {R"("colour_name": 1)",
       "colour_name: unknown key \"colour_name\" (did you mean \"colour\"?); allowed keys for a "
       "test file: format, version, flag, count, ratio, any, name, colour, size, list, inner, "
       "inners, free\n"},
      {R"("old": 1)", "old: \"old\" was removed in version 1; expected \"name\"\n"},
      {R"("name": "a", "name": "b")", "name: duplicate key; expected each key once per object\n"},
      {R"("inner": {"w": 1, "w": 2})",
       "inner.w: duplicate key; expected each key once per object\n"},
  };
  for (const Case& c : cases) EXPECT_EQ(Read(Doc(c.members)), c.message) << c.members;
}

TEST(JsonReader, IntegersAreIntegralValuedNumbers) {
  // One rule for every format, as in JSON Schema: 6.0 is the integer 6, 6.5 is not an integer.
  Diagnostics diag;
  Reader r(kFormat, &diag);
  ASSERT_TRUE(r.Parse(Doc(R"("count": 6.0)")));
  const View top = r.Check();
  int count = 0;
  EXPECT_TRUE(top.Read("count", &count));
  EXPECT_EQ(count, 6);
  EXPECT_TRUE(diag.empty()) << diag.Format();
  EXPECT_EQ(Read(Doc(R"("count": 1e2)")), "");  // 100
}

TEST(JsonReader, HeaderFormatAndVersion) {
  EXPECT_EQ(Read(R"({"version": 1})"), "format: missing required key; expected \"test\"\n");
  EXPECT_EQ(Read(R"({"format": "tset", "version": 1})"), "format: expected \"test\", got \"tset\"\n");
  EXPECT_EQ(Read(R"({"format": "test", "version": 1.5})"), "version: expected integer 1, got 1.5\n");
  EXPECT_EQ(Read(R"({"format": "test", "version": 0})"), "version: expected integer 1, got 0\n");
  // A newer version stops the check: its keys may be new.
  EXPECT_EQ(Read(R"({"format": "test", "version": 2, "new_key": 1})"),
            "version: unsupported version 2: this build reads version 1 (it supports version 1 "
            "only)\n");
  // ... unless the format says the rest is still checked.
  const Object top = {"a test file", {Integer("version").Version(1, false), Bool("b")}};
  EXPECT_EQ(Read(Fmt(top), R"({"version": 3, "b": 1})"),
            "version: unsupported version 3: this build reads version 1 (it supports version 1 "
            "only)\nb: expected boolean (true or false), got 1\n");
}

TEST(JsonReader, EveryProblemIsReportedNotOnlyTheFirst) {
  size_t errors = 0;
  Read(Doc(R"("flag": 1, "count": 0, "extra": 2, "inner": {"w": -1, "p": [1, 2]},
              "inners": [{}, {"w": "1"}])"),
       &errors);
  EXPECT_EQ(errors, 7u);  // flag, count, extra, inner.w, inner.p, inners[0].w, inners[1].w
}

TEST(JsonReader, AHugeArrayOfBadElementsIsSummedUpAfterTwenty) {
  std::string list = "[";
  for (int i = 0; i < 25; ++i) list += std::string(i ? ", " : "") + "-1";
  size_t errors = 0;
  const std::string msg = Read(Doc(R"("list": )" + list + "]"), &errors);
  EXPECT_EQ(errors, 21u);
  EXPECT_NE(msg.find("list[19]: expected a finite number >= 0, got -1\n"), std::string::npos);
  EXPECT_EQ(msg.find("list[20]"), std::string::npos);
  EXPECT_NE(msg.find("list: 5 more invalid elements not listed; expected each a finite number "
                     ">= 0\n"),
            std::string::npos)
      << msg;
}

TEST(JsonReader, VariantsChooseTheirFields) {
  const Format f = Fmt(kVariantTop);
  EXPECT_EQ(Read(f, R"({"kind": "a", "x": 0.5})"), "");
  EXPECT_EQ(Read(f, R"({"kind": "a", "x": 2})"), "x: expected a number in [0, 1], got 2\n");
  EXPECT_EQ(Read(f, R"({"kind": "a", "y": "s"})"),
            "y: unknown key \"y\"; allowed keys for variant a: kind, x\n");
  EXPECT_EQ(Read(f, R"({"kind": "b"})"), "y: missing required key; expected non-empty string\n");
  // An unknown variant: its own error; the keys of every variant are allowed.
  EXPECT_EQ(Read(f, R"({"kind": "c", "x": 2, "y": ""})"),
            "kind: expected one of \"a\", \"b\", got \"c\"\n");
  EXPECT_EQ(Read(f, R"({"x": 1})"), "kind: missing required key; expected one of \"a\", \"b\"\n");
}

TEST(JsonReader, WordingOptions) {
  const Format is_first = Fmt(kTop, {.is_first = true, .unknown_key_in_owner = true});
  EXPECT_EQ(Read(is_first, Doc(R"("name": 3, "extra": 1, "list": [1, 2], "inner": {"p": [1]})")),
            "extra: unknown key in a test file; expected one of: format, version, flag, count, "
            "ratio, any, name, colour, size, list, inner, inners, free\n"
            "name: is number; expected non-empty string\n"
            "inner.w: missing required key; expected a finite number > 0 (mm)\n"
            "inner.p: has 1 entries; expected array of 3 numbers\n");
  EXPECT_EQ(Read(is_first, "[1]"), ": top level is array of 1 elements; expected an object {\"format\": \"test\"}\n");
  const Format values = Fmt(kTop, {.value_in_type_errors = true});
  EXPECT_EQ(Read(values, Doc(R"("name": 3, "ratio": "half")")),
            "ratio: expected a number in (0, 1), got \"half\"\nname: expected non-empty string, got 3\n");
}

TEST(JsonReader, InvalidJsonGivesLineAndColumn) {
  // The second comma is the 9th character of line 2 (counted by hand).
  EXPECT_EQ(Read("{\"format\": \"test\",\n \"a\": 1,,}").substr(0, 36),
            ": invalid JSON at line 2, column 9: ");
  EXPECT_NE(Read("").find("invalid JSON at line 1, column 1: "), std::string::npos);
  EXPECT_NE(Read("{").find("(not valid JSON; expected a test file)"), std::string::npos);
  EXPECT_EQ(Read("[1, 2]"), ": expected an object {\"format\": \"test\"}, got array of 2 elements\n");
}

TEST(JsonReader, NestingAndSizeAreLimitedBeforeParsing) {
  // 64 levels: the document is read; 65: refused with the place of the 65th bracket (the
  // root's "{" is level 1 and Doc's prefix is 41 characters, so the 64th "[" is column 105).
  const std::string ok = Doc(R"("free": )" + std::string(63, '[') + std::string(63, ']'));
  EXPECT_EQ(Read(ok), "free: expected object, got array of 1 elements\n");
  const std::string deep = Doc(R"("free": )" + std::string(64, '[') + std::string(64, ']'));
  EXPECT_EQ(Read(deep),
            ": nested deeper than 64 levels at line 1, column 105; expected at most 64 levels of "
            "arrays and objects\n");
  // 100,000 brackets: no stack overflow; the top-level value is an array, not an object.
  const std::string brackets = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_EQ(Read(brackets),
            ": nested deeper than 64 levels at line 1, column 65; expected at most 64 levels of "
            "arrays and objects\n"
            ": expected an object {\"format\": \"test\"}, got array\n");
  // Brackets inside strings do not count.
  EXPECT_EQ(Read(Doc(R"("name": ")" + std::string(1000, '[') + "\"")), "");
  Format small = kFormat;
  small.max_bytes = 10;
  EXPECT_EQ(Read(small, Doc("")),
            ": the text is 32 bytes; expected at most 10 bytes (test file)\n");
}

TEST(JsonReader, MessagesDescribeValuesShortlyAndNeverRecursively) {
  nlohmann::json big = nlohmann::json::array();
  for (int i = 0; i < 1000; ++i) big.push_back({{"k", std::string(100, 'x')}});
  EXPECT_EQ(Describe(big), "array of 1000 elements");
  EXPECT_EQ(Describe(nlohmann::json::object({{"a", big}})), "object");
  const std::string s(100, 'y');
  EXPECT_EQ(Describe(nlohmann::json(s)), "\"" + std::string(60, 'y') + "...\"");
  EXPECT_EQ(Describe(nlohmann::json("a\"b\xff")), "\"a\\\"b\xef\xbf\xbd\"");  // escaped, U+FFFD
  EXPECT_EQ(Describe(nlohmann::json(2.5)), "2.5");
  EXPECT_EQ(Describe(nlohmann::json(nullptr)), "null");
}

TEST(JsonReader, ViewsReadCheckedValues) {
  Diagnostics diag;
  Reader r(kFormat, &diag);
  ASSERT_TRUE(r.Parse(Doc(R"("flag": true, "ratio": 0.25, "name": "n", "colour": "green",
                              "inner": {"w": 1.5, "p": [1, -2, 0.125]},
                              "inners": [{"w": 2}, {"w": -1}])")));
  const View top = r.Check();
  EXPECT_EQ(diag.ErrorCount(), 1u);  // inners[1].w
  EXPECT_FALSE(top.ok());            // a problem below it
  bool flag = false;
  EXPECT_TRUE(top.Read("flag", &flag));
  EXPECT_TRUE(flag);
  float ratio = 0.f;
  EXPECT_TRUE(top.Read("ratio", &ratio));
  EXPECT_EQ(ratio, 0.25f);
  size_t colour = 9;
  EXPECT_TRUE(top.Choice("colour", &colour));
  EXPECT_EQ(colour, 1u);
  int count = 42;
  EXPECT_FALSE(top.Read("count", &count));  // absent: left alone
  EXPECT_EQ(count, 42);
  const View inner = top.Member("inner");
  EXPECT_TRUE(inner.ok());
  EXPECT_EQ(inner.path(), "inner");
  float3 p{};
  EXPECT_TRUE(inner.Read("p", &p));
  EXPECT_EQ(p.x, 1.f);
  EXPECT_EQ(p.y, -2.f);
  EXPECT_EQ(p.z, 0.125f);
  ASSERT_EQ(top.Size("inners"), 2u);
  EXPECT_TRUE(top.Element("inners", 0).ok());
  const View bad = top.Element("inners", 1);
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.path(), "inners[1]");
  float w = 7.f;
  EXPECT_FALSE(bad.Read("w", &w));  // invalid: left alone
  EXPECT_EQ(w, 7.f);
  EXPECT_EQ(bad.FieldOf("w")->range.min, 0.0);
}

TEST(JsonReader, WhereNamesTheFile) {
  Diagnostics diag;
  Reader r(kFormat, &diag, "f.json");
  ASSERT_TRUE(r.Parse(Doc(R"("flag": 1)")));
  r.Check();
  r.Error("", "whole file");
  EXPECT_EQ(diag.Format(),
            "error: f.json: flag: expected boolean (true or false), got 1\n"
            "error: f.json: whole file\n");
}

TEST(JsonReader, SchemaIsMadeFromTheTables) {
  const Object inner = {"inner", {Number("w").Above(0).Required().About("mm"), Numbers("p", 2)}};
  const Object top = {"top", {Enum("format", {"t"}).Required(),
                              Integer("version").Version(1).Required(),
                              Integer("n").Min(1), Enum("e", {"a", "b"}),
                              String("s").NonEmpty(), Bool("b"),
                              Array("l", ObjectOf("", inner)).NonEmpty()}};
  const Format f = {.name = "t", .root = ObjectOf("", top), .title = "T"};
  const nlohmann::json expected = nlohmann::json::parse(R"({
    "$schema": "http://json-schema.org/draft-07/schema#", "$id": "urn:mimetic:schema:t:1",
    "title": "T", "type": "object", "required": ["format", "version"],
    "additionalProperties": false,
    "properties": {
      "format": {"const": "t"}, "version": {"type": "integer", "const": 1},
      "n": {"type": "integer", "minimum": 1, "maximum": 2147483647},
      "e": {"enum": ["a", "b"]}, "s": {"type": "string", "minLength": 1},
      "b": {"type": "boolean"},
      "l": {"type": "array", "minItems": 1, "items": {
        "type": "object", "required": ["w"], "additionalProperties": false, "properties": {
          "w": {"type": "number", "exclusiveMinimum": 0, "maximum": 3.4028234663852886e+38,
                "description": "mm"},
          "p": {"type": "array", "minItems": 2, "maxItems": 2, "items": {"type": "number",
                "minimum": -3.4028234663852886e+38, "maximum": 3.4028234663852886e+38}}}}}}})");
  EXPECT_EQ(Schema(f), expected) << Schema(f).dump(2);
}

// The example of io/json_reader.h, as written there.
TEST(JsonReader, HeaderExampleWorks) {
  const Object kPoint = {"a point", {
      Number("depth").Min(0).Required().About("mm under the skin"),
      Numbers("offset", 2, "[dx, dy], two finite numbers"),
      Enum("side", {"left", "right"})}};
  const Object kTop = {"a point file", {
      Enum("format", {"my-points"}).Required(), Integer("version").Version(1).Required(),
      Array("points", ObjectOf("", kPoint), "array of points").Required()}};
  const Format kFormat = {"my-points", ObjectOf("", kTop, "an object {\"format\": ...}")};
  auto read = [&](const std::string& text, std::vector<float>* depths, Diagnostics* diag) {
    Reader r(kFormat, diag);
    if (!r.Parse(text)) return false;
    const View top = r.Check();
    if (r.stopped()) return false;
    for (size_t i = 0; i < top.Size("points"); ++i) {
      const View p = top.Element("points", i);
      float depth = 0.f;
      if (p.Read("depth", &depth)) depths->push_back(depth);
    }
    return !r.failed();
  };
  std::vector<float> depths;
  Diagnostics diag;
  EXPECT_TRUE(read(R"({"format": "my-points", "version": 1, "points": [{"depth": 2},
                      {"depth": 0.5, "offset": [1, 2], "side": "left"}]})", &depths, &diag))
      << diag.Format();
  EXPECT_EQ(depths, (std::vector<float>{2.f, 0.5f}));
  depths.clear();
  EXPECT_FALSE(read(R"({"format": "my-points", "version": 1, "points": [{"depth": -1},
                       {"offset": [1], "side": "up"}]})", &depths, &diag));
  EXPECT_EQ(diag.Format(),
            "error: points[0].depth: expected a finite number >= 0, got -1\n"
            "error: points[1].depth: missing required key; expected a finite number >= 0 (mm "
            "under the skin)\n"
            "error: points[1].offset: expected [dx, dy], two finite numbers, got array of 1 "
            "elements\n"
            "error: points[1].side: expected one of \"left\", \"right\", got \"up\"\n");
}

// The same wrinkle count in a rig file and in a template gets the same answer.
TEST(JsonReader, RigFileAndTemplateAgreeOnIntegers) {
  const std::string rig = R"({"format": "mimetic-rig", "version": 1, "mesh": {"path": "m.obj"},
      "units": "mm", "muscles": [{"name": "z_L", "type": "linear", "strength": 1,
      "attachment": [0, 0, 0], "insertion": [1, 0, 0], "zone_angle_deg": 40,
      "falloff_start": 1, "falloff_end": 2, "wrinkles": {"depth": 1, "count": COUNT}}]})";
  const std::string tmpl = R"({"format": "mimetic-muscle-template", "version": 1,
      "muscles": [{"name": "z_L", "type": "linear", "strength": 1,
      "attachment": {"landmarks": [45], "depth": 0}, "insertion": {"landmarks": [54], "depth": 0},
      "zone_angle_deg": 40, "falloff_start": 1, "falloff_end": 2,
      "wrinkles": {"depth": 1, "count": COUNT}}]})";
  auto with = [](std::string text, const std::string& count) {
    return text.replace(text.find("COUNT"), 5, count);
  };
  for (const char* count : {"6", "6.0", "6e0", "6.5", "0", "\"6\""}) {
    SCOPED_TRACE(count);
    RigSpec spec;
    MuscleTemplate t;
    Diagnostics rig_diag, tmpl_diag;
    const bool rig_ok = ParseRigSpec(with(rig, count), "", &spec, &rig_diag);
    const bool tmpl_ok = ParseMuscleTemplate(with(tmpl, count), &t, &tmpl_diag);
    EXPECT_EQ(rig_ok, tmpl_ok) << rig_diag.Format() << tmpl_diag.Format();
    const bool integral = std::string(count) == "6" || std::string(count) == "6.0" ||
                          std::string(count) == "6e0";
    EXPECT_EQ(rig_ok, integral) << rig_diag.Format();
    if (rig_ok && tmpl_ok) {
      EXPECT_EQ(spec.muscle_wrinkles[0]->count, 6);
      EXPECT_EQ(t.muscles[0].wrinkles->count, 6);
    } else {
      const std::string msg = "muscles[0].wrinkles.count: expected an integer >= 1, got";
      EXPECT_NE(rig_diag.Format().find(msg), std::string::npos) << rig_diag.Format();
      EXPECT_NE(tmpl_diag.Format().find(msg), std::string::npos) << tmpl_diag.Format();
    }
  }
}

// No input crashes a Parse function or lets an exception out.
TEST(JsonReader, HostileInputsAreCleanErrorsInEveryFormat) {
  const std::vector<std::string> texts = {
      std::string(100000, '[') + std::string(100000, ']'),
      std::string(100000, '{'),
      "{\"a\":" + std::string(50000, '[') + "1e400" + std::string(50000, ']') + "}",
      "[1e400, -1e400, 1e-400]", "{\"format\": 1e400}", "\"\xff\xfe\"", "nul", "", "{}",
      "{\"points\": [[1e400, 0, 0]]}", "{\"version\": 1e400}", "{\"muscles\": [1e400]}"};
  for (const std::string& text : texts) {
    Diagnostics d1, d2, d3;
    RigSpec spec;
    MuscleTemplate t;
    Landmarks lm;
    EXPECT_FALSE(ParseRigSpec(text, "", &spec, &d1));
    EXPECT_FALSE(ParseMuscleTemplate(text, &t, &d2));
    EXPECT_FALSE(ParseLandmarks(text, "lm.json", &lm, &d3));
    EXPECT_TRUE(d1.HasErrors() && d2.HasErrors() && d3.HasErrors());
  }
}

}  // namespace
}  // namespace mimetic
