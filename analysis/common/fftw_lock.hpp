// FFTW's planner is not thread-safe (fftw_execute is): every stage makes and
// destroys its plans under this one lock, so that analyses may run side by
// side in one process (the planted-truth suite runs several).
#pragma once

#include <mutex>

namespace dem2d::analysis {

std::mutex& fftw_planner_lock();

}  // namespace dem2d::analysis
