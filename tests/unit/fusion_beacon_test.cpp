// A beacon's readings as fixes (fusion/beacon.hpp): one reading per beacon per interval counts,
// each beacon on its own clock, and a copy of the gate (a request's copy of a track's filter)
// goes on from where the original was.
#include <gtest/gtest.h>

#include "locus/motion/fusion/beacon.hpp"

namespace fusion_beacon_test {
namespace {

using locus::fusion::BeaconGate;

TEST(BeaconGate, OneReadingPerBeaconPerInterval) {
    BeaconGate gate(2.0);
    EXPECT_TRUE(gate.take("a", 10.0));
    EXPECT_FALSE(gate.take("a", 11.0));
    EXPECT_FALSE(gate.take("a", 11.99));
    EXPECT_TRUE(gate.take("b", 11.5));  // another beacon, its own clock
    EXPECT_TRUE(gate.take("a", 12.0));  // the interval runs from the reading that counted
    EXPECT_FALSE(gate.take("a", 13.0));
    EXPECT_TRUE(gate.take("a", 14.5));
}

TEST(BeaconGate, ACopyGoesOnFromTheOriginalsState) {
    BeaconGate gate;  // the shared setting
    EXPECT_TRUE(gate.take("a", 0.0));
    BeaconGate copy = gate;
    EXPECT_FALSE(copy.take("a", locus::fusion::kBeaconMinIntervalS / 2));
    EXPECT_TRUE(copy.take("a", locus::fusion::kBeaconMinIntervalS));
    EXPECT_FALSE(gate.take("a", locus::fusion::kBeaconMinIntervalS / 2));  // the original is untouched by the copy
}

}  // namespace
}  // namespace fusion_beacon_test
