#include "locus/plan/route.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "locus/plan/ring.hpp"
#include "string_pull.hpp"

namespace locus::plan {

namespace {

bool usable(const Connector& c, bool step_free) {
    if (!step_free) return true;
    return c.step_free || c.kind == ConnectorKind::elevator || c.kind == ConnectorKind::ramp;
}

double seconds_between(const Connector& c, int from_level, int to_level, const ConnectorSeconds& defaults) {
    double per_level = defaults.stairs;
    switch (c.kind) {
        case ConnectorKind::stairs: per_level = defaults.stairs; break;
        case ConnectorKind::escalator: per_level = defaults.escalator; break;
        case ConnectorKind::ramp: per_level = defaults.ramp; break;
        case ConnectorKind::elevator: per_level = defaults.elevator; break;
    }
    return c.seconds_per_level.value_or(per_level) * std::max(1, std::abs(to_level - from_level));
}

// Shortest 8-connected grid distance between two points when nothing is in the way: a lower
// bound of any grid path, and a metric, so the heuristic built on it stays consistent.
double octile(Point a, Point b) {
    const double dx = std::abs(a.x - b.x), dy = std::abs(a.y - b.y);
    return std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy);
}

std::size_t floor_of_node(const Building& b, std::size_t node) {
    std::size_t f = 0;
    while (f + 1 < b.floors.size() && b.floors[f + 1].first_node <= node) ++f;
    return f;
}

// One search's constraints: which connectors, and which cells of each floor are kept out of.
struct Constraints {
    bool step_free = false;
    std::vector<std::vector<std::uint8_t>> blocked;  // per floor; empty: nothing blocked there
    const std::vector<std::uint8_t>* blocked_on(std::size_t floor) const {
        return blocked[floor].empty() ? nullptr : &blocked[floor];
    }
};

Constraints constraints_for(const Building& b, bool step_free, const std::vector<SpaceRef>& avoid, const std::vector<SpaceRef>& exempt) {
    Constraints c;
    c.step_free = step_free;
    c.blocked.resize(b.floors.size());
    for (const SpaceRef& ref : avoid) {
        if (std::any_of(exempt.begin(), exempt.end(), [&](const SpaceRef& e) { return e.floor_id == ref.floor_id && e.space == ref.space; }))
            continue;
        for (std::size_t f = 0; f < b.floors.size(); ++f) {
            const Floor& floor = b.floors[f];
            if (floor.floor_id != ref.floor_id || ref.space >= floor.plan.spaces.size()) continue;
            auto& mask = c.blocked[f];
            if (mask.empty()) mask.assign(floor.grid.space.size(), 0);
            for (std::size_t cell = 0; cell < mask.size(); ++cell)
                if (floor.grid.space[cell] == static_cast<std::int32_t>(ref.space)) mask[cell] = 1;
        }
    }
    return c;
}

// Lower bound of the seconds from each cell of each floor to the goal, for A*. On the goal's
// floor: the landmark (triangle inequality) bound, or octile distance where that is larger.
// Elsewhere, and on the goal's floor for ways that leave it: the exact walk to a connector
// plus a lower bound of the time from that connector on. All are consistent, so closed nodes
// stay closed, and all hold under avoid and step_free, which only make routes longer.
class Heuristic {
public:
    Heuristic(const Building& b, const Constraints& cons, std::size_t goal_floor, int goal_cell, const RouteOptions& o)
        : b_(b), goal_floor_(goal_floor), speed_(o.walking_speed), via_(b.floors.size()) {
        const Floor& gf = b.floors[goal_floor];
        goal_at_ = gf.grid.centre(goal_cell);
        const float* at_goal = gf.landmarks.at(goal_cell);
        goal_metres_.assign(at_goal, at_goal + gf.landmarks.sources.size());

        struct Node {
            std::size_t floor, connector;
            int cell;
            double bound;
        };
        std::vector<Node> nodes;
        for (std::size_t f = 0; f < b.floors.size(); ++f)
            for (std::size_t k = 0; k < b.floors[f].plan.connectors.size(); ++k) {
                const int cell = b.floors[f].grid.connector_cell[k];
                if (cell < 0 || !usable(b.floors[f].plan.connectors[k], cons.step_free)) continue;
                const double to_goal = f == goal_floor ? b.floors[f].landmarks.at(goal_cell)[k] / speed_ : INFINITY;
                nodes.push_back({f, k, cell, to_goal});
            }
        // Dijkstra backwards from the goal over the few connectors, O(n²).
        std::vector<bool> done(nodes.size(), false);
        for (std::size_t round = 0; round < nodes.size(); ++round) {
            std::size_t best = nodes.size();
            for (std::size_t i = 0; i < nodes.size(); ++i)
                if (!done[i] && (best == nodes.size() || nodes[i].bound < nodes[best].bound)) best = i;
            if (best == nodes.size() || !std::isfinite(nodes[best].bound)) break;
            done[best] = true;
            const Node& n = nodes[best];
            for (std::size_t i = 0; i < nodes.size(); ++i) {
                Node& m = nodes[i];
                if (done[i]) continue;
                const Floor& mf = b.floors[m.floor];
                if (m.floor == n.floor) m.bound = std::min(m.bound, n.bound + mf.landmarks.at(n.cell)[m.connector] / speed_);
                for (const LinkTarget& t : mf.links[m.connector])
                    if (t.floor == n.floor && t.connector == n.connector)
                        m.bound = std::min(m.bound, n.bound + seconds_between(mf.plan.connectors[m.connector], mf.level,
                                                                               b.floors[n.floor].level, o.connector_seconds));
            }
        }
        for (const Node& n : nodes)
            if (std::isfinite(n.bound)) via_[n.floor].push_back({n.connector, n.bound});
    }

    float operator()(std::size_t floor, int cell) const {
        const Floor& f = b_.floors[floor];
        const float* metres = f.landmarks.at(cell);
        double h = INFINITY;
        for (const auto& [connector, bound] : via_[floor]) {
            const float m = metres[connector];
            if (m != kNoPath) h = std::min(h, m / speed_ + bound);
        }
        if (floor == goal_floor_) {
            double same = octile(f.grid.centre(cell), goal_at_);
            for (std::size_t l = 0; l < goal_metres_.size(); ++l) {
                const float here = metres[l], there = goal_metres_[l];
                if (here == kNoPath || there == kNoPath) continue;
                same = std::max(same, static_cast<double>(std::abs(here - there)));
            }
            h = std::min(h, same / speed_);
        }
        return static_cast<float>(h);
    }

private:
    const Building& b_;
    std::size_t goal_floor_;
    Point goal_at_;
    double speed_;
    std::vector<float> goal_metres_;
    std::vector<std::vector<std::pair<std::size_t, double>>> via_;  // per floor: (connector, seconds from it to the goal)
};

// A* over every floor's cells; the nodes from start to goal, or nothing.
std::vector<std::size_t> search(const Building& b, const Constraints& cons, std::size_t start, std::size_t goal, const RouteOptions& o,
                                RouteScratch& scratch) {
    const std::size_t goal_floor = floor_of_node(b, goal);
    const Heuristic h(b, cons, goal_floor, static_cast<int>(goal - b.floors[goal_floor].first_node), o);
    scratch.begin(b.node_count);
    auto& g = scratch.g;
    auto& parent = scratch.parent;
    const auto seen = [&](std::size_t n) { return scratch.mark[n] >= scratch.generation; };
    const auto closed = [&](std::size_t n) { return scratch.mark[n] == scratch.generation + 1; };
    // Ties in f, common on a grid, go to the larger g: the node nearer the goal.
    struct Entry {
        float f, g;
        std::size_t node;
        bool operator>(const Entry& o) const { return f > o.f || (f == o.f && g < o.g); }
    };
    std::vector<Entry> storage;
    storage.reserve(4096);
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open(std::greater<>{}, std::move(storage));
    g[start] = 0.0f;
    scratch.mark[start] = scratch.generation;
    open.push({0.0f, 0.0f, start});
    const auto relax = [&](std::size_t from, std::size_t floor, int cell, double cost) {
        const std::size_t to = b.floors[floor].first_node + static_cast<std::size_t>(cell);
        const auto ng = static_cast<float>(g[from] + cost);
        if (closed(to) || (seen(to) && ng >= g[to])) return;
        scratch.mark[to] = scratch.generation;
        g[to] = ng;
        parent[to] = static_cast<std::uint32_t>(from);
        const float estimate = h(floor, cell);
        if (estimate == kNoPath) return;  // the goal cannot be reached from there at all
        open.push({ng + estimate, ng, to});
    };
    while (!open.empty()) {
        const std::size_t u = open.top().node;
        open.pop();
        if (closed(u)) continue;
        scratch.mark[u] = scratch.generation + 1;
        if (u == goal) break;
        const std::size_t f = floor_of_node(b, u);
        const Floor& floor = b.floors[f];
        const WalkGrid& grid = floor.grid;
        const int cell = static_cast<int>(u - floor.first_node);
        const auto* blocked = cons.blocked_on(f);
        const double straight = grid.options.cell / o.walking_speed, diagonal = straight * std::sqrt(2.0);
        const std::uint8_t moves = grid.moves[static_cast<std::size_t>(cell)];
        for (int d = 0; d < 8; ++d) {
            if (!(moves & (1u << d))) continue;
            const int next = cell + kDirCol[d] + kDirRow[d] * grid.cols;
            if (blocked && (*blocked)[static_cast<std::size_t>(next)]) continue;
            relax(u, f, next, (d % 2) ? diagonal : straight);
        }
        if (!(grid.flags[static_cast<std::size_t>(cell)] & WalkGrid::kConnector)) continue;
        for (std::size_t k = 0; k < floor.plan.connectors.size(); ++k) {
            if (grid.connector_cell[k] != cell || !usable(floor.plan.connectors[k], cons.step_free)) continue;
            for (const LinkTarget& t : floor.links[k]) {
                const Floor& other = b.floors[t.floor];
                const int there = other.grid.connector_cell[t.connector];
                const auto* other_blocked = cons.blocked_on(t.floor);
                if (there < 0 || (other_blocked && (*other_blocked)[static_cast<std::size_t>(there)])) continue;
                relax(u, t.floor, there, seconds_between(floor.plan.connectors[k], floor.level, other.level, o.connector_seconds));
            }
        }
    }
    if (!closed(goal)) return {};
    std::vector<std::size_t> path{goal};
    while (path.back() != start) path.push_back(parent[path.back()]);
    std::reverse(path.begin(), path.end());
    return path;
}

struct Snapped {
    int cell = -1;
    Point point;  // where the route starts or ends
};

Snapped snap(const Floor& floor, Point p) {
    const bool walkable = std::any_of(floor.plan.spaces.begin(), floor.plan.spaces.end(),
                                      [&](const Space& s) { return polygon_contains(s.shape, p); });
    // From inside, the way to the grid may not pass a wall; from outside it has to cross the outline.
    const int cell = floor.grid.snap(p, nullptr, walkable);
    if (cell < 0) return {};
    return {cell, walkable ? p : floor.grid.centre(cell)};
}

// The cheapest connector taking node u (floor fu) to node v (floor fv).
Transfer transfer_between(const Building& b, std::size_t fu, int cu, std::size_t fv, int cv, const Constraints& cons, const RouteOptions& o) {
    const Floor& from = b.floors[fu];
    Transfer best;
    best.seconds = INFINITY;
    for (std::size_t k = 0; k < from.plan.connectors.size(); ++k) {
        const Connector& c = from.plan.connectors[k];
        if (from.grid.connector_cell[k] != cu || !usable(c, cons.step_free)) continue;
        for (const LinkTarget& t : from.links[k]) {
            if (t.floor != fv || b.floors[fv].grid.connector_cell[t.connector] != cv) continue;
            const double s = seconds_between(c, from.level, b.floors[fv].level, o.connector_seconds);
            if (s < best.seconds) best = {c.kind, c.name.empty() ? c.id : c.name, from.level, b.floors[fv].level, s};
        }
    }
    return best;
}

double polyline_length(const std::vector<Point>& path) {
    double len = 0.0;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) len += distance(path[i], path[i + 1]);
    return len;
}

void assemble(const Building& b, const std::vector<std::size_t>& nodes, const Constraints& cons, const RouteOptions& o, Route& r) {
    std::size_t i = 0;
    while (i < nodes.size()) {
        const std::size_t f = floor_of_node(b, nodes[i]);
        const Floor& floor = b.floors[f];
        std::vector<Point> points;
        if (i == 0) points.push_back(r.start);
        std::size_t j = i;
        for (; j < nodes.size() && floor_of_node(b, nodes[j]) == f; ++j)
            points.push_back(floor.grid.centre(static_cast<int>(nodes[j] - floor.first_node)));
        if (j == nodes.size()) points.push_back(r.end);
        points.erase(std::unique(points.begin(), points.end(), [](Point p, Point q) { return p.x == q.x && p.y == q.y; }), points.end());
        Leg leg{floor.floor_id, floor.level, pull_string(floor.grid, cons.blocked_on(f), points), 0.0};
        leg.length_m = polyline_length(leg.path);
        // Riding on through a floor (stairs from 1 to 3) makes one transfer, not two and an empty leg.
        if (!r.transfers.empty() && j < nodes.size() && leg.length_m < 0.5) {
            const std::size_t fv = floor_of_node(b, nodes[j]);
            const Floor& next = b.floors[fv];
            Transfer t = transfer_between(b, f, static_cast<int>(nodes[j - 1] - floor.first_node), fv, static_cast<int>(nodes[j] - next.first_node), cons, o);
            if (t.kind == r.transfers.back().kind) {
                r.transfers.back().to_level = t.to_level;
                r.transfers.back().seconds += t.seconds;
                i = j;
                continue;
            }
        }
        r.legs.push_back(std::move(leg));
        if (j < nodes.size()) {
            const std::size_t fv = floor_of_node(b, nodes[j]);
            r.transfers.push_back(transfer_between(b, f, static_cast<int>(nodes[j - 1] - floor.first_node), fv,
                                                   static_cast<int>(nodes[j] - b.floors[fv].first_node), cons, o));
        }
        i = j;
    }
    for (const Leg& leg : r.legs) r.length_m += leg.length_m;
    r.time_s = r.length_m / o.walking_speed;
    for (const Transfer& t : r.transfers) r.time_s += t.seconds;
    r.steps = instructions(r.legs, r.transfers);
}

std::vector<SpaceRef> spaces_holding(const Floor& floor, Point p) {
    std::vector<SpaceRef> out;
    for (std::size_t s = 0; s < floor.plan.spaces.size(); ++s)
        if (polygon_contains(floor.plan.spaces[s].shape, p)) out.push_back({floor.floor_id, s});
    return out;
}

}  // namespace

const char* to_string(RouteStatus status) {
    switch (status) {
        case RouteStatus::ok: return "ok";
        case RouteStatus::unknown_floor: return "a floor of the route has no plan";
        case RouteStatus::start_off_plan: return "'from' is more than 2 m from any walkable space of its floor's plan";
        case RouteStatus::end_off_plan: return "'to' is more than 2 m from any walkable space of its floor's plan";
        case RouteStatus::unreachable: return "no walkable way joins the two places";
        case RouteStatus::needs_steps: return "the only way takes stairs or an escalator, and 'step_free' is set";
        case RouteStatus::needs_avoided: return "the only way passes through a room in 'avoid'";
        case RouteStatus::needs_steps_and_avoided:
            return "the only way takes stairs or an escalator and passes through a room in 'avoid'";
    }
    return "?";
}

Building build_building(std::vector<FloorSpec> specs, const GridOptions& options) {
    Building b;
    for (FloorSpec& s : specs) {
        Floor f;
        f.floor_id = s.floor_id;
        f.level = s.level;
        f.grid = build_walk_grid(s.plan, options);
        std::vector<int> sources = f.grid.connector_cell;
        for (const int cell : corner_cells(f.grid)) sources.push_back(cell);
        f.landmarks = landmarks_from(f.grid, sources);
        f.plan = std::move(s.plan);
        f.first_node = b.node_count;
        b.node_count += static_cast<std::size_t>(f.grid.cell_count());
        b.floors.push_back(std::move(f));
    }
    for (Floor& f : b.floors) {
        f.links.resize(f.plan.connectors.size());
        for (std::size_t k = 0; k < f.plan.connectors.size(); ++k)
            for (const ConnectorLink& link : f.plan.connectors[k].links)
                for (std::size_t t = 0; t < b.floors.size(); ++t) {
                    if (b.floors[t].floor_id != link.floor_id || &b.floors[t] == &f) continue;
                    const auto& cons = b.floors[t].plan.connectors;
                    // Only a pair: a link its partner does not return waits for that floor's plan.
                    for (std::size_t m = 0; m < cons.size(); ++m)
                        if (cons[m].id == link.connector &&
                            std::any_of(cons[m].links.begin(), cons[m].links.end(), [&](const ConnectorLink& back) {
                                return back.floor_id == f.floor_id && back.connector == f.plan.connectors[k].id;
                            }))
                            f.links[k].push_back({t, m});
                }
    }
    return b;
}

BuildingCost building_cost(const std::vector<FloorSpec>& floors, const GridOptions& options) {
    // Per cell: the grid's flags, moves and space (6 bytes), a route's mark, g and parent (12),
    // the landmark build's distances of one source at a time (4), and 4 per landmark.
    constexpr double kCellBytes = 22.0, kLandmarkBytes = 4.0;
    BuildingCost cost;
    for (const FloorSpec& f : floors) {
        const double cells = walk_grid_cells(f.plan, options);
        const double landmarks = static_cast<double>(f.plan.connectors.size()) + 4.0;  // corner_cells: four
        cost.cells += cells;
        cost.landmark_cells += cells * landmarks;
        cost.bytes += cells * (kCellBytes + kLandmarkBytes * landmarks);
    }
    return cost;
}

std::vector<SpaceRef> spaces_of_room(const Building& building, std::int64_t room_id) {
    std::vector<SpaceRef> out;
    for (const Floor& f : building.floors)
        for (std::size_t s = 0; s < f.plan.spaces.size(); ++s)
            if (f.plan.spaces[s].room_id == room_id) out.push_back({f.floor_id, s});
    return out;
}

void RouteScratch::begin(std::size_t nodes) {
    // Marks of earlier searches are below the new generation, so nothing needs clearing.
    generation += 2;
    if (mark.size() != nodes || generation < 2) {
        mark.assign(nodes, 0);
        g.assign(nodes, 0.0f);
        parent.assign(nodes, 0);
        generation = 2;
    }
}

Route route(const Building& b, const Endpoint& from, const Endpoint& to, const RouteOptions& o) {
    RouteScratch scratch;
    return route(b, from, to, o, scratch);
}

Route route(const Building& b, const Endpoint& from, const Endpoint& to, const RouteOptions& o, RouteScratch& scratch) {
    Route r;
    const auto find_floor = [&](std::int64_t id) {
        std::size_t f = 0;
        while (f < b.floors.size() && b.floors[f].floor_id != id) ++f;
        return f;
    };
    const std::size_t ff = find_floor(from.floor_id), tf = find_floor(to.floor_id);
    if (ff == b.floors.size() || tf == b.floors.size()) {
        r.status = RouteStatus::unknown_floor;
        return r;
    }
    const Snapped s = snap(b.floors[ff], from.at), e = snap(b.floors[tf], to.at);
    if (s.cell < 0 || e.cell < 0) {
        r.status = s.cell < 0 ? RouteStatus::start_off_plan : RouteStatus::end_off_plan;
        return r;
    }
    r.start = s.point;
    r.end = e.point;
    const std::size_t start = b.floors[ff].first_node + static_cast<std::size_t>(s.cell);
    const std::size_t goal = b.floors[tf].first_node + static_cast<std::size_t>(e.cell);

    // Being in an avoided space is no reason to be stuck there.
    std::vector<SpaceRef> exempt = spaces_holding(b.floors[ff], from.at);
    const std::vector<SpaceRef> at_end = spaces_holding(b.floors[tf], to.at);
    exempt.insert(exempt.end(), at_end.begin(), at_end.end());

    const auto attempt = [&](bool step_free, bool avoid) {
        const Constraints cons = constraints_for(b, step_free, avoid ? o.avoid : std::vector<SpaceRef>{}, exempt);
        return std::make_pair(search(b, cons, start, goal, o, scratch), cons);
    };
    auto [nodes, cons] = attempt(o.step_free, true);
    if (!nodes.empty()) {
        r.status = RouteStatus::ok;
        assemble(b, nodes, cons, o, r);
        return r;
    }
    // Which constraint blocked it: relax one at a time, then both.
    const bool avoiding = !o.avoid.empty();
    if (o.step_free && avoiding && !attempt(true, false).first.empty()) r.status = RouteStatus::needs_avoided;
    else if (o.step_free && !attempt(false, true).first.empty()) r.status = RouteStatus::needs_steps;
    else if (avoiding && !o.step_free && !attempt(false, false).first.empty()) r.status = RouteStatus::needs_avoided;
    else if (o.step_free && avoiding && !attempt(false, false).first.empty()) r.status = RouteStatus::needs_steps_and_avoided;
    else r.status = RouteStatus::unreachable;
    return r;
}

}  // namespace locus::plan
