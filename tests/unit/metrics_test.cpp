// The two percentile definitions and the mean behind every reported accuracy and latency figure.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "locus/metrics.hpp"

namespace metrics_test {
namespace {

using locus::metrics::mean;
using locus::metrics::percentile_interpolated;
using locus::metrics::percentile_nearest_rank;

const std::vector<double> kFour{1.0, 2.0, 4.0, 8.0};

TEST(PercentileInterpolated, InterpolatesBetweenOrderStatistics) {
    // pos = p · (n − 1) = p · 3
    EXPECT_DOUBLE_EQ(percentile_interpolated(kFour, 0.5), 3.0);    // pos 1.5: 2 + 0.5 · (4 − 2)
    EXPECT_DOUBLE_EQ(percentile_interpolated(kFour, 0.75), 5.0);   // pos 2.25: 4 + 0.25 · (8 − 4)
    EXPECT_NEAR(percentile_interpolated(kFour, 0.95), 7.4, 1e-12); // pos 2.85: 4 + 0.85 · 4
    EXPECT_DOUBLE_EQ(percentile_interpolated(kFour, 1.0 / 3.0), 2.0);  // pos 1: exactly the second value
}

TEST(PercentileInterpolated, EndsAreTheExtremes) {
    EXPECT_DOUBLE_EQ(percentile_interpolated(kFour, 0.0), 1.0);
    EXPECT_DOUBLE_EQ(percentile_interpolated(kFour, 1.0), 8.0);
}

TEST(PercentileInterpolated, OneValueIsEveryPercentile) {
    const std::vector<double> one{2.5};
    for (double p : {0.0, 0.5, 0.99, 1.0}) EXPECT_DOUBLE_EQ(percentile_interpolated(one, p), 2.5) << p;
}

TEST(PercentileInterpolated, EmptyIsNaN) {
    EXPECT_TRUE(std::isnan(percentile_interpolated(std::vector<double>{}, 0.5)));
}

TEST(PercentileNearestRank, PicksOneOfTheValues) {
    // rank = ceil(p · n), n = 4
    EXPECT_DOUBLE_EQ(percentile_nearest_rank(kFour, 0.5), 2.0);   // rank 2
    EXPECT_DOUBLE_EQ(percentile_nearest_rank(kFour, 0.51), 4.0);  // rank 3
    EXPECT_DOUBLE_EQ(percentile_nearest_rank(kFour, 0.75), 4.0);  // rank 3
    EXPECT_DOUBLE_EQ(percentile_nearest_rank(kFour, 0.95), 8.0);  // rank 4
    // Where the two definitions part: the interpolated p95 of the same values is 7.4.
    std::vector<double> twenty;
    for (int i = 1; i <= 20; ++i) twenty.push_back(i);
    EXPECT_DOUBLE_EQ(percentile_nearest_rank(twenty, 0.95), 19.0);  // rank 19
    EXPECT_NEAR(percentile_interpolated(twenty, 0.95), 19.05, 1e-12);  // pos 18.05
}

TEST(PercentileNearestRank, EndsAreTheExtremes) {
    EXPECT_DOUBLE_EQ(percentile_nearest_rank(kFour, 0.0), 1.0);  // rank 0 counts as the first
    EXPECT_DOUBLE_EQ(percentile_nearest_rank(kFour, 1.0), 8.0);
}

TEST(PercentileNearestRank, OneValueIsEveryPercentile) {
    const std::vector<double> one{-3.0};
    for (double p : {0.0, 0.5, 0.95, 1.0}) EXPECT_DOUBLE_EQ(percentile_nearest_rank(one, p), -3.0) << p;
}

TEST(PercentileNearestRank, EmptyIsNaN) {
    EXPECT_TRUE(std::isnan(percentile_nearest_rank(std::vector<double>{}, 0.95)));
}

TEST(Mean, OfValues) {
    EXPECT_DOUBLE_EQ(mean(kFour), 3.75);
    EXPECT_DOUBLE_EQ(mean(std::vector<double>{-1.0}), -1.0);
    EXPECT_TRUE(std::isnan(mean(std::vector<double>{})));
}

}  // namespace
}  // namespace metrics_test
