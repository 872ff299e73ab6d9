// The phone's RSS offset learnt online (locus/match/device_offset.hpp): looks of a phone that
// reads 6 dB low, shrunk towards 0 by the prior; a scan sharing too few APs is no look; one AP
// far off does not move a look (the median); the clip; and bad configurations refused.
#include <gtest/gtest.h>

#include <stdexcept>

#include "locus/match/device_offset.hpp"

namespace match_device_offset_test {
namespace {

using namespace locus;
using locus::match::DeviceOffset;
using locus::match::DeviceOffsetConfig;
using locus::match::Fingerprint;

const Fingerprint kPlacedAt = {{"aa:00:00:00:00:01", -50.0}, {"aa:00:00:00:00:02", -60.0}, {"aa:00:00:00:00:03", -70.0},
                               {"aa:00:00:00:00:04", -80.0}};

// The fingerprint's APs read `low_db` lower, and one AP the fingerprint has never heard.
Scan read_low(double low_db) {
    Scan s;
    for (const auto& [ap, mean] : kPlacedAt) s.push_back({"wifi", ap, mean - low_db});
    s.push_back({"wifi", "bb:00:00:00:00:09", -40.0});
    return s;
}

TEST(DeviceOffset, LearnsAPhoneThatReadsLowShrunkByThePrior) {
    DeviceOffset offset;  // prior: 5 looks of 0 dB
    EXPECT_EQ(offset.offset_db(), 0.0);
    for (int n = 1; n <= 20; ++n) {
        ASSERT_TRUE(offset.add(read_low(6.0), kPlacedAt));
        EXPECT_NEAR(offset.offset_db(), 6.0 * n / (n + 5.0), 1e-12) << n;
    }
    EXPECT_EQ(offset.looks(), 20);
}

TEST(DeviceOffset, AScanSharingTooFewApsIsNoLook) {
    DeviceOffset offset;
    Scan two = read_low(6.0);
    two.erase(two.begin(), two.begin() + 2);  // two of the fingerprint's APs left, and the stranger
    EXPECT_FALSE(offset.add(two, kPlacedAt));
    EXPECT_FALSE(offset.add(read_low(6.0), {}));
    EXPECT_EQ(offset.looks(), 0);
    EXPECT_EQ(offset.offset_db(), 0.0);
}

TEST(DeviceOffset, OneApFarOffDoesNotMoveALook) {
    DeviceOffsetConfig c;
    c.prior_scans = 0.0;
    DeviceOffset offset(c);
    Scan s = read_low(4.0);
    s[0].rss += 30.0;  // one AP 30 dB louder than the rest say (a reflection, a moved AP)
    ASSERT_TRUE(offset.add(s, kPlacedAt));
    EXPECT_NEAR(offset.offset_db(), 4.0, 1e-12);  // the median of 4, 4, 4, −26 (an even count: the two middle ones)
}

TEST(DeviceOffset, IsClippedToWhatAPhoneCanBe) {
    DeviceOffsetConfig c;
    c.prior_scans = 0.0;
    DeviceOffset offset(c);
    ASSERT_TRUE(offset.add(read_low(40.0), kPlacedAt));
    EXPECT_EQ(offset.offset_db(), 15.0);
    ASSERT_TRUE(offset.add(read_low(-100.0), kPlacedAt));
    EXPECT_EQ(offset.offset_db(), -15.0);  // (40 − 100) / 2
}

TEST(DeviceOffset, RefusesAConfigurationOutsideItsDomain) {
    EXPECT_THROW(DeviceOffset(DeviceOffsetConfig{0, 5.0, 15.0}), std::invalid_argument);
    EXPECT_THROW(DeviceOffset(DeviceOffsetConfig{3, -1.0, 15.0}), std::invalid_argument);
    EXPECT_THROW(DeviceOffset(DeviceOffsetConfig{3, 5.0, 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace match_device_offset_test
