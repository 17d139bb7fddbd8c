// io/expression_file.cpp: writing expression files.
#include "io/expression_file.h"

#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "io/formats.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

using namespace json_reader;

const Object kExpressionFile = {"an expression file", {
    Enum("format", {"mimetic-expression"}).Required(),
    Integer("version", "the integer 1").Version(1).Required(),
    String("name").NonEmpty().Required().About("the expression's name"),
    AnyObject("activations", "an object {\"muscle name\": activation in [0, 1], ...}")
        .Required().About("muscle name -> activation in [0, 1]"),
    AnyObject("solve", "an object of numbers and strings")
        .About("how the expression was made (mimetic solve)")}};

const Format kExpressionFormat = {
    .name = "mimetic-expression",
    .root = ObjectOf("", kExpressionFile, "an object with \"format\": \"mimetic-expression\""),
    .title = "mimetic expression file, version 1"};

}  // namespace

const json_reader::Format& ExpressionFileFormat() { return kExpressionFormat; }

bool ParseExpression(const std::string& text, const std::string& where, Expression* out,
                     Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  return NoThrow(diag, where + ": internal error while reading the expression", [&] {
    Reader r(kExpressionFormat, diag, where);
    if (!r.Parse(text)) return false;
    const View top = r.Check();
    if (r.stopped() || !top.present() || !top.value()->is_object()) return false;
    Expression e;
    top.Read("name", &e.name);
    if (const Json* a = top.Get("activations")) {
      for (const auto& [muscle, value] : a->items()) {
        const std::string path = "activations." + muscle;
        if (muscle.empty()) r.Error("activations", "has an empty muscle name");
        if (!value.is_number() || !(value.get<double>() >= 0.0 && value.get<double>() <= 1.0))
          r.Error(path, "is " + Describe(value) + "; expected an activation in [0, 1]");
        else
          e.activations.push_back({muscle, value.get<float>()});
      }
    }
    if (const Json* s = top.Get("solve")) {
      for (const auto& [key, value] : s->items()) {
        if (value.is_number()) e.solve_numbers.push_back({key, value.get<double>()});
        else if (value.is_string()) e.solve_strings.push_back({key, value.get<std::string>()});
        else if (!value.is_null())
          r.Error("solve." + key, "is " + Describe(value) + "; expected a number or a string");
      }
    }
    if (r.failed()) return false;
    *out = std::move(e);
    return true;
  });
}

bool LoadExpression(const std::string& path, Expression* out, Diagnostics* diag) {
  return ParseFile(path, diag, [&](const std::string& text, Diagnostics* local) {
    return ParseExpression(text, "", out, local);
  });
}

std::string ExpressionToJson(const Expression& e) {
  nlohmann::ordered_json j;
  j["format"] = "mimetic-expression";
  j["version"] = 1;
  j["name"] = e.name;
  nlohmann::ordered_json a = nlohmann::ordered_json::object();
  // Six decimals: an activation is not more precise than that, and 0.82f reads as 0.82.
  for (const auto& [muscle, value] : e.activations) a[muscle] = std::round(double(value) * 1e6) / 1e6;
  j["activations"] = a;
  if (!e.solve_numbers.empty() || !e.solve_strings.empty()) {
    nlohmann::ordered_json s = nlohmann::ordered_json::object();
    for (const auto& [k, v] : e.solve_strings) s[k] = v;
    for (const auto& [k, v] : e.solve_numbers) s[k] = std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr;
    j["solve"] = s;
  }
  return j.dump(2) + "\n";
}

bool SaveExpression(const std::string& path, const Expression& e, Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  if (e.name.empty()) diag->Error(path + ": name", "is empty; expected the expression's name");
  std::set<std::string> seen;
  for (size_t i = 0; i < e.activations.size(); ++i) {
    const auto& [muscle, value] = e.activations[i];
    const std::string where = path + ": activations[" + std::to_string(i) + "]";
    if (muscle.empty()) diag->Error(where, "muscle name is empty");
    else if (!seen.insert(muscle).second) diag->Error(where, "'" + muscle + "' appears twice");
    if (!(value >= 0.f && value <= 1.f))
      diag->Error(where, "'" + muscle + "' = " + std::to_string(value) +
                             "; expected an activation in [0, 1]");
  }
  if (diag->ErrorCount() != before) return false;
  return WriteFileAtomic(path, ExpressionToJson(e), diag);
}

}  // namespace mimetic
