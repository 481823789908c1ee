// What a numeric key of a scene file means: what it is, its unit and its
// allowed range. Declared beside the code that uses the value (a contact
// term's parameters, contact/law_terms.hpp) and checked by the scene reader
// (scene/scene_toml.cpp), which names the key, the value and this range in
// its messages.
#pragma once

#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "core/number_text.hpp"  // sig3, shortest

namespace dem2d {

enum class Rule { finite, positive, non_negative, unit_open_closed, interval };

struct Num {
  const char* what;  // "normal stiffness"
  const char* unit;  // "N/m", "" if dimensionless
  Rule rule;
  // Rule::interval: lo .. hi, each end open or closed
  double lo = 0.0, hi = 0.0;
  bool lo_open = false, hi_open = false;
};

// "> 0", "in [0, 1)"
inline std::string rule_text(const Num& n) {
  constexpr const char* kText[] = {"finite", "> 0", ">= 0", "in (0, 1]"};
  if (n.rule != Rule::interval) return kText[static_cast<int>(n.rule)];
  std::ostringstream os;
  os << "in " << (n.lo_open ? "(" : "[") << n.lo << ", " << n.hi << (n.hi_open ? ")" : "]");
  return os.str();
}

inline bool obeys(const Num& n, double v) {
  switch (n.rule) {
    case Rule::finite: return std::isfinite(v);
    case Rule::positive: return std::isfinite(v) && v > 0.0;
    case Rule::non_negative: return std::isfinite(v) && v >= 0.0;
    case Rule::unit_open_closed: return v > 0.0 && v <= 1.0;
    case Rule::interval:
      return std::isfinite(v) && (n.lo_open ? v > n.lo : v >= n.lo) && (n.hi_open ? v < n.hi : v <= n.hi);
  }
  return false;
}

// Whether v obeys a rule as rule_text spells it ("finite", "> 0", ">= 0",
// "in (0, 1]", "in [lo, hi)"); nothing if the text is none of these.
inline std::optional<bool> obeys_rule_text(const std::string& rule, double v) {
  if (rule == "finite") return std::isfinite(v);
  if (rule == "> 0") return std::isfinite(v) && v > 0.0;
  if (rule == ">= 0") return std::isfinite(v) && v >= 0.0;
  if (rule.size() < 8 || rule.compare(0, 3, "in ") != 0 || (rule[3] != '(' && rule[3] != '[') ||
      (rule.back() != ')' && rule.back() != ']'))
    return std::nullopt;
  std::istringstream is(std::string(rule.begin() + 4, rule.end() - 1));
  double lo = 0.0, hi = 0.0;
  char comma = 0;
  if (!(is >> lo >> comma >> hi) || comma != ',' || !(is >> std::ws).eof()) return std::nullopt;
  return std::isfinite(v) && (rule[3] == '(' ? v > lo : v >= lo) && (rule.back() == ')' ? v < hi : v <= hi);
}

// "normal stiffness in N/m"
inline std::string describe(const Num& n) {
  return std::string(n.what) + (*n.unit ? std::string(" in ") + n.unit : "");
}
// "normal stiffness in N/m, > 0"
inline std::string range_text(const Num& n) { return describe(n) + ", " + rule_text(n); }

}  // namespace dem2d
