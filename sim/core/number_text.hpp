// Numbers in messages: never the 300 digits std::to_string gives 1e300.
#pragma once

#include <charconv>
#include <sstream>
#include <string>

namespace dem2d {

// The shortest text that reads back as v ("0.003", "1e+300").
inline std::string shortest(double v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

// A derived quantity: 3 significant digits ("0.00449", "4.96e+10").
inline std::string sig3(double v) {
  std::ostringstream os;
  os.precision(3);
  os << v;
  return os.str();
}

}  // namespace dem2d
