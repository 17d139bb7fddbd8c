#include "expressions/offline/activation_binding.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace mimetic {
namespace {

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string Suggest(const std::vector<std::string>& names, const std::string& wrong) {
  // Names that contain what was typed come first (`frontalis` -> `frontalis_inner_L`), then
  // the rest by edit distance.
  std::vector<std::pair<size_t, std::string>> ranked;
  for (const std::string& n : names) {
    const bool contains = !wrong.empty() && n.find(wrong) != std::string::npos;
    ranked.push_back({contains ? n.size() - wrong.size() : 1000 + EditDistance(n, wrong), n});
  }
  std::sort(ranked.begin(), ranked.end());
  std::string out;
  for (size_t i = 0; i < ranked.size() && i < 3; ++i) out += (i ? ", " : "") + ranked[i].second;
  return out;
}

}  // namespace

std::string ClosestNames(const std::vector<std::string>& names, const std::string& wrong) {
  return Suggest(names, wrong);
}

bool BindActivations(const std::vector<std::string>& muscle_names,
                     const std::vector<std::string>& assignments, std::vector<float>* out,
                     Diagnostics* diag) {
  out->assign(muscle_names.size(), 0.f);
  std::vector<bool> seen(muscle_names.size(), false);
  const size_t errors_before = diag->ErrorCount();
  for (const std::string& a : assignments) {
    const std::string where = "--set " + a;
    const size_t eq = a.find('=');
    if (eq == std::string::npos || eq == 0) {
      diag->Error(where, "expected NAME=VALUE with a muscle name and a number in [0, 1]");
      continue;
    }
    const std::string name = a.substr(0, eq), value = a.substr(eq + 1);
    // NAME sets NAME_L and NAME_R together when the rig has no muscle NAME but has both.
    std::vector<size_t> targets;
    const auto it = std::find(muscle_names.begin(), muscle_names.end(), name);
    if (it != muscle_names.end()) {
      targets.push_back(size_t(it - muscle_names.begin()));
    } else {
      const auto l = std::find(muscle_names.begin(), muscle_names.end(), name + "_L");
      const auto r = std::find(muscle_names.begin(), muscle_names.end(), name + "_R");
      if (l != muscle_names.end() && r != muscle_names.end())
        targets = {size_t(l - muscle_names.begin()), size_t(r - muscle_names.begin())};
    }
    if (targets.empty()) {
      diag->Error(where, "unknown muscle '" + name + "'" +
                             (muscle_names.empty() ? std::string(" (the rig has no muscles)")
                                                   : "; closest: " + Suggest(muscle_names, name)));
      continue;
    }
    errno = 0;
    char* end = nullptr;
    const double v = value.empty() ? NAN : std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
      diag->Error(where, "value '" + value + "' is not a finite number (expected a number in [0, 1])");
      continue;
    }
    if (v < 0.0 || v > 1.0) {
      diag->Error(where, "value " + value + " is outside [0, 1] (activations are fractions of "
                                            "full contraction)");
      continue;
    }
    for (size_t index : targets) {
      if (seen[index]) {
        diag->Error(where, "muscle '" + muscle_names[index] + "' is set more than once");
        continue;
      }
      seen[index] = true;
      (*out)[index] = float(v);
    }
  }
  return diag->ErrorCount() == errors_before;
}

}  // namespace mimetic
