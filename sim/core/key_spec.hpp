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

// flag: an on/off value stored as a number, 1 (on) or 0 (off)
enum class Rule { finite, positive, non_negative, unit_open_closed, flag, interval };

struct Num {
  const char* what;  // "normal stiffness"
  const char* unit;  // "N/m", "" if dimensionless
  Rule rule;
  // Rule::interval: lo .. hi, each end open or closed
  double lo = 0.0, hi = 0.0;
  bool lo_open = false, hi_open = false;
};

// "> 0", "in [0, 1)", "0 or 1"
inline std::string rule_text(const Num& n) {
  constexpr const char* kText[] = {"finite", "> 0", ">= 0", "in (0, 1]", "0 or 1"};
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
    case Rule::flag: return v == 0.0 || v == 1.0;
    case Rule::interval:
      return std::isfinite(v) && (n.lo_open ? v > n.lo : v >= n.lo) && (n.hi_open ? v < n.hi : v <= n.hi);
  }
  return false;
}

// The rule rule_text spells ("finite", "> 0", ">= 0", "0 or 1", "in (0, 1]", "in [lo, hi)"), to check
// values with obeys(); nothing if the text is none of these.
inline std::optional<Num> rule_from_text(const std::string& rule) {
  for (const Rule r : {Rule::finite, Rule::positive, Rule::non_negative, Rule::flag})
    if (rule == rule_text(Num{"", "", r})) return Num{"", "", r};
  if (rule.size() < 8 || rule.compare(0, 3, "in ") != 0 || (rule[3] != '(' && rule[3] != '[') ||
      (rule.back() != ')' && rule.back() != ']'))
    return std::nullopt;
  std::istringstream is(std::string(rule.begin() + 4, rule.end() - 1));
  Num n{"", "", Rule::interval};
  char comma = 0;
  if (!(is >> n.lo >> comma >> n.hi) || comma != ',' || !(is >> std::ws).eof()) return std::nullopt;
  n.lo_open = rule[3] == '(';
  n.hi_open = rule.back() == ')';
  return n;
}

// "normal stiffness in N/m"
inline std::string describe(const Num& n) {
  return std::string(n.what) + (*n.unit ? std::string(" in ") + n.unit : "");
}
// "normal stiffness in N/m, > 0"
inline std::string range_text(const Num& n) { return describe(n) + ", " + rule_text(n); }

}  // namespace dem2d
