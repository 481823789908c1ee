// How many threads `dem2d run` uses when --threads is not given: as many as
// the scene's size makes worth their barriers and as the machine has cores
// free right now (two threads on a core shared with another program waited
// on each other every step). Results do not depend on it (engine.md,
// "Thread count"); the run's first progress line says the choice and why.
#pragma once

#include <cstddef>
#include <string>

namespace dem2d {

struct ThreadChoice {
  int threads = 1;
  std::string why;
};

// grains: the scene's particles; cores: the processors this process may use;
// free_cores: of those, how many were idle (free_cores_now()).
ThreadChoice choose_threads(std::size_t grains, int cores, double free_cores);

// "1 thread", "2 threads"
std::string threads_text(int n);

// The processors idle over the next `seconds` (from /proc/stat; `cores` if it cannot be read).
double free_cores_now(int cores, double seconds = 0.1);

}  // namespace dem2d
