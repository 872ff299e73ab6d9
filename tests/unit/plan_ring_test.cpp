// plan::interior_point: a point inside any space, for spaces the directory lists without a room.
#include <gtest/gtest.h>

#include "locus/plan/ring.hpp"

namespace plan_ring_test {
namespace {

using locus::Point;
using locus::plan::Polygon;
using locus::plan::Ring;

Ring rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}; }

TEST(PlanRing, InteriorPointOfAConvexSpaceIsItsCentroid) {
    const Point p = locus::plan::interior_point({rect(10, 4, 20, 10), {}});
    EXPECT_DOUBLE_EQ(p.x, 15.0);
    EXPECT_DOUBLE_EQ(p.y, 7.0);
}

TEST(PlanRing, InteriorPointOfAUOrACourtyardIsInsideIt) {
    // A U open at the top: its centroid falls in the gap between the arms.
    const Polygon u{{{0, 0}, {9, 0}, {9, 9}, {6, 9}, {6, 3}, {3, 3}, {3, 9}, {0, 9}, {0, 0}}, {}};
    const Point pu = locus::plan::interior_point(u);
    EXPECT_TRUE(locus::plan::polygon_contains(u, pu)) << pu.x << ", " << pu.y;
    // A ring of corridors around a courtyard: the centroid is in the hole.
    const Polygon ring{rect(0, 0, 10, 10), {rect(2, 2, 8, 8)}};
    const Point pr = locus::plan::interior_point(ring);
    EXPECT_TRUE(locus::plan::polygon_contains(ring, pr)) << pr.x << ", " << pr.y;
}

}  // namespace
}  // namespace plan_ring_test
