// The geometry of GET /v1/tracks/{a}/relative/{b} (server/tracks/relative.hpp): bearings
// clockwise from the plan's +y as headings are, turned into (-180, 180], and their words.
#include "tracks/relative.hpp"

#include <gtest/gtest.h>

namespace locus::tracks::tracks_relative_test {
namespace {

Fix at(double x, double y) {
    Fix f;
    f.x = x;
    f.y = y;
    return f;
}

TEST(TracksRelative, BearingIsClockwiseFromPlusYInZeroTo360) {
    const Fix o = at(2, 3);
    EXPECT_NEAR(bearing_deg(o, at(2, 8)), 0.0, 1e-9);
    EXPECT_NEAR(bearing_deg(o, at(7, 3)), 90.0, 1e-9);
    EXPECT_NEAR(bearing_deg(o, at(2, -2)), 180.0, 1e-9);
    EXPECT_NEAR(bearing_deg(o, at(-3, 3)), 270.0, 1e-9);
    EXPECT_NEAR(bearing_deg(o, at(3, 4)), 45.0, 1e-9);
    EXPECT_NEAR(bearing_deg(o, at(1, 4)), 315.0, 1e-9);
}

TEST(TracksRelative, TurnedBearingWrapsIntoMinus180To180) {
    EXPECT_NEAR(turned_deg(10, 350), 20.0, 1e-9);    // just past north, facing just before it
    EXPECT_NEAR(turned_deg(350, 10), -20.0, 1e-9);
    EXPECT_NEAR(turned_deg(180, 0), 180.0, 1e-9);    // straight behind is +180, never -180
    EXPECT_NEAR(turned_deg(0, 180), 180.0, 1e-9);
    EXPECT_NEAR(turned_deg(90, 90), 0.0, 1e-9);
    EXPECT_NEAR(turned_deg(45, 300), 105.0, 1e-9);
}

TEST(TracksRelative, DirectionTextNamesTheSideAndRoundedDegrees) {
    EXPECT_EQ(direction_text(0), "ahead");
    EXPECT_EQ(direction_text(-10), "ahead");
    EXPECT_EQ(direction_text(10.4), "ahead, 10\u00b0 right");
    EXPECT_EQ(direction_text(-30), "ahead, 30\u00b0 left");
    EXPECT_EQ(direction_text(89.6), "ahead, 90\u00b0 right");  // under 90: still ahead, the words round
    EXPECT_EQ(direction_text(90), "behind, 90\u00b0 right");
    EXPECT_EQ(direction_text(-120), "behind, 120\u00b0 left");
    EXPECT_EQ(direction_text(170), "behind");
    EXPECT_EQ(direction_text(-179.9), "behind");
}

}  // namespace
}  // namespace locus::tracks::tracks_relative_test
