#pragma once
// Software prefetch of whole objects, for loops whose next data the hardware prefetcher does not foresee (random
// records, the next row of a tile).
#include <cstddef>

namespace candela {

// Starts loading every cache line `x` occupies (an object of 72 bytes may straddle two or three). Never faults.
template <class T>
inline void prefetch_object(const T& x) {
  const char* p = reinterpret_cast<const char*>(&x);
  for (size_t at = 0; at < sizeof(T); at += 64) __builtin_prefetch(p + at);  // unrolled: sizeof(T) is a constant
  __builtin_prefetch(p + sizeof(T) - 1);
}

}  // namespace candela
