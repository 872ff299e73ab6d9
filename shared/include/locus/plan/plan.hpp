#pragma once
// A floor's plan in floor metres (x right, y up, origin at the floor's lower-left corner, as
// every coordinate of the API): the spaces people are in, the walls between them, the doors
// through the walls and the connectors (stairs, lifts, …) to other floors. It is what routing,
// map matching and the web map read; the exchange form is GeoJSON (server/http), this is the
// typed form the core works on.
//
// Walking space is the union of the spaces; walls cut it (a wall drawn through a space
// divides it), and a door is a gap in the walls it lies on. So a plan may be "rooms with
// doors between them" or "free space with walls drawn in", or both.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "locus/geometry.hpp"

namespace locus::plan {

// Coordinates beyond this (metres) are refused: far more than any building, and small enough
// that squared distances stay exact in a double.
inline constexpr double kMaxPlanCoordinate = 1e5;

// A closed ring as GeoJSON writes it: first point repeated as the last, at least 4 points.
using Ring = std::vector<Point>;

struct Polygon {
    Ring outer;
    std::vector<Ring> holes;  // pillars, light wells: not walkable
};

struct Space {
    std::string name;
    std::string kind = "room";       // "room", "corridor", "hall", "stairwell", … (free text)
    std::vector<std::string> tags;   // directory entries: people's names, departments
    Polygon shape;
    // The API room it is kept in step with: every named space has one once stored (spaces of
    // one name share it); on a PUT, absent means "the floor's room of that name, or a new one".
    std::optional<std::int64_t> room_id;
};

struct Wall {
    std::vector<Point> line;  // a polyline, ≥ 2 points
};

// A gap in the walls: a point on a wall (a door of default width) or a short segment along it.
struct Door {
    Point a;
    Point b;  // == a for a point door
    std::string name;
};
inline constexpr double kDefaultDoorWidth = 0.9;

enum class ConnectorKind { stairs, elevator, escalator, ramp };

// "stairs", "elevator", "escalator", "ramp": the names the API and the store use.
inline const char* connector_kind_name(ConnectorKind k) {
    switch (k) {
        case ConnectorKind::stairs: return "stairs";
        case ConnectorKind::elevator: return "elevator";
        case ConnectorKind::escalator: return "escalator";
        case ConnectorKind::ramp: return "ramp";
    }
    return "stairs";
}
inline std::optional<ConnectorKind> connector_kind_named(std::string_view name) {
    for (auto k : {ConnectorKind::stairs, ConnectorKind::elevator, ConnectorKind::escalator, ConnectorKind::ramp})
        if (name == connector_kind_name(k)) return k;
    return std::nullopt;
}

// One end of a link between floors: the connector on another floor it leads to.
struct ConnectorLink {
    std::int64_t floor_id = 0;
    std::string connector;  // that connector's id in that floor's plan
};

struct Connector {
    std::string id;  // unique within the plan; how other floors' plans name it
    ConnectorKind kind = ConnectorKind::stairs;
    std::string name;
    Point at;
    bool step_free = false;  // usable without steps (lifts, ramps; stairs and escalators: no)
    // Seconds to take it from one floor to the next; absent: walking time of its length
    // (stairs: 6 s per level) or 30 s for an elevator (waiting included).
    std::optional<double> seconds_per_level;
    std::vector<ConnectorLink> links;
    // The API POI it is kept in step with (as Space::room_id): every stored connector has one.
    std::optional<std::int64_t> poi_id;
};

struct Plan {
    std::vector<Space> spaces;
    std::vector<Wall> walls;
    std::vector<Door> doors;
    std::vector<Connector> connectors;
};

// Another floor of the same map, with its plan when it has one.
struct OtherFloor {
    std::int64_t floor_id = 0;
    const Plan* plan = nullptr;
};

// Links between floors, checked when `plan` becomes floor `floor_id`'s: every link names
// another floor of the map and, where that floor has a plan, a connector of it. A link is
// used for routing only once both ends name each other (build_building), so each floor's plan
// can add or drop its side on its own: two floors are joined by PUTting both, and parted by
// PUTting either. Returns one message per problem, naming the connector.
std::vector<std::string> link_problems(std::int64_t floor_id, const Plan& plan, const std::vector<OtherFloor>& others);

}  // namespace locus::plan
