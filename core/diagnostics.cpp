#include "core/diagnostics.h"

namespace mimetic {

void Diagnostics::Error(std::string where, std::string what) {
  items_.push_back({Severity::kError, std::move(where), std::move(what)});
}

void Diagnostics::Warning(std::string where, std::string what) {
  items_.push_back({Severity::kWarning, std::move(where), std::move(what)});
}

void Diagnostics::Append(const Diagnostics& other, const std::string& prefix) {
  for (const Diagnostic& d : other.items_) {
    Diagnostic copy = d;
    if (!prefix.empty()) copy.where = copy.where.empty() ? prefix : prefix + ": " + copy.where;
    items_.push_back(std::move(copy));
  }
}

bool Diagnostics::HasErrors() const { return ErrorCount() > 0; }

size_t Diagnostics::ErrorCount() const {
  size_t n = 0;
  for (const Diagnostic& d : items_) n += d.severity == Severity::kError;
  return n;
}

bool Diagnostics::Contains(const std::string& needle) const {
  for (const Diagnostic& d : items_) {
    if (d.where.find(needle) != std::string::npos || d.what.find(needle) != std::string::npos)
      return true;
  }
  return false;
}

std::string Diagnostics::Format(size_t limit) const {
  std::string out;
  size_t shown = 0;
  for (const Diagnostic& d : items_) {
    if (shown++ == limit) break;
    out += d.severity == Severity::kError ? "error: " : "warning: ";
    if (!d.where.empty()) out += d.where + ": ";
    out += d.what;
    out += '\n';
  }
  if (items_.size() > limit) {
    size_t errors = 0, warnings = 0;
    for (size_t i = limit; i < items_.size(); ++i)
      (items_[i].severity == Severity::kError ? errors : warnings) += 1;
    out += "... and " + std::to_string(items_.size() - limit) + " more (" +
           std::to_string(errors) + " errors, " + std::to_string(warnings) +
           " warnings) not shown\n";
  }
  return out;
}

CappedErrors::~CappedErrors() {
  if (count_ > limit_)
    diag_->Error(summary_where_, "... and " + std::to_string(count_ - limit_) + " more " + kind_);
}

void CappedErrors::Add(std::string where, std::string what) {
  if (count_++ < limit_) diag_->Error(std::move(where), std::move(what));
}

}  // namespace mimetic
