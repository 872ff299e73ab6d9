// The distance filter for RSSI between phones: on a straight walk at B it tracks the distance
// far better than single readings do and learns that the distance falls a metre per metre
// walked; an acoustic range pulls it to centimetres.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "locus/relative/phone_rssi.hpp"
#include "locus/relative/range_kalman.hpp"

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
