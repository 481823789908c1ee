// The effects of the term-contract test build: the engine's list (core/effects.hpp) and the proof
// term's own line (DEM2D_EXTRA_EFFECTS_HEADER, tests/CMakeLists.txt), as a new term adds its line there.
#define DEM2D_EXTRA_EFFECTS(X) X(inner_pull, none, "pull inside the overlap (tests/extra_term/inner_pull.hpp)")
