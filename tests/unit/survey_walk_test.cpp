// The walking survey's core (locus/survey/walk.hpp): interpolation between landmarks, the
// spans it skips, and binning along the path. Expected positions are worked out by hand.
#include <gtest/gtest.h>

#include <stdexcept>

#include "locus/survey/walk.hpp"

namespace survey_walk_test {
namespace {

using namespace locus;
using namespace locus::survey;

// An L-shaped walk on floor 0: (0,0) at t=10, (10,0) at t=20, (10,20) at t=30.
std::vector<Landmark> l_walk() { return {{10.0, 0, {0, 0}}, {20.0, 0, {10, 0}}, {30.0, 0, {10, 20}}}; }

TEST(SurveyWalk, InterpolatesLinearlyInTimeOnOneFloor) {
    const auto p = place(l_walk(), 15.0);
    ASSERT_TRUE(p.position);
    EXPECT_DOUBLE_EQ(p.position->at.x, 5.0);
    EXPECT_DOUBLE_EQ(p.position->at.y, 0.0);
    EXPECT_DOUBLE_EQ(p.position->path_m, 5.0);
    const auto q = place(l_walk(), 27.5);  // three quarters up the second leg
    ASSERT_TRUE(q.position);
    EXPECT_DOUBLE_EQ(q.position->at.x, 10.0);
    EXPECT_DOUBLE_EQ(q.position->at.y, 15.0);
    EXPECT_DOUBLE_EQ(q.position->path_m, 25.0);
    EXPECT_EQ(q.position->floor, 0);
}

TEST(SurveyWalk, InstantsOnLandmarksTakeTheLandmark) {
    const auto first = place(l_walk(), 10.0), last = place(l_walk(), 30.0), mid = place(l_walk(), 20.0);
    ASSERT_TRUE(first.position && last.position && mid.position);
    EXPECT_DOUBLE_EQ(first.position->at.x, 0.0);
    EXPECT_DOUBLE_EQ(mid.position->at.x, 10.0);
    EXPECT_DOUBLE_EQ(mid.position->at.y, 0.0);
    EXPECT_DOUBLE_EQ(last.position->at.y, 20.0);
    EXPECT_DOUBLE_EQ(last.position->path_m, 30.0);
}

TEST(SurveyWalk, BeforeTheFirstAndAfterTheLastAreSkipped) {
    const auto before = place(l_walk(), 9.99), after = place(l_walk(), 30.01);
    EXPECT_FALSE(before.position);
    EXPECT_EQ(before.why, Unplaced::before_first);
    EXPECT_FALSE(after.position);
    EXPECT_EQ(after.why, Unplaced::after_last);
}

TEST(SurveyWalk, SpansBetweenFloorsAreSkipped) {
    // Floor 0 to the stairs' foot on floor -2 between t=20 and t=40, then on along -2.
    const std::vector<Landmark> walk = {{10, 0, {0, 0}}, {20, 0, {10, 0}}, {40, -2, {12, 0}}, {50, -2, {12, 10}}};
    const auto stairs = place(walk, 30.0);
    EXPECT_FALSE(stairs.position);
    EXPECT_EQ(stairs.why, Unplaced::floor_change);
    const auto below = place(walk, 45.0);
    ASSERT_TRUE(below.position);
    EXPECT_EQ(below.position->floor, -2);
    EXPECT_DOUBLE_EQ(below.position->at.x, 12.0);
    EXPECT_DOUBLE_EQ(below.position->at.y, 5.0);
    // The stairs add nothing to the path; the span changes.
    EXPECT_DOUBLE_EQ(below.position->path_m, 15.0);
    EXPECT_EQ(below.position->span, 1u);
    // The landmark at the foot of the stairs is on -2.
    const auto foot = place(walk, 40.0);
    ASSERT_TRUE(foot.position);
    EXPECT_EQ(foot.position->floor, -2);
}

TEST(SurveyWalk, APauseOnALandmarkStaysThere) {
    // The walker stands on (10,0) from t=20 to t=28 (the landmark logged twice).
    const std::vector<Landmark> walk = {{10, 0, {0, 0}}, {20, 0, {10, 0}}, {28, 0, {10, 0}}, {38, 0, {10, 10}}};
    for (double t : {20.0, 22.0, 27.9}) {
        const auto p = place(walk, t);
        ASSERT_TRUE(p.position) << t;
        EXPECT_DOUBLE_EQ(p.position->at.x, 10.0) << t;
        EXPECT_DOUBLE_EQ(p.position->at.y, 0.0) << t;
    }
    const auto on = place(walk, 33.0);
    ASSERT_TRUE(on.position);
    EXPECT_DOUBLE_EQ(on.position->at.y, 5.0);
}

TEST(SurveyWalk, PlaceScansCountsWhatItSkips) {
    const std::vector<Landmark> walk = {{10, 0, {0, 0}}, {20, 0, {10, 0}}, {40, -2, {12, 0}}, {50, -2, {12, 10}}};
    const auto r = place_scans(walk, {5, 12, 30, 35, 45, 60, 61});
    EXPECT_EQ(r.before_first, 1u);
    EXPECT_EQ(r.floor_change, 2u);
    EXPECT_EQ(r.after_last, 2u);
    ASSERT_EQ(r.placed.size(), 2u);
    EXPECT_EQ(r.placed[0].scan, 1u);
    EXPECT_DOUBLE_EQ(r.placed[0].where.at.x, 2.0);
    EXPECT_EQ(r.placed[1].scan, 4u);
    EXPECT_EQ(r.placed[1].where.floor, -2);
}

TEST(SurveyWalk, LandmarksOutOfOrderOrNoneAreRefused) {
    EXPECT_THROW(place({}, 1.0), std::invalid_argument);
    EXPECT_THROW(place({{10, 0, {0, 0}}, {9, 0, {1, 0}}}, 9.5), std::invalid_argument);
}

TEST(SurveyWalk, BinsAlongThePath) {
    // At 1 m/s round the corner (10,0); scans every 2 s: path 2, 4, 6, ..., 18 m.
    const std::vector<Landmark> walk = {{10, 0, {0, 0}}, {20, 0, {10, 0}}, {40, 0, {10, 20}}};
    std::vector<double> times;
    for (double t = 12; t <= 28; t += 2) times.push_back(t);
    const auto placed = place_scans(walk, times).placed;
    ASSERT_EQ(placed.size(), 9u);
    const auto bins = bin_along_path(placed, 5.0);
    // From 2 m: 2,4,6 (≤ 7); from 8: 8,10,12; from 14: 14,16,18.
    ASSERT_EQ(bins.size(), 3u);
    EXPECT_EQ(bins[0].members, (std::vector<std::size_t>{0, 1, 2}));
    EXPECT_DOUBLE_EQ(bins[0].at.x, 4.0);  // (2 + 4 + 6) / 3 along x
    EXPECT_DOUBLE_EQ(bins[0].at.y, 0.0);
    // The corner bin: (8,0), (10,0), (10,2).
    EXPECT_DOUBLE_EQ(bins[1].at.x, 28.0 / 3.0);
    EXPECT_DOUBLE_EQ(bins[1].at.y, 2.0 / 3.0);
    EXPECT_EQ(bins[2].members.size(), 3u);
}

TEST(SurveyWalk, CellZeroIsOneBinPerScanAndPausesShareABin) {
    const std::vector<Landmark> walk = {{10, 0, {0, 0}}, {20, 0, {10, 0}}, {28, 0, {10, 0}}, {38, 0, {10, 10}}};
    const auto placed = place_scans(walk, {21, 23, 25, 27}).placed;  // all during the pause
    EXPECT_EQ(bin_along_path(placed, 0.0).size(), 4u);
    const auto pooled = bin_along_path(placed, 0.5);
    ASSERT_EQ(pooled.size(), 1u);
    EXPECT_DOUBLE_EQ(pooled[0].at.x, 10.0);
    EXPECT_THROW(bin_along_path(placed, -1.0), std::invalid_argument);
}

TEST(SurveyWalk, BinsNeverCrossAFloorChange) {
    // Floor 0 ends at (10,0); floor -2 starts at (10,0) too, right after the stairs.
    const std::vector<Landmark> walk = {{10, 0, {0, 0}}, {20, 0, {10, 0}}, {22, -2, {10, 0}}, {32, -2, {20, 0}}};
    const auto placed = place_scans(walk, {19, 20, 22, 23}).placed;
    ASSERT_EQ(placed.size(), 4u);
    const auto bins = bin_along_path(placed, 50.0);
    ASSERT_EQ(bins.size(), 2u);
    EXPECT_EQ(bins[0].floor, 0);
    EXPECT_EQ(bins[0].members.size(), 2u);
    EXPECT_EQ(bins[1].floor, -2);
    EXPECT_EQ(bins[1].members.size(), 2u);
}

}  // namespace
}  // namespace survey_walk_test
