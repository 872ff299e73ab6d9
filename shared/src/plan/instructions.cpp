#include "locus/plan/instructions.hpp"

#include <cmath>
#include <numbers>

namespace locus::plan {

namespace {

constexpr double kNoTurnBelow = 20.0, kSlightBelow = 45.0, kTurnBelow = 135.0;  // degrees

// Signed heading change from ab to bc, degrees, left positive.
double turn_degrees(Point a, Point b, Point c) {
    const double h1 = std::atan2(b.y - a.y, b.x - a.x), h2 = std::atan2(c.y - b.y, c.x - b.x);
    double d = (h2 - h1) * 180.0 / std::numbers::pi;
    while (d > 180.0) d -= 360.0;
    while (d <= -180.0) d += 360.0;
    return d;
}

Step walk(double metres) {
    const long rounded = std::max(1L, std::lround(metres));
    return {StepKind::walk, metres, {}, {}, 0, 0, "Walk " + std::to_string(rounded) + " m"};
}

Step turn(double degrees) {
    const bool left = degrees > 0.0;
    const double a = std::abs(degrees);
    if (a < kSlightBelow) return {left ? StepKind::slight_left : StepKind::slight_right, 0, {}, {}, 0, 0, left ? "Turn slightly left" : "Turn slightly right"};
    if (a < kTurnBelow) return {left ? StepKind::turn_left : StepKind::turn_right, 0, {}, {}, 0, 0, left ? "Turn left" : "Turn right"};
    return {left ? StepKind::sharp_left : StepKind::sharp_right, 0, {}, {}, 0, 0, left ? "Turn sharp left" : "Turn sharp right"};
}

void leg_steps(const std::vector<Point>& path, std::vector<Step>& out) {
    double walked = 0.0, pending = 0.0;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        walked += distance(path[i], path[i + 1]);
        if (i + 2 >= path.size()) break;
        pending += turn_degrees(path[i], path[i + 1], path[i + 2]);
        // The bend is announced once the path runs straight long enough after it.
        if (distance(path[i + 1], path[i + 2]) < kMergeTurnsWithin) continue;
        if (std::abs(pending) >= kNoTurnBelow) {
            out.push_back(walk(walked));
            out.push_back(turn(pending));
            walked = 0.0;
        }
        pending = 0.0;
    }
    if (walked > 0.0) out.push_back(walk(walked));
}

}  // namespace

std::vector<Step> instructions(const std::vector<Leg>& legs, const std::vector<Transfer>& transfers) {
    std::vector<Step> out;
    for (std::size_t i = 0; i < legs.size(); ++i) {
        leg_steps(legs[i].path, out);
        if (i >= transfers.size()) continue;
        const Transfer& t = transfers[i];
        Step s{StepKind::take_connector, 0.0, t.kind, t.name, t.from_level, t.to_level, ""};
        const char* way = t.to_level > t.from_level ? "up" : "down";
        s.text = std::string("Take the ") + connector_kind_name(t.kind) + " " + way + " to level " + std::to_string(t.to_level);
        out.push_back(s);
    }
    out.push_back({StepKind::arrive, 0, {}, {}, 0, 0, "Arrive at your destination"});
    return out;
}

}  // namespace locus::plan
