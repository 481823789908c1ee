// What a numeric key of a scene file means: what it is, its unit and its
// allowed range. Declared beside the code that uses the value (a contact
// term's parameters, contact/law_terms.hpp) and checked by the scene reader
// (scene/scene_toml.cpp), which names the key, the value and this range in
// its messages.
#pragma once

#include <cmath>
#include <sstream>
#include <string>

namespace dem2d {

enum class Rule { finite, positive, non_negative, unit_open_closed };

struct Num {
  const char* what;  // "normal stiffness"
  const char* unit;  // "N/m", "" if dimensionless
  Rule rule;
};

inline const char* rule_text(Rule r) {
  constexpr const char* kText[] = {"finite", "> 0", ">= 0", "in (0, 1]"};
  return kText[static_cast<int>(r)];
}

inline bool obeys(Rule r, double v) {
  return std::isfinite(v) && (r == Rule::finite || (r == Rule::positive && v > 0.0) ||
                              (r == Rule::non_negative && v >= 0.0) ||
                              (r == Rule::unit_open_closed && v > 0.0 && v <= 1.0));
}

// "normal stiffness in N/m"
inline std::string describe(const Num& n) {
  return std::string(n.what) + (*n.unit ? std::string(" in ") + n.unit : "");
}
// "normal stiffness in N/m, > 0"
inline std::string range_text(const Num& n) { return describe(n) + ", " + rule_text(n.rule); }

// A derived quantity in a message: 3 significant digits.
inline std::string sig3(double v) {
  std::ostringstream os;
  os.precision(3);
  os << v;
  return os.str();
}

}  // namespace dem2d
