// io/expression_file.h: an expression, a named set of muscle activations (JSON,
// "format": "mimetic-expression"). Written by `mimetic solve`; the expression library and the
// clip formats of the playback work read the same file.
//
//   {"format": "mimetic-expression", "version": 1, "name": "mouthSmile_L",
//    "activations": {"zygomatic_major_L": 0.82, ...},      (every muscle of the rig, rig order)
//    "solve": {"rig": "...", "target": "...", ...}}         (optional: how it was made)
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"

namespace mimetic {

struct Expression {
  std::string name;
  std::vector<std::pair<std::string, float>> activations;  // muscle name -> [0, 1]
  // What it is and where it comes from: read and written by the expression library
  // (io/expression_library.h) only; the expression file has no such keys.
  std::string description;
  std::string sources;
  // Optional provenance, written as the "solve" object: key -> number or string.
  std::vector<std::pair<std::string, double>> solve_numbers;
  std::vector<std::pair<std::string, std::string>> solve_strings;
};

// Parses an expression file (the table in io/expression_file.cpp, the schema
// assets/schema/mimetic-expression.schema.json). Records every problem with its JSON path:
// wrong format or version, a missing or empty name, activations not an object, an activation
// that is not a number in [0, 1], an empty muscle name, unknown keys. `solve` is read as it
// is (numbers and strings). Returns false when any error was recorded; `where` prefixes the
// messages (usually the file name).
bool ParseExpression(const std::string& text, const std::string& where, Expression* out,
                     Diagnostics* diag);
bool LoadExpression(const std::string& path, Expression* out, Diagnostics* diag);

// The JSON text of `expression` (keys in the order given).
std::string ExpressionToJson(const Expression& expression);

// Writes the file atomically. Refuses (false, with a message naming the entry) an empty name,
// an empty or repeated muscle name, an activation outside [0, 1] or not finite.
bool SaveExpression(const std::string& path, const Expression& expression, Diagnostics* diag);

}  // namespace mimetic
