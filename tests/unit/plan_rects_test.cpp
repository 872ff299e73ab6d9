// plan::rects_of: a space's polygon as the rectangles of the room kept in step with it.
#include <gtest/gtest.h>

#include <cmath>

#include "locus/plan/rects.hpp"
#include "plan_fixture.hpp"

namespace plan_rects_test {
namespace {

using namespace plan_fixture;

double area(const std::vector<locus::Rect>& rs) {
    double a = 0;
    for (const auto& r : rs) a += r.area();
    return a;
}

// No two rectangles overlap (they may share an edge).
bool disjoint(const std::vector<locus::Rect>& rs) {
    for (std::size_t i = 0; i < rs.size(); ++i)
        for (std::size_t j = i + 1; j < rs.size(); ++j) {
            const double w = std::min(rs[i].xmax, rs[j].xmax) - std::max(rs[i].xmin, rs[j].xmin);
            const double h = std::min(rs[i].ymax, rs[j].ymax) - std::max(rs[i].ymin, rs[j].ymin);
            if (w > 1e-12 && h > 1e-12) return false;
        }
    return true;
}

TEST(PlanRects, ARectangleIsOneRect) {
    const auto rs = rects_of({rect(2, 1, 7, 4), {}});
    ASSERT_EQ(rs.size(), 1u);
    EXPECT_EQ(rs[0].xmin, 2);
    EXPECT_EQ(rs[0].ymin, 1);
    EXPECT_EQ(rs[0].xmax, 7);
    EXPECT_EQ(rs[0].ymax, 4);
}

TEST(PlanRects, AnLShapeIsTwoRectsOfItsExactArea) {
    // 10 × 4 along the bottom, 4 × 6 up the left side: 40 + 24 = 64 m².
    const Ring l = {{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}, {0, 0}};
    const auto rs = rects_of({l, {}});
    ASSERT_EQ(rs.size(), 2u);
    EXPECT_DOUBLE_EQ(area(rs), 64.0);
    EXPECT_TRUE(disjoint(rs));
    // The tall part spans the whole height, the rest only the bottom strip.
    EXPECT_EQ(rs[0].xmin, 0);
    EXPECT_EQ(rs[0].xmax, 4);
    EXPECT_EQ(rs[0].ymax, 10);
    EXPECT_EQ(rs[1].xmin, 4);
    EXPECT_EQ(rs[1].xmax, 10);
    EXPECT_EQ(rs[1].ymax, 4);
    // Clockwise rings give the same answer.
    const Ring cw(l.rbegin(), l.rend());
    EXPECT_DOUBLE_EQ(area(rects_of({cw, {}})), 64.0);
}

TEST(PlanRects, AHoleIsLeftOut) {
    // 10 × 10 with a 2 × 2 pillar at (4..6, 4..6): 96 m², and no rect covers the pillar.
    const auto rs = rects_of({rect(0, 0, 10, 10), {rect(4, 4, 6, 6)}});
    EXPECT_DOUBLE_EQ(area(rs), 96.0);
    EXPECT_TRUE(disjoint(rs));
    EXPECT_EQ(rs.size(), 4u);  // left, below the pillar, above it, right
    const locus::Room room{1, "r", rs};
    EXPECT_FALSE(room.contains({5, 5}));
    EXPECT_TRUE(room.contains({5, 3}));
    EXPECT_TRUE(room.contains({5, 7}));
    EXPECT_TRUE(room.contains({1, 5}));
}

TEST(PlanRects, ATriangleIsApproximatedWithinItsSlabs) {
    // A right triangle of 8 × 6 (24 m²) has vertices at x = 0 and 8 only: one slab, read at
    // x = 4, where it is 3 high: a 8 × 3 rect of exactly the same area. Its outline is what
    // is approximate: the rect sticks out of the hypotenuse by at most half the height.
    const Ring tri = {{0, 0}, {8, 0}, {0, 6}, {0, 0}};
    const auto rs = rects_of({tri, {}});
    ASSERT_EQ(rs.size(), 1u);
    EXPECT_NEAR(area(rs), 24.0, 1e-9);
    EXPECT_DOUBLE_EQ(rs[0].ymax, 3.0);

    // A many-sided circle: a slab between each pair of neighbouring vertex x's; straight
    // edges make each slab's mid-height its mean height, so the area is the polygon's.
    Ring circle;
    const int n = 40;
    for (int i = 0; i <= n; ++i) {
        const double a = 2 * M_PI * (i % n) / n;
        circle.push_back({10 + 5 * std::cos(a), 10 + 5 * std::sin(a)});
    }
    const double polygon_area = 0.5 * n * 25 * std::sin(2 * M_PI / n);
    const auto cr = rects_of({circle, {}});
    EXPECT_NEAR(area(cr), polygon_area, 0.01 * polygon_area);
    EXPECT_TRUE(disjoint(cr));
    // Mirrored vertices share their x up to rounding: one cut each, so n / 2 slabs.
    EXPECT_EQ(cr.size(), static_cast<std::size_t>(n / 2));
}

TEST(PlanRects, ManyVerticesAreThinnedToTheCap) {
    // A staircase outline with 200 steps: more slabs than the cap, so cuts are thinned; the
    // area stays close and the count bounded.
    Ring steps = {{0, 0}};
    for (int i = 0; i < 200; ++i) {
        steps.push_back({i + 1.0, i * 0.1});
        steps.push_back({i + 1.0, (i + 1) * 0.1});
    }
    steps.push_back({0, 20});
    steps.push_back({0, 0});
    // The region between the steps and y = 20; its exact area by the shoelace formula.
    double twice = 0;
    for (std::size_t i = 0; i + 1 < steps.size(); ++i) twice += steps[i].x * steps[i + 1].y - steps[i + 1].x * steps[i].y;
    const double exact = std::abs(twice) / 2;
    const auto rs = rects_of({steps, {}});
    EXPECT_LE(rs.size(), kMaxRoomSlabs);
    EXPECT_NEAR(area(rs), exact, 0.02 * exact);
    EXPECT_TRUE(disjoint(rs));
}

TEST(PlanRects, ADegeneratePolygonHasNoRects) {
    EXPECT_TRUE(rects_of({{}, {}}).empty());
    EXPECT_TRUE(rects_of({{{1, 1}, {1, 5}, {1, 1}}, {}}).empty());
}

TEST(PlanRects, ACombOfManyTeethIsJoinedAcrossItsNarrowestGaps) {
    // A spine x ∈ [0, 1] with 50 teeth to x = 10, each 1 m high with 1 m gaps, except one gap
    // of 5 m: 50 intervals in the teeth's slab, more than a slab may keep. The narrowest gaps
    // are joined first, so the one wide gap stays open, and a room never needs more rectangles
    // than the API allows however many teeth a space has.
    const auto bottom = [](int i) { return i < 25 ? 2.0 * i : 2.0 * i + 4; };
    Ring comb = {{0, 0}};
    for (int i = 0; i < 50; ++i) {
        if (i > 0) comb.push_back({1, bottom(i)});
        comb.push_back({10, bottom(i)});
        comb.push_back({10, bottom(i) + 1});
        if (i < 49) comb.push_back({1, bottom(i) + 1});
    }
    comb.push_back({0, bottom(49) + 1});
    comb.push_back({0, 0});
    const auto rs = rects_of({comb, {}});
    EXPECT_LE(rs.size(), kMaxSlabIntervals + 1);
    EXPECT_TRUE(disjoint(rs));
    // The teeth's slab: nothing covers the middle of the wide gap, every tooth is covered.
    const auto covered = [&](locus::Point p) {
        for (const auto& r : rs)
            if (r.contains(p)) return true;
        return false;
    };
    EXPECT_FALSE(covered({5, bottom(24) + 1 + 2.5}));
    for (int i = 0; i < 50; ++i) EXPECT_TRUE(covered({5, bottom(i) + 0.5})) << "tooth " << i;
}

}  // namespace
}  // namespace plan_rects_test
