// The law's terms in this test build: the engine's list with InnerPull added
// (DEM2D_LAW_TERMS_HEADER, tests/CMakeLists.txt).
#pragma once

#include "inner_pull.hpp"

namespace dem2d {
using LawTerms = TermList<NormalLaw, Cohesion, InnerPull, Tangential, Rolling>;
}  // namespace dem2d
