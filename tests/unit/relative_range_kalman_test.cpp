// The distance filter for RSSI between phones: on a straight walk at B it tracks the distance
// far better than single readings do and learns that the distance falls a metre per metre
// walked; an acoustic range pulls it to centimetres.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "locus/motion/relative/phone_rssi.hpp"
#include "locus/motion/relative/range_fit.hpp"
#include "locus/motion/relative/range_kalman.hpp"

namespace relative_range_kalman_test {
namespace {

using namespace locus::relative;

TEST(RangeKalman, SmoothsRssiOnAWalkAtTheTarget) {
    const PhoneLink link;
    double raw_sq = 0, filtered_sq = 0, rate = 0;
    int n = 0;
    for (int walk = 0; walk < 50; ++walk) {
        std::mt19937_64 rng(walk);
        std::normal_distribution<double> shadow(0.0, 4.0);
        RangeKalman f;
        EXPECT_FALSE(f.distance());
        for (int k = 0; k < 25; ++k) {  // 20 m to 3.2 m in 0.7 m steps
            const double d = 20.0 - 0.7 * k;
            if (k) f.predict(0.7);
            const double raw = phone_distance(link, locus::ranging::rss_at(link.model, d) + shadow(rng));
            f.update_rssi(raw);
            if (k >= 10) {  // once it has had some readings
                raw_sq += (raw - d) * (raw - d);
                filtered_sq += (*f.distance() - d) * (*f.distance() - d);
                ++n;
            }
        }
        rate += f.rate() / 50;
    }
    // About 3.7 m RMS for single readings, 2.0 m filtered (lagging a little behind the walk).
    EXPECT_LT(std::sqrt(filtered_sq / n), 0.7 * std::sqrt(raw_sq / n));
    EXPECT_LT(rate, -0.5);  // falling about a metre per metre walked
}

TEST(RangeKalman, AnAcousticRangeWins) {
    RangeKalman f;
    f.update_rssi(3.0);
    f.predict(0.7);
    f.update_direct(1.0, 0.01);
    EXPECT_NEAR(*f.distance(), 1.0, 0.02);
}

// The range fit: exact distances along an L-shaped walk give B; a straight walk leaves the
// side open and the preferred bearing picks it.
TEST(RangeFit, FindsTheTargetFromAnLShapedWalk) {
    const locus::Point b{7.0, 9.0};
    std::vector<locus::Point> at;
    std::vector<double> d;
    for (int k = 0; k < 8; ++k) at.push_back({0.7 * k, 0.0});
    for (int k = 1; k < 6; ++k) at.push_back({0.7 * 7, 0.7 * k});
    for (const auto& p : at) d.push_back(std::hypot(b.x - p.x, b.y - p.y));
    const auto got = fit_target(at, d, at.back(), d.back(), -90.0);  // even preferring the wrong side
    ASSERT_TRUE(got);
    EXPECT_NEAR(got->x, b.x, 0.01);
    EXPECT_NEAR(got->y, b.y, 0.01);
    EXPECT_FALSE(fit_target(std::span(at).first(2), std::span(d).first(2), at[1], d[1], 0.0));
}

TEST(RangeFit, AStraightWalkTakesThePreferredSide) {
    std::vector<locus::Point> at;
    std::vector<double> d;
    for (int k = 0; k < 10; ++k) at.push_back({0.7 * k, 0.0});
    for (const auto& p : at) d.push_back(std::hypot(12.0 - p.x, 5.0 - p.y));  // B at (12, 5)
    const auto left = fit_target(at, d, at.back(), d.back(), 60.0);
    const auto right = fit_target(at, d, at.back(), d.back(), -60.0);
    ASSERT_TRUE(left && right);
    EXPECT_NEAR(left->y, 5.0, 0.05);
    EXPECT_NEAR(right->y, -5.0, 0.05);
    EXPECT_NEAR(left->x, 12.0, 0.05);
}

}  // namespace
}  // namespace relative_range_kalman_test
