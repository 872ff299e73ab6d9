// A floor's rooms and POIs indexed for "where am I, in words" (locus/floor_places.hpp): the room
// at a point is the first in the rooms' order that holds it (an overlap goes to the earlier
// room, a shared wall too, the outside is no room), the same answer as the plain scan of every
// room on a floor of many; the POIs near a point come nearest first, the radius inclusive.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "locus/floor_places.hpp"

namespace floor_places_test {
namespace {

using locus::FloorPlaces;
using locus::Point;
using locus::Poi;
using locus::Rect;
using locus::Room;

Room room(long long id, const char* name, std::vector<Rect> rects) { return {id, name, std::move(rects)}; }

TEST(FloorPlaces, TheRoomAtAPointIsTheFirstThatHoldsIt) {
    // An L-shaped hall of two rectangles, an office inside its corner (listed after it), a lab
    // beside the hall sharing its wall at x = 10, and a store room far off.
    const FloorPlaces places({room(1, "hall", {{0, 0, 10, 4}, {0, 4, 4, 12}}), room(2, "office", {{1, 1, 3, 3}}),
                              room(3, "lab", {{10, 0, 16, 6}}), room(4, "store", {{40, 40, 42, 41}})},
                             {});
    const auto name_at = [&](double x, double y) {
        const Room* r = places.room_at({x, y});
        return r ? r->name : std::string("-");
    };
    EXPECT_EQ(name_at(5, 2), "hall");
    EXPECT_EQ(name_at(2, 10), "hall");   // the L's other arm
    EXPECT_EQ(name_at(2, 2), "hall");    // the office overlaps the hall, which comes first
    EXPECT_EQ(name_at(10, 2), "hall");   // on the shared wall: the earlier room
    EXPECT_EQ(name_at(10.5, 2), "lab");
    EXPECT_EQ(name_at(16, 6), "lab");    // a far corner, closed
    EXPECT_EQ(name_at(8, 8), "-");       // inside the box, in no room
    EXPECT_EQ(name_at(41, 40.5), "store");
    EXPECT_EQ(name_at(42, 41), "store"); // the box's far corner
    EXPECT_EQ(name_at(-1, 2), "-");
    EXPECT_EQ(name_at(50, 50), "-");
    EXPECT_EQ(name_at(NAN, 2), "-");
}

TEST(FloorPlaces, AFloorOfAThousandRoomsAnswersAsTheScanOfEveryRoom) {
    // 1,000 rooms of one to three rectangles on a 200 m × 100 m floor, overlapping at random.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> x(0, 200), y(0, 100), side(0.5, 12);
    std::vector<Room> rooms;
    for (long long i = 1; i <= 1000; ++i) {
        Room r{i, "room " + std::to_string(i), {}};
        const int n = 1 + static_cast<int>(i % 3);
        for (int k = 0; k < n; ++k) {
            const double x0 = x(rng), y0 = y(rng);
            r.rects.push_back({x0, y0, x0 + side(rng), y0 + side(rng)});
        }
        rooms.push_back(std::move(r));
    }
    const FloorPlaces places(rooms, {});
    std::uniform_real_distribution<double> px(-5, 215), py(-5, 115);
    int in_some = 0;
    for (int k = 0; k < 20000; ++k) {
        const Point p{px(rng), py(rng)};
        const Room* got = places.room_at(p);
        const Room* want = nullptr;
        for (const auto& r : rooms)
            if (r.contains(p)) {
                want = &r;
                break;
            }
        ASSERT_EQ(got ? got->id : 0, want ? want->id : 0) << p.x << ", " << p.y;
        in_some += want != nullptr;
    }
    EXPECT_GT(in_some, 5000);  // the test asked inside rooms often, not only outside
    // The grid is about one cell per rectangle: the index stays a few times the rooms' size.
    EXPECT_LT(places.memory_bytes(), 1'000'000u);
}

TEST(FloorPlaces, NearbyPoisComeNearestFirstWithinTheRadius) {
    const FloorPlaces places({}, {Poi{5, "lift", "lift", {3, 4}}, Poi{2, "exit", "exit", {0, 1.5}}, Poi{9, "desk", "desk", {1.5, 0}},
                                  Poi{7, "far", "desk", {0, 1.6}}});
    const auto near = places.nearby({0, 0});  // the default checkpoint radius, 1.5 m
    ASSERT_EQ(near.size(), 2u);
    EXPECT_EQ(near[0].poi->id, 2);  // 1.5 m, on the radius: in; tied with the desk, the smaller id first
    EXPECT_EQ(near[1].poi->id, 9);
    EXPECT_DOUBLE_EQ(near[0].distance_m, 1.5);
    const auto wide = places.nearby({0, 0}, 5.0);
    ASSERT_EQ(wide.size(), 4u);
    EXPECT_EQ(wide[2].poi->id, 7);
    EXPECT_EQ(wide[3].poi->id, 5);
    EXPECT_DOUBLE_EQ(wide[3].distance_m, 5.0);
    EXPECT_TRUE(places.nearby({100, 100}).empty());
    EXPECT_EQ(places.room_at({0, 0}), nullptr);  // no rooms: no room anywhere
}

}  // namespace
}  // namespace floor_places_test
