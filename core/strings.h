// core/strings.h: small string helpers shared by the modules.
#pragma once

#include <string_view>

namespace mimetic {

inline bool EndsWith(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

}  // namespace mimetic
