#pragma once
// What a map's directory lists, read from one store snapshot: every room (its name, plus the
// tags and kind of the plan spaces linked to it by room_id), every POI (name and kind), and
// every plan space with a name or tags that no room stands for. Each with the place a
// visitor is routed to: a room's centre, a POI's point, a point inside a space.
#include <cstdint>
#include <string>
#include <vector>

#include "locus/directory/index.hpp"
#include "locus/geometry.hpp"
#include "store/documents.hpp"

namespace locus::directory {

enum class PlaceKind { room, poi, space };

struct Place {
    PlaceKind kind = PlaceKind::room;
    std::int64_t id = 0;  // the room's or POI's; 0 for a space
    std::string name;
    std::string category;  // the POI's or space's kind; "" when none says more than "room"
    std::vector<std::string> tags;
    std::int64_t floor_id = 0, building_id = 0, level = 0;
    Point at;
    // The route endpoint is {room_id} or {poi_id}, whose position the route endpoint takes
    // as `at`; false: {floor_id, x, y} (a space, or a room without rectangles).
    bool routed_by_id = true;
};

// A map's places and the search index over them (document i is place i).
struct MapDirectory {
    std::vector<Place> places;
    Index index;
};

MapDirectory build_directory(const std::vector<store::FloorDirectory>& floors);

}  // namespace locus::directory
