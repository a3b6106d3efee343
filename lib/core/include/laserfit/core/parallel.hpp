#pragma once
// Runs f(i) for every i in [0, n) on up to `jobs` threads (never more than n; on the calling
// thread when that is one), one index at a time (so each runs exactly once, in no fixed order:
// results must be stored by index). The first exception stops the handing out of work and is
// rethrown as laserfit::Error once every thread has joined — a worker's exception must never
// reach std::terminate.
#include <cstddef>
#include <functional>

namespace laserfit {

void parallel_for(size_t n, int jobs, const std::function<void(size_t)>& f);

}  // namespace laserfit
