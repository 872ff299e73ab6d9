// plan_from_image on drawings made here, pixel by pixel: two rooms with a door gap between
// them come out as one walkable inside, the rooms joined through the gap and only through it,
// the walls where they were drawn (within a pixel) and the options' bad values refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "locus/imaging/plan_from_image.hpp"
#include "locus/plan/check.hpp"
#include "locus/plan/ring.hpp"
#include "locus/plan/route.hpp"
#include "locus/plan/walk_grid.hpp"

namespace plan_from_image_test {
namespace {

using locus::Point;
using locus::imaging::FromImageOptions;
using locus::imaging::GreyImage;
using locus::imaging::plan_from_image;
namespace plan = locus::plan;

constexpr double kPxPerM = 20.0;
constexpr int kW = 400, kH = 200;  // 20 m × 10 m

struct Drawing {
    GreyImage image{kW, kH, std::vector<std::uint8_t>(static_cast<std::size_t>(kW) * kH, 255)};
    void ink(int u0, int v0, int u1, int v1, std::uint8_t grey = 0) {  // inclusive pixel box
        for (int v = v0; v <= v1; ++v)
            for (int u = u0; u <= u1; ++u) image.pixels[static_cast<std::size_t>(v) * kW + static_cast<std::size_t>(u)] = grey;
    }
};

// Outer walls 3 px thick around pixels 20…379 × 20…179, and a wall at columns 199–201 between
// the two rooms, open over rows [gap_from, gap_to) when gap_to > gap_from.
Drawing two_rooms(int gap_from, int gap_to) {
    Drawing d;
    d.ink(20, 20, 379, 22);
    d.ink(20, 177, 379, 179);
    d.ink(20, 20, 22, 179);
    d.ink(377, 20, 379, 179);
    for (int v = 20; v <= 179; ++v)
        if (v < gap_from || v >= gap_to) d.ink(199, v, 201, v);
    return d;
}

// The image's pixel centre (u, v) in plan metres (y up).
Point at_px(double u, double v) { return {(u + 0.5) / kPxPerM, (kH - (v + 0.5)) / kPxPerM}; }

double nearest_wall(const plan::Plan& p, Point q) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& w : p.walls)
        for (std::size_t i = 0; i + 1 < w.line.size(); ++i) best = std::min(best, locus::distance_to_segment(q, w.line[i], w.line[i + 1]));
    return best;
}

plan::Route route_between(const plan::Plan& p, Point a, Point b) {
    std::vector<plan::FloorSpec> floors{{1, 0, p}};
    const auto building = plan::build_building(std::move(floors));
    return plan::route(building, {1, a}, {1, b});
}

FromImageOptions options() {
    FromImageOptions o;
    o.px_per_m = kPxPerM;
    return o;
}

TEST(PlanFromImage, TwoRoomsWithADoorGapAreOneInsideJoinedThroughTheGap) {
    const auto d = two_rooms(90, 120);  // a 1.5 m gap, rows 90–119
    locus::imaging::FromImageStats stats;
    const auto p = plan_from_image(d.image, options(), &stats);
    EXPECT_TRUE(plan::check_plan(p).empty());
    ASSERT_EQ(p.spaces.size(), 1u);
    EXPECT_EQ(stats.spaces, 1u);
    EXPECT_GT(stats.walls, 0u);
    EXPECT_EQ(stats.walls, p.walls.size());
    // The inside spans the drawn outline (pixels 20…379 × 20…179), within a pixel.
    double minx = 1e9, maxx = -1e9, miny = 1e9, maxy = -1e9;
    for (const auto& q : p.spaces[0].shape.outer)
        minx = std::min(minx, q.x), maxx = std::max(maxx, q.x), miny = std::min(miny, q.y), maxy = std::max(maxy, q.y);
    const double px = 1.0 / kPxPerM;
    EXPECT_NEAR(minx, at_px(20, 0).x, px);
    EXPECT_NEAR(maxx, at_px(379, 0).x, px);
    EXPECT_NEAR(maxy, at_px(0, 20).y, px);
    EXPECT_NEAR(miny, at_px(0, 179).y, px);

    const Point left = at_px(110, 100), right = at_px(290, 100);
    const auto r = route_between(p, left, right);
    ASSERT_EQ(r.status, plan::RouteStatus::ok) << plan::to_string(r.status);
    EXPECT_GE(r.length_m, std::hypot(right.x - left.x, right.y - left.y) - 1e-9);
    // It crosses the middle wall's column inside the gap.
    bool through_gap = false;
    for (const auto& leg : r.legs)
        for (std::size_t i = 0; i + 1 < leg.path.size(); ++i) {
            const Point a = leg.path[i], b = leg.path[i + 1];
            const double xm = at_px(200, 0).x;
            if ((a.x - xm) * (b.x - xm) > 0 || a.x == b.x) continue;
            const double y = a.y + (xm - a.x) / (b.x - a.x) * (b.y - a.y);
            through_gap = through_gap || (y < at_px(0, 90).y && y > at_px(0, 119).y);
        }
    EXPECT_TRUE(through_gap);
}

TEST(PlanFromImage, WallsAreWhereTheyWereDrawnWithinAPixel) {
    const auto d = two_rooms(90, 120);
    const auto p = plan_from_image(d.image, options());
    const double px = 1.0 / kPxPerM;
    // Along the middle wall (column 200) above and below the gap, and along the outer walls'
    // middle lines: a wall outline within one pixel (the stroke is 3 px: its outline runs one
    // pixel to each side of the middle).
    for (int v = 30; v < 85; v += 5) EXPECT_LE(nearest_wall(p, at_px(200, v)), px + 1e-9) << "row " << v;
    for (int v = 125; v < 175; v += 5) EXPECT_LE(nearest_wall(p, at_px(200, v)), px + 1e-9) << "row " << v;
    for (int u = 30; u < 370; u += 20) {
        EXPECT_LE(nearest_wall(p, at_px(u, 21)), px + 1e-9) << "column " << u;
        EXPECT_LE(nearest_wall(p, at_px(u, 178)), px + 1e-9) << "column " << u;
    }
    // And none in the gap or the rooms.
    EXPECT_GE(nearest_wall(p, at_px(200, 105)), 14 * px);
    EXPECT_GE(nearest_wall(p, at_px(110, 100)), 3.0);
}

TEST(PlanFromImage, WithoutTheGapTheRoomsAreApart) {
    const auto d = two_rooms(0, 0);
    const auto p = plan_from_image(d.image, options());
    EXPECT_TRUE(plan::check_plan(p).empty());
    const auto r = route_between(p, at_px(110, 100), at_px(290, 100));
    EXPECT_EQ(r.status, plan::RouteStatus::unreachable);
}

TEST(PlanFromImage, AGapInTheOuterWallUpToCloseMDoesNotLetTheOutsideIn) {
    auto d = two_rooms(90, 120);
    d.ink(100, 20, 140, 22, 255);  // a 2 m entrance in the top wall
    auto o = options();
    o.close_m = 3.0;
    auto p = plan_from_image(d.image, o);
    ASSERT_EQ(p.spaces.size(), 1u);
    o.close_m = 1.0;  // narrower than the entrance: the rooms are outside
    p = plan_from_image(d.image, o);
    EXPECT_TRUE(p.spaces.empty());
}

TEST(PlanFromImage, LightLinesBelowTheThresholdAreNotWalls) {
    auto d = two_rooms(90, 120);
    d.ink(100, 60, 100, 150, 200);  // a light grey line, like a glass partition or furniture
    const auto p = plan_from_image(d.image, options());
    EXPECT_GT(nearest_wall(p, at_px(100, 100)), 1.0);
    auto o = options();
    o.threshold = 220;
    EXPECT_LE(nearest_wall(plan_from_image(d.image, o), at_px(100, 100)), 1.0 / kPxPerM + 1e-9);
}

TEST(PlanFromImage, ACupboardWhoseOutlineHasANarrowGapIsNoWalkableSpace) {
    // A 1.3 m square box (26 px) in the left room, its outline open over 6 px (0.3 m): no one
    // gets in, so it is a hole in the space, not a speck of floor a position could snap into.
    auto d = two_rooms(90, 120);
    d.ink(60, 60, 86, 61);
    d.ink(60, 85, 86, 86);
    d.ink(60, 60, 61, 86);
    d.ink(85, 60, 86, 70);
    d.ink(85, 77, 86, 86);  // the gap: rows 71–76
    const auto p = plan_from_image(d.image, options());
    ASSERT_EQ(p.spaces.size(), 1u);
    EXPECT_TRUE(plan::check_plan(p).empty());
    EXPECT_FALSE(plan::polygon_contains(p.spaces[0].shape, at_px(73, 73)));
    EXPECT_TRUE(plan::polygon_contains(p.spaces[0].shape, at_px(110, 100)));
    // A door-wide gap (1 m) leaves it a room of its own.
    d.ink(85, 62, 86, 84, 255);
    const auto open = plan_from_image(d.image, options());
    ASSERT_EQ(open.spaces.size(), 1u);
    EXPECT_TRUE(plan::polygon_contains(open.spaces[0].shape, at_px(73, 73)));
}

TEST(PlanFromImage, BadInputIsRefusedByName) {
    const auto d = two_rooms(90, 120);
    auto expect_refused = [](const GreyImage& img, const FromImageOptions& o, const std::string& word) {
        try {
            plan_from_image(img, o);
            ADD_FAILURE() << "accepted; expected a refusal naming " << word;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
        }
    };
    auto o = options();
    o.px_per_m = 0;
    expect_refused(d.image, o, "px_per_m");
    o = options();
    o.threshold = 0;
    expect_refused(d.image, o, "threshold");
    o = options();
    o.px_per_m = 0.5;  // 800 m × 400 m: past the largest plan
    expect_refused(d.image, o, "more than a plan may");
    GreyImage bad = d.image;
    bad.pixels.pop_back();
    expect_refused(bad, options(), "pixels");
    expect_refused(GreyImage{}, options(), "empty");
}

}  // namespace
}  // namespace plan_from_image_test
