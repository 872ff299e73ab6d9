#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "locus/rss_stats.hpp"

namespace rss_stats_test {
namespace {

using locus::kMaxCount;
using locus::RssStats;

RssStats naive(const std::vector<double>& v) {
    double mean = 0.0;
    for (double x : v) mean += x;
    mean /= static_cast<double>(v.size());
    double m2 = 0.0;
    for (double x : v) m2 += (x - mean) * (x - mean);
    return {mean, m2 / static_cast<double>(v.size()), static_cast<std::int64_t>(v.size())};
}

TEST(RssStats, SingleSampleHasZeroVariance) {
    RssStats s;
    s.add(-61.0);
    EXPECT_EQ(s.count, 1);
    EXPECT_DOUBLE_EQ(s.mean, -61.0);
    EXPECT_DOUBLE_EQ(s.variance, 0.0);
}

TEST(RssStats, HandComputedPopulationVariance) {
    const std::vector<double> v{-60, -62, -64};
    const auto s = RssStats::of(v);
    EXPECT_DOUBLE_EQ(s.mean, -62.0);
    EXPECT_NEAR(s.variance, 8.0 / 3.0, 1e-12);
    EXPECT_EQ(s.count, 3);
}

TEST(RssStats, MergingTwoUploadsEqualsOneUploadOfAllSamplesInAnyOrder) {
    std::mt19937 rng(42);
    std::normal_distribution<double> noise(-70.0, 6.0);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<double> all(2 + rng() % 60);
        for (auto& x : all) x = noise(rng);
        const std::size_t cut = 1 + rng() % (all.size() - 1);
        const std::vector<double> a(all.begin(), all.begin() + static_cast<long>(cut));
        const std::vector<double> b(all.begin() + static_cast<long>(cut), all.end());
        const auto expected = naive(all);
        for (const auto& got : {locus::merged(RssStats::of(a), RssStats::of(b)),
                                locus::merged(RssStats::of(b), RssStats::of(a))}) {
            EXPECT_EQ(got.count, expected.count);
            EXPECT_NEAR(got.mean, expected.mean, 1e-9);
            EXPECT_NEAR(got.variance, expected.variance, 1e-9);
        }
    }
}

TEST(RssStats, MergeIsAssociativeOverManyUploads) {
    std::vector<double> all;
    std::vector<RssStats> parts;
    for (int p = 0; p < 7; ++p) {
        std::vector<double> chunk;
        for (int i = 0; i <= p; ++i) chunk.push_back(-50.0 - p * 3.0 - i * 0.5);
        all.insert(all.end(), chunk.begin(), chunk.end());
        parts.push_back(RssStats::of(chunk));
    }
    std::reverse(parts.begin(), parts.end());
    RssStats acc;
    for (const auto& p : parts) acc.merge(p);
    const auto expected = naive(all);
    EXPECT_NEAR(acc.mean, expected.mean, 1e-9);
    EXPECT_NEAR(acc.variance, expected.variance, 1e-9);
    EXPECT_EQ(acc.count, expected.count);
}

TEST(RssStats, MergingEmptyChangesNothing) {
    auto s = RssStats::of(std::vector<double>{-40, -44});
    const auto before = s;
    s.merge(RssStats{});
    EXPECT_EQ(s.count, before.count);
    EXPECT_DOUBLE_EQ(s.mean, before.mean);
    RssStats empty;
    empty.merge(before);
    EXPECT_DOUBLE_EQ(empty.variance, before.variance);
}

TEST(RssStats, CanMergeStopsAtTheLargestStoredCount) {
    const RssStats half{-50.0, 1.0, kMaxCount / 2};
    EXPECT_TRUE(half.can_merge(half));  // exactly 2^53
    EXPECT_FALSE(half.can_merge(RssStats{-50.0, 1.0, kMaxCount / 2 + 1}));
    EXPECT_TRUE(RssStats{}.can_merge(RssStats{-50.0, 1.0, kMaxCount}));  // an empty side adds nothing
    EXPECT_FALSE(RssStats{}.can_merge(RssStats{-50.0, 1.0, kMaxCount + 1}));
    const RssStats full{-50.0, 1.0, kMaxCount};
    EXPECT_FALSE(full.can_merge(RssStats{-50.0, 1.0, 1}));
    EXPECT_TRUE(full.can_merge(RssStats{}));
}

}  // namespace
}  // namespace rss_stats_test
