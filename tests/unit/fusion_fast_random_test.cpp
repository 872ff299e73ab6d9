// The particle filters' generator (fusion/fast_random.hpp): its normal deviates have the
// standard normal's moments and tails (the ziggurat's layers and its tail both drawn), its
// uniforms are uniform, and a seed (a track's id) gives one stream, which a copy continues.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "locus/motion/fusion/fast_random.hpp"

namespace fusion_fast_random_test {
namespace {

using locus::fusion::FastRandom;

TEST(FastRandom, NormalsHaveTheStandardNormalsMomentsAndTails) {
    FastRandom rng(42);
    constexpr int kN = 2'000'000;
    double sum = 0, sum2 = 0, sum4 = 0;
    int beyond1 = 0, beyond2 = 0, beyond3 = 0, beyond_tail = 0, negative = 0;
    for (int i = 0; i < kN; ++i) {
        const double v = rng.normal();
        sum += v;
        sum2 += v * v;
        sum4 += v * v * v * v;
        const double a = std::abs(v);
        beyond1 += a > 1.0;
        beyond2 += a > 2.0;
        beyond3 += a > 3.0;
        beyond_tail += a > 3.6;  // past the ziggurat's base layer: only the tail draws these
        negative += v < 0;
    }
    const double mean = sum / kN, var = sum2 / kN - mean * mean;
    EXPECT_NEAR(mean, 0.0, 0.003);
    EXPECT_NEAR(var, 1.0, 0.004);
    EXPECT_NEAR(sum4 / kN, 3.0, 0.03);  // kurtosis
    // P(|Z| > k): 0.31731, 0.045500, 0.0026998, 0.00031824; binomial σ ≈ 0.0003, 0.00015, 4e-5, 1.3e-5.
    EXPECT_NEAR(static_cast<double>(beyond1) / kN, 0.31731, 0.0015);
    EXPECT_NEAR(static_cast<double>(beyond2) / kN, 0.045500, 0.0008);
    EXPECT_NEAR(static_cast<double>(beyond3) / kN, 0.0026998, 0.0002);
    EXPECT_NEAR(static_cast<double>(beyond_tail) / kN, 0.00031824, 0.00007);
    EXPECT_NEAR(static_cast<double>(negative) / kN, 0.5, 0.002);
}

TEST(FastRandom, UniformsAreUniform) {
    FastRandom rng(7);
    std::vector<int> bins(10, 0);
    std::vector<int> picked(7, 0);
    constexpr int kN = 1'000'000;
    for (int i = 0; i < kN; ++i) {
        const double u = rng.uniform();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        ++bins[static_cast<int>(u * 10)];
        ++picked[static_cast<std::size_t>(rng.below(7))];
    }
    for (int b : bins) EXPECT_NEAR(b, kN / 10, 1500);  // σ ≈ 300
    for (int p : picked) EXPECT_NEAR(p, kN / 7, 1500);
}

TEST(FastRandom, ASeedGivesOneStreamAndACopyContinuesIt) {
    FastRandom a(3), b(3), c(4);
    for (int i = 0; i < 100; ++i) {
        const auto x = a.next();
        EXPECT_EQ(x, b.next());
        EXPECT_NE(x, c.next());  // neighbouring seeds (track ids) give unrelated streams
    }
    FastRandom copy = a;
    for (int i = 0; i < 100; ++i) EXPECT_EQ(copy.normal(), a.normal());
    FastRandom zero(0);
    EXPECT_NE(zero.next(), zero.next());  // seed 0 is a seed like any other
}

}  // namespace
}  // namespace fusion_fast_random_test
