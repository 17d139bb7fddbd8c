// io/expression_library.h: a library of named expressions (JSON, "format":
// "mimetic-expression-library"), each a set of muscle activations with what it is and where
// it comes from. assets/expressions/default.library.json is the default rig's (docs/facs.md).
//
//   {"format": "mimetic-expression-library", "version": 1,
//    "expressions": [{"name": "Surprise", "description": "...", "sources": "...",
//                     "activations": {"frontalis_inner_L": 0.8, ...}}, ...]}
//
// Muscle names are written out: NAME does not stand for NAME_L and NAME_R here.
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "io/expression_file.h"

namespace mimetic {

// Parses a library (the table in io/expression_library.cpp, the schema
// assets/schema/mimetic-expression-library.schema.json). Records every problem with its JSON
// path: wrong format or version, expressions not an array, an entry without a name or with an
// empty one, a name used twice, activations not an object, an empty muscle name, an activation
// that is not a number in [0, 1], unknown keys. `solve` stays empty. False on any error;
// `where` prefixes the messages.
bool ParseExpressionLibrary(const std::string& text, const std::string& where,
                            std::vector<Expression>* out, Diagnostics* diag);
bool LoadExpressionLibrary(const std::string& path, std::vector<Expression>* out,
                           Diagnostics* diag);

// The JSON text of a library (expressions and activations in the order given; empty
// description and sources are left out).
std::string ExpressionLibraryToJson(const std::vector<Expression>& library);

// Writes the file atomically. Refuses (false, with a message naming the entry) an empty or
// repeated expression name, an empty or repeated muscle name, an activation outside [0, 1].
bool SaveExpressionLibrary(const std::string& path, const std::vector<Expression>& library,
                           Diagnostics* diag);

// Every muscle named in `library` is one of `muscle_names` (a rig's): an error per unknown
// name, with the path of the entry and the closest names of the rig. `where` prefixes the
// messages. False when any was unknown.
bool CheckLibraryMuscles(const std::vector<Expression>& library,
                         const std::vector<std::string>& muscle_names, const std::string& where,
                         Diagnostics* diag);

}  // namespace mimetic
