#pragma once
// Where one live track's latest fix is from another's (GET /v1/tracks/{a}/relative/{b},
// docs/tracks.md): the straight distance, the bearing (clockwise from the plan's +y, as
// headings), that bearing turned from a's heading in words, the floors between them and the
// walk on the map's building graph. The geometry is pure; the walk costs one route search.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "locus/plan/route.hpp"
#include "store/store.hpp"
#include "tracks/fix.hpp"
#include "tracks/service.hpp"

namespace locus::tracks {

// Why two tracks have no relative position: on different maps, or one has no fix yet.
struct Unrelated : std::runtime_error {
    enum class Why { other_map, no_fix };
    Why why;
    Unrelated(Why w, const std::string& what) : std::runtime_error(what), why(w) {}
};

struct Relative {
    Fix from, to;  // a's and b's latest fixes
    double from_age_s = 0, to_age_s = 0;
    double straight_distance_m = 0;
    double bearing_deg = 0;
    std::optional<double> relative_bearing_deg;  // when a's fix has a heading
    std::string direction;                       // direction_text of it, when it is known
    std::int64_t floor_difference = 0;           // b's floor level minus a's
    std::optional<plan::Route> route;            // the walk, when one was found
    std::string walking_problem;                 // else why not
};

// Why a map has no building graph to walk on (its message says why: a graph past the
// server's bound); the answer then has no route but a walking_problem.
struct NoGraph : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The map's building graph (routing::Service::building); store::NotFound when the map is
// gone, NoGraph when it has no graph to give.
using BuildingOf = std::function<std::shared_ptr<const plan::Building>(std::int64_t map_id)>;

// Tracks a and b as the Service has them (their access checked by the caller): throws
// Unrelated, the Service's Refused, store::NotFound for a floor gone from the store.
Relative relative(Service& svc, store::Store& store, const BuildingOf& building_of, std::int64_t a_id, std::int64_t b_id);

// From `from` to `to` in [0, 360), clockwise from +y.
double bearing_deg(const Fix& from, const Fix& to);
// The bearing as turned from a heading, in (-180, 180] (positive: clockwise, to the right).
double turned_deg(double bearing_deg, double heading_deg);
// "ahead", "behind", "ahead, 30° left", "behind, 120° right": where the other is, turned from
// one's heading by `relative_deg`.
std::string direction_text(double relative_deg);

}  // namespace locus::tracks
