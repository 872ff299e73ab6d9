// Map matching on a floor plan as the server holds it (fusion/plan_walkable.hpp): walls and
// door gaps of plan::Plan constrain the particle filter and the Kalman filter, and the
// simulator's rooms-and-doors floors convert to an equivalent plan (fusion/rooms_plan.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/particle_filter.hpp"
#include "locus/motion/fusion/rooms_plan.hpp"
#include "locus/plan/check.hpp"
#include "plan_fixture.hpp"
#include "sim/scenario.hpp"

namespace fusion_plan_test {
namespace {

using locus::Point;
using namespace locus::fusion;

constexpr double kEast = std::numbers::pi / 2.0;  // θ clockwise from +y

// plan_fixture::two_rooms: West x ∈ [0, 10], East x ∈ [10, 20], y ∈ [0, 8]; the wall x = 10
// has a 0.9 m door centred on (10, 4), i.e. open for y ∈ (3.55, 4.45).
std::shared_ptr<const PlanWalkable> two_rooms(bool door = true) {
    return std::make_shared<const PlanWalkable>(plan_fixture::two_rooms(door));
}

// Whether the move a → b passes x = 10 outside the door gap.
bool through_the_wall(Point a, Point b) {
    if ((a.x < 10.0) == (b.x < 10.0)) return false;
    const double y = a.y + (10.0 - a.x) * (b.y - a.y) / (b.x - a.x);
    return y < 3.55 || y > 4.45;
}

TEST(PlanWalkable, InsideIsTheSpacesOffTheWalls) {
    const auto w = two_rooms();
    EXPECT_TRUE(w->inside({5.0, 4.0}));
    EXPECT_TRUE(w->inside({10.0, 4.0}));    // in the door gap
    EXPECT_TRUE(w->inside({0.15, 4.0}));    // next to the outer wall, within routing's clearance
    EXPECT_FALSE(w->inside({0.05, 4.0}));   // within the wall's margin
    EXPECT_FALSE(w->inside({10.0, 2.0}));   // in the wall
    EXPECT_FALSE(w->inside({10.05, 3.0}));  // in the wall's margin below the door
    EXPECT_FALSE(w->inside({21.0, 4.0}));   // outside the building
    EXPECT_THROW(PlanWalkable(locus::plan::Plan{}), std::invalid_argument);
}

TEST(PlanWalkable, WallsAreCrossedOnlyThroughTheDoor) {
    const auto w = two_rooms();
    EXPECT_TRUE(w->can_move({9.0, 4.0}, {11.0, 4.0}));
    EXPECT_TRUE(w->can_move({9.0, 3.7}, {11.0, 3.9}));
    EXPECT_FALSE(w->can_move({9.0, 2.0}, {11.0, 2.0}));
    EXPECT_FALSE(w->can_move({9.0, 3.4}, {11.0, 3.4}));  // just past the door's edge
    EXPECT_FALSE(w->can_move({19.5, 4.0}, {20.5, 4.0}));  // out of the building
    EXPECT_TRUE(w->can_move({25.0, 4.0}, {19.0, 4.0}));   // a point off the plan may come back
    EXPECT_FALSE(two_rooms(false)->can_move({9.0, 4.0}, {11.0, 4.0}));
}

TEST(PlanWalkable, ParticlesNeverCrossTheWallButThroughTheDoor) {
    // Walking east from the middle of West: the wall stops most particles, the door lets
    // some through, and no move of any particle, blocked or retried, cuts the wall.
    for (const bool door : {true, false}) {
        ParticleConfig c;
        c.seed = 7;
        c.heading_sigma_rad = 0.4;     // wide headings: many particles hit the wall next to the door
        c.resample_fraction = 0.0;     // no resampling, so particle i before a step is particle i after
        ParticleFilter pf(Walkable::from_plan(plan_fixture::two_rooms(door)), {6.0, 4.0}, c);
        for (int i = 0; i < 40; ++i) {
            std::vector<Point> before;
            for (const Particle& p : pf.particles()) before.push_back(p.at);
            pf.predict(0.7, kEast);
            for (std::size_t k = 0; k < before.size(); ++k) {
                const Point now = pf.particles()[k].at;
                ASSERT_FALSE(through_the_wall(before[k], now)) << before[k].x << "," << before[k].y << " → " << now.x << "," << now.y;
                ASSERT_TRUE(pf.map().inside(now)) << now.x << "," << now.y;
            }
        }
        int in_east = 0;
        for (const Particle& p : pf.particles()) in_east += p.at.x > 10.0;
        if (door)
            EXPECT_GT(in_east, 50);
        else
            EXPECT_EQ(in_east, 0);
    }
}

TEST(PlanWalkable, NoSingleParticleMoveCutsTheWall) {
    // can_move is what the filter asks before every move, so check it on random moves near the
    // wall, as many as a long walk of 1000 particles makes.
    const Walkable w = Walkable::from_plan(plan_fixture::two_rooms());
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> x(8.0, 12.0), y(0.2, 7.8), step(-1.0, 1.0);
    int allowed_through_door = 0;
    for (int i = 0; i < 20000; ++i) {
        const Point a{x(rng), y(rng)};
        const Point b{a.x + step(rng), a.y + step(rng)};
        if (!w.inside(a) || !w.can_move(a, b)) continue;
        ASSERT_FALSE(through_the_wall(a, b)) << a.x << "," << a.y << " → " << b.x << "," << b.y;
        allowed_through_door += (a.x < 10.0) != (b.x < 10.0);
    }
    EXPECT_GT(allowed_through_door, 50);
}

TEST(PlanWalkable, KalmanFixInTheWallOrOutsideIsSnappedIntoFreeSpace) {
    const auto w = two_rooms();
    KalmanConfig c;
    c.initial_sigma_m = 10.0;  // the fix decides
    for (const Point fix : {Point{10.0, 2.0}, Point{21.0, 4.0}, Point{5.0, -0.5}}) {
        KalmanFilter kf({5.0, 4.0}, c, w);
        kf.update(fix, Eigen::Matrix2d::Identity() * 0.01);
        EXPECT_TRUE(w->inside(kf.position())) << fix.x << "," << fix.y << " → " << kf.position().x << "," << kf.position().y;
        EXPECT_LT(locus::distance(kf.position(), fix), 1.5);  // a free cell's centre, ≥ 0.2 m off walls
    }
    // A fix far off the plan (past the grid's 2 m snap radius) comes to its nearest edge.
    KalmanFilter far({5.0, 4.0}, c, w);
    far.update({30.0, 4.0}, Eigen::Matrix2d::Identity() * 0.01);
    EXPECT_TRUE(w->inside(far.position()));
    EXPECT_GT(far.position().x, 19.0);
    EXPECT_NEAR(far.position().y, 4.0, 0.3);
    // A posterior caught in the wall between its prior and its fix lands on the fix's side.
    KalmanConfig even;
    even.initial_sigma_m = 1.0;  // P = R: the posterior is the midpoint, (10, 2), in the wall
    for (const double fix_x : {11.0, 9.0}) {
        KalmanFilter kf({20.0 - fix_x, 2.0}, even, w);
        kf.update({fix_x, 2.0}, Eigen::Matrix2d::Identity());
        EXPECT_TRUE(w->inside(kf.position()));
        EXPECT_EQ(kf.position().x > 10.0, fix_x > 10.0) << kf.position().x;
        EXPECT_NEAR(kf.position().x, 10.0, 0.2);
    }
    // Without the plan the same fix is taken as it is.
    KalmanFilter free_kf({5.0, 4.0}, c);
    free_kf.update({21.0, 4.0}, Eigen::Matrix2d::Identity() * 0.01);
    EXPECT_GT(free_kf.position().x, 20.5);
}

TEST(PlanWalkable, KalmanStepsStopAtWallsAndPassDoors) {
    const auto w = two_rooms();
    KalmanConfig blocking;
    blocking.walls_block_steps = true;
    KalmanFilter through({9.0, 4.0}, blocking, w);
    through.predict({2.0, 0.0});
    EXPECT_NEAR(through.position().x, 11.0, 1e-9);  // through the door
    EXPECT_NEAR(through.position().y, 4.0, 1e-9);

    KalmanFilter blocked({9.0, 2.0}, blocking, w);
    blocked.predict({2.0, 0.0});
    EXPECT_LT(blocked.position().x, 10.0);
    EXPECT_GT(blocked.position().x, 9.8);  // stopped at the wall, not before it

    KalmanFilter slides({9.0, 1.0}, blocking, w);
    slides.predict({2.0, 1.0});  // diagonally into the wall: the along-wall part is kept
    EXPECT_LT(slides.position().x, 10.0);
    EXPECT_GT(slides.position().y, 1.4);
    EXPECT_TRUE(w->inside(slides.position()));

    KalmanFilter jamb({9.7, 3.2}, blocking, w);
    jamb.predict({0.7, 0.0});  // clips the door's jamb: goes round it into East
    EXPECT_GT(jamb.position().x, 10.0);
    EXPECT_TRUE(w->inside(jamb.position()));

    // By default a step may pass the wall; where it ends is still walkable.
    KalmanFilter passes({9.0, 2.0}, {}, w);
    passes.predict({2.0, 0.0});
    EXPECT_NEAR(passes.position().x, 11.0, 1e-9);
    KalmanFilter into_wall({9.0, 2.0}, {}, w);
    into_wall.predict({1.0, 0.0});
    EXPECT_TRUE(w->inside(into_wall.position()));
    EXPECT_NEAR(into_wall.position().x, 10.0, 0.5);
}

TEST(RoomsPlan, ScenariosBecomeValidPlansThatAgreeWithTheirRooms) {
    for (const std::string& name : locus::sim::scenario_names()) {
        const Walkable& rooms = locus::sim::scenario(name).map;
        const locus::plan::Plan plan = rooms_plan(rooms);
        EXPECT_TRUE(locus::plan::check_plan(plan).empty()) << name;
        EXPECT_EQ(plan.doors.size(), rooms.doors.size());
        const Walkable planned = Walkable::from_plan(plan);
        // Random short moves: both forms agree on which are legal, except moves passing
        // within a few cm of a door's end. The rooms form only asks "is a door crossed" of
        // a move that changes rooms, so it lets a move through a door and then through a
        // wall beyond it: there the plan, which tests every wall, must be the stricter one.
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> x(0.0, rooms.plan.width), y(0.0, rooms.plan.height), step(-1.5, 1.5);
        const auto near_door_end = [&](Point a, Point b) {
            for (const auto& d : rooms.doors)
                if (locus::distance_to_segment(d.a, a, b) < 0.15 || locus::distance_to_segment(d.b, a, b) < 0.15) return true;
            return false;
        };
        const auto room_changes = [&](Point a, Point b) {
            int changes = 0;
            const locus::Room* last = rooms.plan.room_at(a);
            for (int k = 1; k <= 200; ++k) {
                const locus::Room* r = rooms.plan.room_at({a.x + k / 200.0 * (b.x - a.x), a.y + k / 200.0 * (b.y - a.y)});
                if (r != last) ++changes;
                last = r;
            }
            return changes;
        };
        int legal = 0, compared = 0;
        for (int i = 0; i < 20000; ++i) {
            const Point a{x(rng), y(rng)};
            const Point b{a.x + step(rng), a.y + step(rng)};
            if (!planned.inside(a) || !planned.inside(b) || near_door_end(a, b)) continue;
            const bool by_rooms = rooms.can_move(a, b), by_plan = planned.can_move(a, b);
            if (by_plan) {
                ASSERT_TRUE(by_rooms) << name << ": " << a.x << "," << a.y << " → " << b.x << "," << b.y;
            }
            if (room_changes(a, b) > 1) continue;
            ++compared;
            legal += by_rooms;
            ASSERT_EQ(by_rooms, by_plan) << name << ": " << a.x << "," << a.y << " → " << b.x << "," << b.y;
        }
        EXPECT_GT(compared, 5000);
        EXPECT_GT(legal, compared / 2);
        // Some moves cross walls, except in a single open room (open_area) where none can.
        if (rooms.plan.rooms.size() > 1) {
            EXPECT_LT(legal, compared) << name;
        }
    }
}

TEST(RoomsPlan, AnLShapedRoomHasNoWallBetweenItsRectangles) {
    Walkable rooms;
    rooms.plan.rooms.push_back({1, "L", {{0.0, 0.0, 10.0, 2.0}, {0.0, 0.0, 2.0, 10.0}}});
    const locus::plan::Plan plan = rooms_plan(rooms);
    EXPECT_EQ(plan.spaces.size(), 2u);
    EXPECT_TRUE(locus::plan::check_plan(plan).empty());
    const Walkable planned = Walkable::from_plan(plan);
    EXPECT_TRUE(planned.can_move({1.0, 1.0}, {1.0, 5.0}));   // from one arm into the other
    EXPECT_TRUE(planned.can_move({5.0, 1.0}, {1.0, 1.5}));
    EXPECT_FALSE(planned.can_move({1.9, 3.0}, {3.0, 1.9}));  // the corner is cut through the outline
    // Open rooms: no walls, only the outline.
    Walkable open = locus::sim::scenario("ground").map;
    open.walls_between_rooms = false;
    const locus::plan::Plan open_plan = rooms_plan(open);
    EXPECT_TRUE(open_plan.walls.empty());
    EXPECT_TRUE(open_plan.doors.empty());
    EXPECT_TRUE(Walkable::from_plan(open_plan).can_move({1.0, 3.0}, {1.0, 5.0}));  // office 1 → corridor off the door
}

}  // namespace
}  // namespace fusion_plan_test
