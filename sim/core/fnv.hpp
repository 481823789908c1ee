// FNV-1a, 64 bits: a checksum of bytes (not a cryptographic hash), for the
// seal of the files a run resumes from (runfile/h5_seal.hpp) and the identity of
// the state a run starts from (scene/initial_state.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace dem2d {

struct Fnv1a {
  std::uint64_t h = 1469598103934665603ULL;
  void add(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 1099511628211ULL;
  }
  // A string and its end, so that ("ab", "c") and ("a", "bc") differ.
  void add(const std::string& s) {
    add(s.data(), s.size());
    add("\0", 1);
  }
  // 16 hexadecimal digits.
  std::string hex() const {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
  }
};

}  // namespace dem2d
