#pragma once
// Software prefetch of whole objects, for loops whose next data the hardware prefetcher does not foresee (random
// records, the next row of a tile).
#include <cstddef>

namespace candela {

// Starts loading every cache line of the `count` objects at `first` (an object of 72 bytes may straddle two or three),
// with kWrite for writing (the lines come in owned, so that the stores that follow do not wait for them). Never
// faults.
template <int kWrite = 0, class T>
inline void prefetch_objects(const T* first, size_t count) {
  const char* p = reinterpret_cast<const char*>(first);
  const size_t bytes = sizeof(T) * count;
  for (size_t at = 0; at < bytes; at += 64) __builtin_prefetch(p + at, kWrite);  // one object: unrolled
  // The last byte's line (none for no objects). Not an early return for count 0: with one, GCC 12 dropped the
  // prefetches altogether (the binary's 142 prefetch instructions became 39).
  if (bytes > 0) __builtin_prefetch(p + bytes - 1, kWrite);
}
template <class T>
inline void prefetch_object(const T& x) {
  prefetch_objects(&x, 1);
}
// The lines of objects the caller is about to overwrite.
template <class T>
inline void prefetch_to_write(const T* first, size_t count = 1) {
  prefetch_objects<1>(first, count);
}

}  // namespace candela
