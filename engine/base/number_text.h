#pragma once
// A number as messages and notes print it: printf's %g with `significant` digits.
#include <cstdio>
#include <string>

namespace refrax {

inline std::string numberText(double v, int significant = 6) {
  char s[40];
  std::snprintf(s, sizeof s, "%.*g", significant, v);
  return s;
}

}  // namespace refrax
