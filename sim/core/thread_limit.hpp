// The --threads option of dem2d run and of the analysis stages: 0 (the program
// chooses: dem2d run from the scene's size and the cores free, a stage OpenMP's
// default) up to 4 threads per processor. More only wait on
// each other, and at 65536 libgomp fails without a message.
#pragma once

#include <omp.h>

#include <algorithm>
#include <charconv>
#include <string>

namespace dem2d {

inline int max_threads() { return 4 * std::max(omp_get_num_procs(), 1); }

// "" when `text` is a whole number of threads in range; else why not
inline std::string thread_count_problem(const std::string& text) {
  long n = -1;
  const char* end = text.data() + text.size();
  const auto [at, ec] = std::from_chars(text.data(), end, n);
  if (ec == std::errc() && at == end && n >= 0 && n <= max_threads()) return "";
  return text + ": must be an integer from 0 (the program chooses) to " + std::to_string(max_threads()) + " (4 x the " +
         std::to_string(max_threads() / 4) + " processors here)";
}

}  // namespace dem2d
