#include "sim/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <stdexcept>

namespace locus::sim {

namespace {

std::string bssid(int floor, int i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "02:10:%02x:00:00:%02x", floor, i);
    return buf;
}

Room room(long long id, const std::string& name, Rect r) { return Room{id, name, {r}}; }

// A horizontal door on the wall y = y0 spanning x ∈ [x0, x1], or a vertical one.
Segment hdoor(double x0, double x1, double y0) { return {{x0, y0}, {x1, y0}}; }

Scenario make_ground() {
    Scenario s;
    s.name = "ground";
    s.description = "DISI ground floor, 222.8 m2: hall, corridor and four offices; walk of 26.5 m";
    auto& plan = s.map.plan;
    plan.width = 28.0;
    plan.height = 10.3;
    plan.rooms = {
        room(1, "corridor", {0.0, 4.0, 28.0, 6.2}),  // 61.6 m²
        room(2, "office 1", {0.0, 0.0, 7.0, 4.0}),   // 4 × 28 m²
        room(3, "office 2", {7.0, 0.0, 14.0, 4.0}),
        room(4, "office 3", {14.0, 0.0, 21.0, 4.0}),
        room(5, "office 4", {21.0, 0.0, 28.0, 4.0}),
        room(6, "hall", {0.0, 6.2, 12.0, 10.3}),      // 49.2 m²
    };
    s.map.doors = {hdoor(2.5, 3.5, 4.0), hdoor(9.5, 10.5, 4.0), hdoor(16.5, 17.5, 4.0), hdoor(22.0, 23.0, 4.0),
                   hdoor(4.0, 7.0, 6.2)};
    s.path = {{2.5, 8.5}, {5.5, 8.5}, {5.5, 5.1}, {22.5, 5.1}, {22.5, 2.0}};
    s.aps = {{bssid(0, 1), {1.0, 9.5}, -38.0},  {bssid(0, 2), {11.0, 9.0}, -40.0}, {bssid(0, 3), {3.5, 1.0}, -41.0},
             {bssid(0, 4), {13.0, 5.8}, -39.0}, {bssid(0, 5), {17.5, 1.5}, -42.0}, {bssid(0, 6), {26.5, 3.0}, -40.0},
             {bssid(0, 7), {26.0, 5.5}, -38.0}, {bssid(0, 8), {9.0, 2.0}, -43.0}};
    // Reinforced concrete, radiators, desks: the compass is bent by ~10° here and there.
    s.structure_deflection_rad = 10.0 * std::numbers::pi / 180.0;
    s.structure_norm_ripple = 0.03;
    s.environment_seed = 1001;
    s.rps = points_along(s.path, 2.0);
    return s;
}

Scenario make_basement() {
    Scenario s;
    s.name = "basement";
    s.description =
        "DISI basement, 452.4 m2: technical room with a strong magnetic anomaly, iron structure; walk of 52 m";
    auto& plan = s.map.plan;
    plan.width = 36.0;
    plan.height = 14.6;
    plan.rooms = {
        room(1, "corridor", {0.0, 6.0, 36.0, 8.5}),          // 90 m²
        room(2, "technical room", {0.0, 0.0, 9.0, 6.0}),     // 4 × 54 m²
        room(3, "lab 1", {9.0, 0.0, 18.0, 6.0}),
        room(4, "storage", {18.0, 0.0, 27.0, 6.0}),
        room(5, "lab 2", {27.0, 0.0, 36.0, 6.0}),
        room(6, "archive", {0.0, 8.5, 12.0, 14.6}),          // 2 × 73.2 m²
        room(7, "study room", {24.0, 8.5, 36.0, 14.6}),
    };
    s.map.doors = {hdoor(4.0, 5.0, 6.0),   hdoor(13.0, 14.0, 6.0), hdoor(22.0, 23.0, 6.0), hdoor(31.0, 32.0, 6.0),
                   hdoor(5.5, 6.5, 8.5),   hdoor(29.5, 30.5, 8.5)};
    s.path = {{1.5, 1.5}, {4.5, 1.5}, {4.5, 7.25}, {30.0, 7.25}, {30.0, 12.5}, {34.5, 12.5}, {34.5, 9.5}, {29.5, 9.5}};
    s.aps = {{bssid(1, 1), {8.0, 5.0}, -40.0},   {bssid(1, 2), {1.0, 13.5}, -41.0}, {bssid(1, 3), {13.5, 1.0}, -42.0},
             {bssid(1, 4), {17.0, 8.0}, -39.0},  {bssid(1, 5), {24.0, 3.0}, -40.0}, {bssid(1, 6), {35.0, 1.0}, -41.0},
             {bssid(1, 7), {25.0, 13.5}, -40.0}, {bssid(1, 8), {35.5, 14.0}, -42.0}, {bssid(1, 9), {29.0, 6.5}, -39.0}};
    s.wall_loss_db = 5.0;  // concrete
    s.structure_deflection_rad = 35.0 * std::numbers::pi / 180.0;
    s.structure_scale_m = 7.0;
    s.structure_norm_ripple = 0.06;
    s.sources = {{{4.5, 3.0}, 45.0, 3.5}};  // the technical room's hardware
    s.environment_seed = 2002;
    s.rps = points_along(s.path, 2.0);
    return s;
}

// The test area of the Kalman-fusion paper (docs/spec.md §8 "Sources"), its §4: a
// 300 m² open area with chairs, tables and people passing, 2 WiFi APs and 4 BLE tags as
// anchors, the phone in hand walking one fixed path, coordinates every 5 s. The paper gives
// neither plan nor path nor anchor positions: a 25 m × 12 m hall, the walk a loop along its
// middle (the free "corridor" between the furniture), the anchors on the two long sides of
// it, 4 m from the walk, so every point of it has at least four anchors within the paper's
// 10 m cutoff. The anchors' model is the paper's (n = 2, RSS at 1 m as configured); the room's
// true exponents scatter around it.
Scenario make_open_area() {
    Scenario s;
    s.name = "open_area";
    s.description = "the Kalman-fusion paper's open area, 300 m2: 4 BLE + 2 WiFi anchors around the walk's corridor; loop of 46 m";
    auto& plan = s.map.plan;
    plan.width = 25.0;
    plan.height = 12.0;
    plan.rooms = {room(1, "hall", {0.0, 0.0, 25.0, 12.0})};
    s.path = {{3.0, 6.0}, {22.0, 6.0}, {22.0, 8.0}, {8.0, 8.0}, {8.0, 4.0}, {16.0, 4.0}};
    s.aps = {{bssid(4, 1), {12.5, 2.0}, -40.0}, {bssid(4, 2), {12.5, 10.0}, -40.0}};
    s.beacons = {
        {"ble", "cc1350-1", {4.0, 2.0}, 2.5, -59.0, 2.0, 2.05},
        {"ble", "cc1350-2", {21.0, 2.0}, 2.5, -59.0, 2.0, 1.95},
        {"ble", "cc1350-3", {4.0, 10.0}, 2.5, -59.0, 2.0, 2.0},
        {"ble", "cc1350-4", {21.0, 10.0}, 2.5, -59.0, 2.0, 2.1},
        {"wifi", s.aps[0].bssid, s.aps[0].at, 2.5, -40.0, 2.0, 2.05},
        {"wifi", s.aps[1].bssid, s.aps[1].at, 2.5, -40.0, 2.0, 1.95},
    };
    s.path_loss_exponent = 2.0;
    s.beacon_shadowing_sigma_db = 1.0;
    s.structure_deflection_rad = 8.0 * std::numbers::pi / 180.0;
    s.structure_norm_ripple = 0.03;
    s.environment_seed = 4004;
    s.rps = points_along(s.path, 2.0);
    return s;
}

}  // namespace

double Scenario::area_m2() const {
    double a = 0.0;
    for (const Room& r : map.plan.rooms) a += r.area();
    return a;
}

double Scenario::path_length_m() const {
    double l = 0.0;
    for (std::size_t i = 1; i < path.size(); ++i) l += distance(path[i - 1], path[i]);
    return l;
}

Point point_at_arc(const std::vector<Point>& path, double s) {
    if (path.empty()) return {};
    for (std::size_t i = 1; i < path.size(); ++i) {
        const double seg = distance(path[i - 1], path[i]);
        if (s <= seg || i + 1 == path.size()) {
            const double t = seg > 0.0 ? std::clamp(s / seg, 0.0, 1.0) : 0.0;
            return {path[i - 1].x + t * (path[i].x - path[i - 1].x), path[i - 1].y + t * (path[i].y - path[i - 1].y)};
        }
        s -= seg;
    }
    return path.front();
}

std::vector<Point> points_along(const std::vector<Point>& path, double spacing_m) {
    double total = 0.0;
    for (std::size_t i = 1; i < path.size(); ++i) total += distance(path[i - 1], path[i]);
    const int n = std::max(1, static_cast<int>(std::round(total / spacing_m)));
    std::vector<Point> out;
    for (int i = 0; i <= n; ++i) out.push_back(point_at_arc(path, total * i / n));
    return out;
}

const Scenario& scenario(const std::string& name) {
    static const Scenario ground = make_ground();
    static const Scenario basement = make_basement();
    static const Scenario open_area = make_open_area();
    if (name == "ground") return ground;
    if (name == "basement") return basement;
    if (name == "open_area" || name == kOpenAreaAlias) return open_area;
    throw std::invalid_argument("unknown scenario '" + name + "' (ground, basement, open_area)");
}

std::span<const std::string> scenario_names() {
    static const std::vector<std::string> names{"ground", "basement", "open_area"};
    return names;
}

}  // namespace locus::sim
