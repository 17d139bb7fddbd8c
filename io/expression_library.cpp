// io/expression_library.cpp: reading and writing expression libraries.
#include "io/expression_library.h"

#include <cmath>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "expressions/offline/activation_binding.h"
#include "expressions/runtime/clip.h"
#include "io/formats.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

using namespace json_reader;

const Object kLibraryEntry = {"a library expression", {
    String("name").NonEmpty().Required().About("the expression's name, unique in the library"),
    String("description").About("what the expression is and how its activations were set"),
    String("sources").About("where the muscles and values come from (papers, FACS, solves)"),
    AnyObject("activations", "an object {\"muscle name\": activation in [0, 1], ...}")
        .Required().About("muscle name -> activation in [0, 1]; muscles not named are 0")}};

const Object kLibraryFile = {"an expression library", {
    Enum("format", {"mimetic-expression-library"}).Required(),
    Integer("version", "the integer 1").Version(1).Required(),
    Array("expressions", ObjectOf("", kLibraryEntry, "an expression object"),
          "an array of expressions")
        .Required().About("the library's expressions")}};

const Format kLibraryFormat = {
    .name = "mimetic-expression-library",
    .root = ObjectOf("", kLibraryFile,
                     "an object with \"format\": \"mimetic-expression-library\""),
    .title = "mimetic expression library, version 1"};

}  // namespace

const json_reader::Format& ExpressionLibraryFormat() { return kLibraryFormat; }

bool ParseExpressionLibrary(const std::string& text, const std::string& where,
                            std::vector<Expression>* out, Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  return NoThrow(diag, where + ": internal error while reading the expression library", [&] {
    Reader r(kLibraryFormat, diag, where);
    if (!r.Parse(text)) return false;
    const View top = r.Check();
    if (r.stopped() || !top.present() || !top.value()->is_object()) return false;
    std::vector<Expression> library;
    std::map<std::string, size_t> first;  // name -> index of its first entry
    for (size_t i = 0; i < top.Size("expressions"); ++i) {
      const View v = top.Element("expressions", i);
      const std::string path = Index("expressions", i);
      if (!v.present() || !v.value()->is_object()) continue;
      Expression e;
      if (v.Read("name", &e.name)) {
        const auto [it, fresh] = first.insert({e.name, i});
        if (!fresh)
          r.Error(Key(path, "name"), Quoted(e.name) + " is also the name of " +
                                         Index("expressions", it->second) +
                                         "; expected a name used once");
      }
      v.Read("description", &e.description);
      v.Read("sources", &e.sources);
      if (const Json* a = v.Get("activations")) {
        for (const auto& [muscle, value] : a->items()) {
          const std::string apath = Key(Key(path, "activations"), muscle);
          if (muscle.empty()) r.Error(Key(path, "activations"), "has an empty muscle name");
          if (!value.is_number() ||
              !(value.get<double>() >= 0.0 && value.get<double>() <= 1.0))
            r.Error(apath, "is " + Describe(value) + "; expected an activation in [0, 1]");
          else
            e.activations.push_back({muscle, value.get<float>()});
        }
      }
      library.push_back(std::move(e));
    }
    if (r.failed()) return false;
    *out = std::move(library);
    return true;
  });
}

bool LoadExpressionLibrary(const std::string& path, std::vector<Expression>* out,
                           Diagnostics* diag) {
  return ParseFile(path, diag, [&](const std::string& text, Diagnostics* local) {
    return ParseExpressionLibrary(text, "", out, local);
  });
}

std::string ExpressionLibraryToJson(const std::vector<Expression>& library) {
  nlohmann::ordered_json j;
  j["format"] = "mimetic-expression-library";
  j["version"] = 1;
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const Expression& e : library) {
    nlohmann::ordered_json x;
    x["name"] = e.name;
    if (!e.description.empty()) x["description"] = e.description;
    if (!e.sources.empty()) x["sources"] = e.sources;
    nlohmann::ordered_json a = nlohmann::ordered_json::object();
    // Six decimals, as in expression files (io/expression_file.cpp).
    for (const auto& [muscle, value] : e.activations)
      a[muscle] = std::round(double(value) * 1e6) / 1e6;
    x["activations"] = a;
    list.push_back(x);
  }
  j["expressions"] = list;
  return j.dump(2) + "\n";
}

bool SaveExpressionLibrary(const std::string& path, const std::vector<Expression>& library,
                           Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  std::set<std::string> names;
  for (size_t i = 0; i < library.size(); ++i) {
    const Expression& e = library[i];
    const std::string where = path + ": expressions[" + std::to_string(i) + "]";
    if (e.name.empty()) diag->Error(where, "name is empty; expected the expression's name");
    else if (!names.insert(e.name).second)
      diag->Error(where, "name '" + e.name + "' appears twice; expected a name used once");
    std::set<std::string> seen;
    for (size_t k = 0; k < e.activations.size(); ++k) {
      const auto& [muscle, value] = e.activations[k];
      const std::string at = where + ".activations[" + std::to_string(k) + "]";
      if (muscle.empty()) diag->Error(at, "muscle name is empty");
      else if (!seen.insert(muscle).second) diag->Error(at, "'" + muscle + "' appears twice");
      if (!(value >= 0.f && value <= 1.f))
        diag->Error(at, "'" + muscle + "' = " + std::to_string(value) +
                            "; expected an activation in [0, 1]");
    }
  }
  if (diag->ErrorCount() != before) return false;
  return WriteFileAtomic(path, ExpressionLibraryToJson(library), diag);
}

bool CheckLibraryMuscles(const std::vector<Expression>& library,
                         const std::vector<std::string>& muscle_names, const std::string& where,
                         Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  const std::set<std::string> known(muscle_names.begin(), muscle_names.end());
  const std::string prefix = where.empty() ? "" : where + ": ";
  for (size_t i = 0; i < library.size(); ++i)
    for (const auto& [muscle, value] : library[i].activations)
      if (!known.count(muscle) && muscle != kJawInputName)
        diag->Error(prefix + "expressions[" + std::to_string(i) + "].activations." + muscle,
                    "expression '" + library[i].name + "' names the unknown muscle '" + muscle +
                        "'; the closest muscles of the rig: " + ClosestNames(muscle_names, muscle));
  return diag->ErrorCount() == before;
}

}  // namespace mimetic
