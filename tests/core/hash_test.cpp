#include "core/hash.h"

#include <gtest/gtest.h>

namespace hipfai {
namespace {

TEST(Hasher, EqualInputsGiveEqualKeysAndDifferentOnesDiffer) {
  EXPECT_EQ(Hasher().add("abc").add(1.5).hex(), Hasher().add("abc").add(1.5).hex());
  EXPECT_NE(Hasher().add("ab").add("c").hex(), Hasher().add("a").add("bc").hex());
  EXPECT_NE(Hasher().add(0.1).hex(), Hasher().add(0.1 + 1e-15).hex());
  EXPECT_EQ(Hasher().hex().size(), 16u);
}

// FNV-1a 64 of the empty string is the offset basis; one byte "a" then separator is fixed by the
// algorithm's definition: check the first step by hand.
TEST(Hasher, FollowsFnv1a) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  h ^= 'a';
  h *= 0x100000001b3ULL;
  h ^= 0xff;
  h *= 0x100000001b3ULL;
  EXPECT_EQ(Hasher().add("a").value(), h);
}

}  // namespace
}  // namespace hipfai
