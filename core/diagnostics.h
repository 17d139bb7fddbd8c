// core/diagnostics.h: problems found in offline input, collected rather than thrown.
//
// Loaders never stop at the first problem: they record every one with where it is (a JSON
// path such as `muscles[3].insertion`, or a mesh element such as `triangle 17`) and what was
// expected, and the caller prints them all. Runtime code does not use this (it returns bool).
#pragma once

#include <string>
#include <vector>

namespace mimetic {

enum class Severity { kError, kWarning };

struct Diagnostic {
  Severity severity = Severity::kError;
  std::string where;  // JSON path, file name or mesh element; may be empty
  std::string what;   // what is wrong and what was expected
};

class Diagnostics {
 public:
  void Error(std::string where, std::string what);
  void Warning(std::string where, std::string what);
  // Appends `other`, prefixing each `where` with `prefix` (e.g. the file name).
  void Append(const Diagnostics& other, const std::string& prefix = {});

  bool HasErrors() const;
  size_t ErrorCount() const;
  const std::vector<Diagnostic>& items() const { return items_; }
  bool empty() const { return items_.empty(); }
  void Clear() { items_.clear(); }

  // True when some diagnostic's `where` or `what` contains `needle` (for tests and tools).
  bool Contains(const std::string& needle) const;

  // One line per diagnostic: "error: <where>: <what>", at most `limit` lines (errors first
  // kept in order; warnings and errors alike), then one "... and N more (E errors, W warnings)
  // not shown" line. Tools print this, so 200,000 bad entries print 51 lines.
  static constexpr size_t kPrintLimit = 50;
  std::string Format(size_t limit = kPrintLimit) const;

 private:
  std::vector<Diagnostic> items_;
};

// Records at most `limit` errors of one kind, then (when destroyed) one "... and N more <kind>"
// line, so that a broken 100k-vertex mesh does not print 100k messages.
class CappedErrors {
 public:
  static constexpr size_t kDefaultLimit = 20;
  CappedErrors(Diagnostics* diag, std::string summary_where, std::string kind,
               size_t limit = kDefaultLimit)
      : diag_(diag), summary_where_(std::move(summary_where)), kind_(std::move(kind)),
        limit_(limit) {}
  ~CappedErrors();
  CappedErrors(const CappedErrors&) = delete;
  CappedErrors& operator=(const CappedErrors&) = delete;
  void Add(std::string where, std::string what);
  size_t count() const { return count_; }

 private:
  Diagnostics* diag_;
  std::string summary_where_;
  std::string kind_;
  size_t limit_;
  size_t count_ = 0;
};

}  // namespace mimetic
