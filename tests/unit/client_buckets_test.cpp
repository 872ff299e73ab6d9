// Per-client token buckets (http/front/client_buckets.hpp): a burst, then the rate, each client on
// its own; how long a refused client is told to wait; and a table that never holds more than
// its capacity, dropping the longest-idle client first. The clock is the `now` argument.
#include <gtest/gtest.h>

#include <string>

#include "http/front/client_buckets.hpp"

namespace client_buckets_test {
namespace {

using locus::http::ClientBuckets;

// "c12": appended, as GCC 12 misreads "c" + std::to_string(i) (-Wrestrict).
std::string name(const char* prefix, int i) { return std::string(prefix).append(std::to_string(i)); }

TEST(ClientBuckets, ABurstThenTheRate) {
    ClientBuckets b(2.0, 5, 100);  // 2 a second, 5 at once
    for (int i = 0; i < 5; ++i) EXPECT_TRUE(b.take("a", 10.0).allowed) << i;
    const auto refused = b.take("a", 10.0);
    EXPECT_FALSE(refused.allowed);
    EXPECT_DOUBLE_EQ(refused.wait_s, 0.5);  // one token at 2 a second
    EXPECT_FALSE(b.take("a", 10.25).allowed);
    EXPECT_DOUBLE_EQ(b.take("a", 10.25).wait_s, 0.25);  // refusals do not push the refill back
    EXPECT_TRUE(b.take("a", 10.5).allowed);
    EXPECT_FALSE(b.take("a", 10.5).allowed);
    // Ten idle seconds refill no more than the burst.
    for (int i = 0; i < 5; ++i) EXPECT_TRUE(b.take("a", 20.5).allowed) << i;
    EXPECT_FALSE(b.take("a", 20.5).allowed);
}

TEST(ClientBuckets, ACostSpendsThatManyTokens) {
    ClientBuckets b(10.0, 1000, 100);  // bytes, say: 10 a second, 1000 at once
    EXPECT_TRUE(b.take("a", 0, 600).allowed);
    const auto refused = b.take("a", 0, 600);  // 400 left
    EXPECT_FALSE(refused.allowed);
    EXPECT_DOUBLE_EQ(refused.wait_s, 20.0);  // 200 short at 10 a second
    EXPECT_TRUE(b.take("a", 0, 400).allowed);
    EXPECT_FALSE(b.take("a", 0, 1).allowed);
}

TEST(ClientBuckets, ACostAboveTheBurstIsTakenFromAFullBucketAndPaidAfter) {
    ClientBuckets b(2.0, 5, 100);
    EXPECT_TRUE(b.take("a", 0, 1).allowed);
    EXPECT_FALSE(b.take("a", 0, 8).allowed);  // four left: a batch above the burst needs a full bucket
    EXPECT_DOUBLE_EQ(b.take("a", 0, 8).wait_s, 0.5);
    EXPECT_TRUE(b.take("a", 0.5, 8).allowed);  // full again: taken, leaving 5 - 8 = -3
    const auto after = b.take("a", 0.5, 1);
    EXPECT_FALSE(after.allowed);
    EXPECT_DOUBLE_EQ(after.wait_s, 2.0);  // from -3 to 1 at 2 a second
}

TEST(ClientBuckets, EachClientHasItsOwn) {
    ClientBuckets b(1.0, 2, 100);
    EXPECT_TRUE(b.take("a", 0).allowed);
    EXPECT_TRUE(b.take("a", 0).allowed);
    EXPECT_FALSE(b.take("a", 0).allowed);
    EXPECT_TRUE(b.take("b", 0).allowed);
    EXPECT_TRUE(b.take("b", 0).allowed);
    EXPECT_FALSE(b.take("b", 0).allowed);
}

TEST(ClientBuckets, ASlowRateWaitsLong) {
    ClientBuckets b(0.1, 1, 10);  // one every 10 s
    EXPECT_TRUE(b.take("a", 100).allowed);
    const auto r = b.take("a", 103);
    EXPECT_FALSE(r.allowed);
    EXPECT_NEAR(r.wait_s, 7.0, 1e-9);
}

TEST(ClientBuckets, AClockGoingBackRefillsNothing) {
    ClientBuckets b(1.0, 1, 10);
    EXPECT_TRUE(b.take("a", 50).allowed);
    EXPECT_FALSE(b.take("a", 40).allowed);
    EXPECT_TRUE(b.take("a", 51).allowed);
}

TEST(ClientBuckets, TheTableIsBoundedAndDropsTheLongestIdle) {
    ClientBuckets b(1.0, 3, 4);
    // Five clients spend their whole bursts: the first is dropped for the fifth.
    for (int c = 0; c < 5; ++c)
        for (int i = 0; i < 3; ++i) EXPECT_TRUE(b.take(name("c", c), 0.01 * c).allowed);
    EXPECT_EQ(b.size(), 4u);
    EXPECT_FALSE(b.take("c4", 0.05).allowed);
    EXPECT_FALSE(b.take("c1", 0.05).allowed);  // still held: still empty
    EXPECT_TRUE(b.take("c0", 0.05).allowed);   // dropped: a full bucket again
    EXPECT_LE(b.size(), 4u);
    // Ten thousand clients later the table still holds four.
    for (int c = 0; c < 10'000; ++c) b.take(name("x", c), 1.0);
    EXPECT_EQ(b.size(), 4u);
}

TEST(ClientBuckets, FullBucketsAreNotKept) {
    ClientBuckets b(1.0, 2, 100);
    for (int c = 0; c < 50; ++c) EXPECT_TRUE(b.take(name("c", c), 0).allowed);
    EXPECT_EQ(b.size(), 50u);
    // A second later each of them is full again; the next request lets them go.
    EXPECT_TRUE(b.take("late", 1.0).allowed);
    EXPECT_EQ(b.size(), 1u);
}

TEST(ClientBuckets, BadParametersAreRefused) {
    EXPECT_THROW(ClientBuckets(0, 1, 1), std::invalid_argument);
    EXPECT_THROW(ClientBuckets(1, 0.5, 1), std::invalid_argument);
    EXPECT_THROW(ClientBuckets(1, 1, 0), std::invalid_argument);
}

}  // namespace
}  // namespace client_buckets_test
