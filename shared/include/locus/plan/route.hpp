#pragma once
// Routing through a building: every floor's walk grid, joined by the connectors' links, and
// A* over all of them at once (cost: seconds). The grid path of each floor is then
// straightened by line of sight ("string pulling") so a leg has few vertices and nearly the
// length of the true shortest path; docs/routing.md has the figures.
#include <cstdint>
#include <string>
#include <vector>

#include "locus/plan/instructions.hpp"
#include "locus/plan/landmarks.hpp"
#include "locus/plan/plan.hpp"
#include "locus/plan/walk_grid.hpp"

namespace locus::plan {

struct FloorSpec {
    std::int64_t floor_id = 0;
    int level = 0;  // 0 ground, 1 first, … what instructions say
    Plan plan;
};

// Where a connector's link leads, resolved to indices.
struct LinkTarget {
    std::size_t floor;      // index in Building::floors
    std::size_t connector;  // index in that floor's plan.connectors
};

struct Floor {
    std::int64_t floor_id = 0;
    int level = 0;
    Plan plan;
    WalkGrid grid;
    std::vector<std::vector<LinkTarget>> links;  // per plan connector; unresolvable links dropped (check_links reports them)
    Landmarks landmarks;  // sources: each connector's cell (same order), then the corners
    std::size_t first_node = 0;  // this floor's cells are nodes first_node … first_node + cells − 1
};

struct Building {
    std::vector<Floor> floors;
    std::size_t node_count = 0;
};

Building build_building(std::vector<FloorSpec> floors, const GridOptions& options = {});

// What build_building would hold, worked out from the plans alone (no grid is built): each
// floor's walk grid cells (walk_grid_cells), and per cell a landmark distance (a float) from
// each of its connectors and four corners, each of them also a Dijkstra over the whole floor.
// bytes estimates the memory: the landmark floats, the grid's per-cell arrays and a route's
// per-cell search arrays. Building time grows as `landmark_cells`.
struct BuildingCost {
    double cells = 0.0;
    double landmark_cells = 0.0;  // Σ over floors of cells × landmarks
    double bytes = 0.0;
};
BuildingCost building_cost(const std::vector<FloorSpec>& floors, const GridOptions& options = {});

// A space to keep out of, by floor and index in that floor's plan.spaces.
struct SpaceRef {
    std::int64_t floor_id = 0;
    std::size_t space = 0;
};
// The spaces kept in step with an API room (Space::room_id), to avoid a room by its id.
std::vector<SpaceRef> spaces_of_room(const Building& building, std::int64_t room_id);

// Seconds per level for connectors that do not give their own.
struct ConnectorSeconds {
    double stairs = 6.0;
    double escalator = 10.0;
    double ramp = 6.0;
    double elevator = 30.0;  // waiting included
};

struct RouteOptions {
    bool step_free = false;  // no stairs or escalators (a connector with step_free set is allowed)
    // Cells of these spaces are not walked, unless the start or the end is in the space.
    std::vector<SpaceRef> avoid;
    double walking_speed = 1.3;  // m/s
    ConnectorSeconds connector_seconds;
};

struct Endpoint {
    std::int64_t floor_id = 0;
    Point at;
};

enum class RouteStatus {
    ok,
    unknown_floor,
    start_off_plan,   // no free cell within kSnapRadius of the start
    end_off_plan,
    unreachable,      // not even without step_free and avoid
    needs_steps,      // reachable only without step_free
    needs_avoided,    // reachable only through an avoided space
    needs_steps_and_avoided,  // reachable only with both relaxed
};
// Why there is no route, in the words the API answers (422 no_route), naming the option or
// endpoint that blocked it.
const char* to_string(RouteStatus status);

struct Route {
    RouteStatus status = RouteStatus::unreachable;
    Point start, end;  // after snapping: the endpoints themselves when they were walkable
    double length_m = 0.0;
    double time_s = 0.0;  // walking plus connectors
    std::vector<Leg> legs;
    std::vector<Transfer> transfers;  // transfers[i] leads from legs[i] to legs[i + 1]
    std::vector<Step> steps;
};

// The search's per-node arrays, kept between routes on one building so each route does not
// allocate and clear megabytes; one per thread (routes on it must not run concurrently).
struct RouteScratch {
    std::vector<std::uint32_t> mark;  // generation: reached; generation + 1: closed
    std::vector<float> g;
    std::vector<std::uint32_t> parent;
    std::uint32_t generation = 0;
    void begin(std::size_t nodes);
};

Route route(const Building& building, const Endpoint& from, const Endpoint& to, const RouteOptions& options = {});
Route route(const Building& building, const Endpoint& from, const Endpoint& to, const RouteOptions& options, RouteScratch& scratch);

}  // namespace locus::plan
