#pragma once
// Every parallel loop in Candela goes through these functions, so one place says how work is split over
// threads.
//
// Normal builds run on TBB's workers. A ThreadSanitizer build (CANDELA_TSAN, set by
// -DCANDELA_SANITIZE=thread) runs the same loop bodies on std::threads started for the loop and joined
// after it: Debian's libtbb is not instrumented, so TSan cannot see the ordering a TBB task spawn and
// wait provide and reports every parallel loop (and TBB's own task bookkeeping) as a race, while it sees
// thread creation and join exactly. The bodies, which are what the check is about, are the same; only the
// scheduler differs.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#ifdef CANDELA_TSAN
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#endif

namespace candela {

// Runs fn(b, e) over sub-ranges [b, e) of [begin, end) of `grain` indices (the last may be shorter), in
// parallel; returns when all have run.
template <class Index, class Fn>
void parallel_for_ranges(Index begin, Index end, Index grain, Fn&& fn) {
#ifdef CANDELA_TSAN
  // Workers take the next range from a shared counter until none is left (as many workers as TBB would
  // use, so --threads still applies).
  if (end <= begin) return;
  const size_t ranges = (size_t(end - begin) + size_t(grain) - 1) / size_t(grain);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t r; (r = next.fetch_add(1)) < ranges;) {
      const Index b = Index(begin + Index(r) * grain);
      fn(b, Index(std::min<size_t>(size_t(end - b), size_t(grain)) + b));
    }
  };
  const size_t threads =
      std::min<size_t>(ranges, tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  std::vector<std::thread> workers;
  for (size_t t = 1; t < threads; ++t) workers.emplace_back(work);
  work();
  for (std::thread& w : workers) w.join();
#else
  tbb::parallel_for(tbb::blocked_range<Index>(begin, end, grain),
                    [&](const tbb::blocked_range<Index>& r) { fn(r.begin(), r.end()); });
#endif
}

// Runs fn(i) for every i in [begin, end) in parallel (TBB chooses how many indices a task takes).
template <class Index, class Fn>
void parallel_for(Index begin, Index end, Fn&& fn) {
  parallel_for_ranges(begin, end, Index(1), [&](Index b, Index e) {
    for (Index i = b; i < e; ++i) fn(i);
  });
}

// Runs a() and b(), possibly at the same time; returns when both have run.
template <class A, class B>
void parallel_invoke(A&& a, B&& b) {
#ifdef CANDELA_TSAN
  std::thread other(b);
  a();
  other.join();
#else
  tbb::parallel_invoke(a, b);
#endif
}

}  // namespace candela
