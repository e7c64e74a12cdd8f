// The random streams (engine/rng.h): RngRow, which advances many streams together, gives each slot the
// numbers its own Rng gives one at a time, and leaves each stream where that Rng would be.
#include <gtest/gtest.h>

#include <cstring>

#include "engine/rng.h"

namespace candela {
namespace {

// 64 streams keyed in a row as the ReSTIR stages key a tile row's pixels (RngRow::key), 23 numbers each (an odd
// count, so that no slot's numbers line up with a vector's), filled in two calls over the first 61 slots: every
// number and every stream's next number must equal the bits of the scalar stream Rng::for_key gives.
TEST(Rng, RowGivesEachStreamsNumbers) {
  constexpr int kSlots = 64, kUsed = 61, kFirst = 9, kSecond = 14;
  RngRow<kSlots> row;
  row.key(kUsed, 1234, 1000, 5, 0xd1);
  Rng scalar[kSlots];
  for (int s = 0; s < kUsed; ++s) scalar[s] = Rng::for_key(1234, uint64_t(1000 + s), 5, 0xd1);
  std::vector<float> first(kFirst * kSlots), second(kSecond * kSlots);
  row.fill(kFirst, kUsed, first.data());
  row.fill(kSecond, kUsed, second.data());
  for (int s = 0; s < kUsed; ++s) {
    for (int n = 0; n < kFirst + kSecond; ++n) {
      const float expected = scalar[s].next_float();
      const float got = n < kFirst ? first[size_t(n * kSlots + s)] : second[size_t((n - kFirst) * kSlots + s)];
      ASSERT_EQ(std::memcmp(&expected, &got, sizeof(float)), 0) << "slot " << s << ", number " << n;
    }
    Rng rest = row.stream(s);
    for (int n = 0; n < 3; ++n) ASSERT_EQ(rest.next_u32(), scalar[s].next_u32()) << "slot " << s;
  }
}

}  // namespace
}  // namespace candela
