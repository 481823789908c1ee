// The one loop over a run's snapshots that the stages plug their measures into
// (in the manner of freud's compute(): a measure is a pure function of one
// snapshot and opens no file). Snapshots are read in order, in batches of
// 2 x threads (the HDF5 reads are serial), measured in parallel, and handed to
// `fold` one by one in snapshot order, so that the result does not depend on
// the thread count when the measure is pure.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

#include "common/snapshot_source.hpp"
#include "common/stage_error.hpp"

namespace dem2d::analysis {

// measure(k, snapshot) -> M, or measure(k, snapshot, displacement) -> M with
// the grains' PIV-like displacements before snapshot k (SnapshotSource), for
// every k of `ks` (increasing); then fold(k, M&&) in the order of `ks`. An
// exception of a measure (or of fold) becomes a StageError "PATH: snapshot K:
// WHAT" (the first in snapshot order).
template <class Measure, class Fold>
void for_each_snapshot(const SnapshotSource& run, const std::vector<std::size_t>& ks, int threads, Measure measure,
                       Fold fold) {
  using Disp = std::vector<Vec2>;
  constexpr bool with_disp = std::is_invocable_v<Measure, std::size_t, const Snapshot&, const Disp&>;
  const auto call = [&](std::size_t k, const Snapshot& s, const Disp& d) {
    if constexpr (with_disp) return measure(k, s, d);
    else return measure(k, s);
  };
  using M = decltype(call(std::size_t{}, std::declval<const Snapshot&>(), std::declval<const Disp&>()));
  const auto named = [&](std::size_t k, const std::string& what) {
    return StageError(run.path() + ": snapshot " + std::to_string(k) + ": " + what);
  };
  const std::size_t batch = static_cast<std::size_t>(std::max(1, 2 * threads));
  for (std::size_t q0 = 0; q0 < ks.size(); q0 += batch) {
    const std::size_t q1 = std::min(ks.size(), q0 + batch);
    std::vector<Snapshot> snaps;
    std::vector<Disp> disp(q1 - q0);
    for (std::size_t q = q0; q < q1; ++q) {
      snaps.push_back(run.snapshot(ks[q]));
      if (with_disp && run.has_displacements()) disp[q - q0] = run.displacement(ks[q]);
    }
    std::vector<M> out(snaps.size());
    std::vector<std::string> errors(snaps.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (std::size_t q = 0; q < snaps.size(); ++q) {
      try {
        out[q] = call(ks[q0 + q], snaps[q], disp[q]);
      } catch (const std::exception& e) {
        errors[q] = e.what();
      }
    }
    for (std::size_t q = 0; q < snaps.size(); ++q) {
      if (!errors[q].empty()) throw named(ks[q0 + q], errors[q]);
      try {
        fold(ks[q0 + q], std::move(out[q]));
      } catch (const std::exception& e) {
        throw named(ks[q0 + q], e.what());
      }
    }
  }
}

// One value of each per-snapshot result, as a column (a series for the stage's file).
template <class T = double, class Result, class Get>
std::vector<T> column_of(const std::vector<Result>& results, Get get) {
  std::vector<T> v;
  v.reserve(results.size());
  for (const Result& x : results) v.push_back(static_cast<T>(get(x)));
  return v;
}

// Snapshot indices 0, every, 2 every, ... and the last one (every >= 1).
std::vector<std::size_t> every_kth(std::size_t snapshots, std::size_t every);
// `count` of the snapshot indices ks, evenly spread, the first and last included.
std::vector<std::size_t> spread_over(const std::vector<std::size_t>& ks, std::size_t count);

// Every snapshot of the run: 0, 1, ..., S - 1.
inline std::vector<std::size_t> all_snapshots(const SnapshotSource& run) {
  std::vector<std::size_t> ks(run.snapshots());
  std::iota(ks.begin(), ks.end(), std::size_t{0});
  return ks;
}

}  // namespace dem2d::analysis
