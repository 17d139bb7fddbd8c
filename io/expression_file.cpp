// io/expression_file.cpp: writing expression files.
#include "io/expression_file.h"

#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "core/file_util.h"

namespace mimetic {

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
