// GNSS on a thin client's track (docs/tracks.md, "GNSS and the phone's offset"), against the real
// server: `gnss` fixes on POST /v1/tracks/{id}/steps, taken on the track's floor through its
// georeference, pull a walk_pf track towards them (one fix per 10 s at most); a Kalman track
// drops a fix beyond its gate; GNSS alone starts no track; a floor without a georeference
// ignores them; a retried batch moves nothing twice; and bad GNSS is refused with nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_tracks_gnss_test {
namespace {

using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::track_call;
using locus::testing::unix_now;
using nlohmann::json;

// The floor's georeference: floor point (0, 0) at 45° N 7° E, its +y axis pointing east
// (bearing 90°), so its +x axis points south. Metres per degree at 45° from the usual series
// for the WGS84 ellipsoid (111132.954 − 559.822 cos 2φ + 1.175 cos 4φ along a meridian,
// 111412.84 cos φ − 93.5 cos 3φ along a parallel), not the server's conversion: over 40 m they
// agree with the exact one to a few centimetres.
constexpr double kLat0 = 45.0, kLon0 = 7.0;
constexpr double kMetresPerDegLat = 111131.779;
constexpr double kMetresPerDegLon = 78846.84;

json floor_geo() { return {{"lat", kLat0}, {"lon", kLon0}, {"x", 0.0}, {"y", 0.0}, {"bearing_deg", 90.0}}; }

// Where floor point (x, y) is on Earth: north is −x, east is +y.
std::pair<double, double> lat_lon_of(double x, double y) { return {kLat0 - x / kMetresPerDegLat, kLon0 + y / kMetresPerDegLon}; }

std::string steps_path(std::int64_t track) { return "/v1/tracks/" + std::to_string(track) + "/steps"; }

json fix_at(double t, std::int64_t floor, double x, double y, double accuracy_m = 2.0) {
    return {{"t", t}, {"floor_id", floor}, {"x", x}, {"y", y}, {"accuracy_m", accuracy_m}};
}

json gnss_at(double t, double x, double y, double accuracy_m) {
    const auto [lat, lon] = lat_lon_of(x, y);
    return {{"t", t}, {"lat", lat}, {"lon", lon}, {"accuracy_m", accuracy_m}};
}

// A walk along +x from (5, 5): a radio fix there at t0, then a 0.7 m step each second for 40 s
// (heading 180°, the compass azimuth as a phone reads it on a georeferenced floor: south, the
// floor's +x). With `gnss`, a receiver fix every 2 s
// at half seconds, 30 m off to +y beside where the walker is, claiming 5 m (σ 10 m for the
// filter): one every 10 s is taken, at t0 + 1.5, 11.5, 21.5 and 31.5.
constexpr int kSteps = 40;
constexpr int kGnssTaken = 4;
json walk(std::int64_t floor, double t0, bool gnss) {
    json steps = json::array(), fixes = json::array({fix_at(t0, floor, 5.0, 5.0)}), g = json::array();
    for (int i = 1; i <= kSteps; ++i) steps.push_back({{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", 180.0}});
    for (int k = 0; k < 20; ++k) {
        const double dt = 1.5 + 2 * k;
        g.push_back(gnss_at(t0 + dt, 5.0 + 0.7 * dt, 35.0, 5.0));
    }
    json body = {{"steps", steps}, {"fixes", fixes}};
    if (gnss) body["gnss"] = g;
    return body;
}

// How many of the fused fixes fall at half seconds (the GNSS fixes'; steps and the radio fix are
// on whole seconds).
int at_half_seconds(const json& fused, double t0) {
    int n = 0;
    for (const json& f : fused) {
        const double dt = f["t"].get<double>() - t0;
        if (std::abs(dt - std::floor(dt) - 0.5) < 1e-6) ++n;
    }
    return n;
}

struct Venue {
    locus::testing::Hierarchy h;
    std::string floor_path;
};

Venue georeferenced(const ServerProcess& s) {
    Venue v{locus::testing::make_hierarchy(s), ""};
    v.floor_path = "/v1/floors/" + std::to_string(v.h.floor);
    EXPECT_EQ(s.patch(v.floor_path, {{"geo", floor_geo()}}).status, 200);
    return v;
}

TEST(ServerTracksGnss, GnssPullsAWalkTowardsItOneFixPerTenSeconds) {
    ServerProcess s({"--quiet"});
    const Venue v = georeferenced(s);
    const double t0 = std::floor(unix_now()) - 100;
    const Track plain = open_track(s, {{"map_id", v.h.map}, {"fusion", "walk_pf"}}),
                pulled = open_track(s, {{"map_id", v.h.map}, {"fusion", "walk_pf"}});
    const json without = body_of(track_call(s, "POST", steps_path(plain.id), {plain.token}, walk(v.h.floor, t0, false).dump()));
    const json with = body_of(track_call(s, "POST", steps_path(pulled.id), {pulled.token}, walk(v.h.floor, t0, true).dump()));
    // A fused fix per step and radio fix, and one per GNSS fix taken: 20 sent, 4 taken.
    ASSERT_EQ(without["fused"].size(), static_cast<std::size_t>(kSteps + 1)) << without.dump();
    ASSERT_EQ(with["fused"].size(), static_cast<std::size_t>(kSteps + 1 + kGnssTaken)) << with.dump();
    EXPECT_EQ(at_half_seconds(without["fused"], t0), 0);
    EXPECT_EQ(at_half_seconds(with["fused"], t0), kGnssTaken);
    const json& a = without["fused"].back();
    const json& b = with["fused"].back();
    // Steps alone keep the walker near y = 5; the receiver, 30 m off at y = 35, pulls it that way,
    // at most onto its line: the rotation known from the georeference, the particles re-drawn
    // round a fix walk on as the cloud does, and the next fix keeps them (as in `locus eval
    // ipin`'s walk_pf); the steps after the last fix spread them by a metre or two.
    EXPECT_LT(std::abs(a["y"].get<double>() - 5.0), 2.0) << a.dump();
    EXPECT_GT(b["y"].get<double>() - a["y"].get<double>(), 5.0) << "without " << a.dump() << ", with " << b.dump();
    EXPECT_LT(b["y"].get<double>(), 37.0);
    // The same batch again is a retry: nothing moves, nothing more is stored.
    const json again = body_of(track_call(s, "POST", steps_path(pulled.id), {pulled.token}, walk(v.h.floor, t0, true).dump()));
    EXPECT_EQ(again["fused"].size(), 0u) << again.dump();
    EXPECT_EQ(again["stored"], 0);
    EXPECT_EQ(again["latest"], b);
}

TEST(ServerTracksGnss, GnssAtOrBeforeWhatTheFilterRanIsSkipped) {
    ServerProcess s({"--quiet"});
    const Venue v = georeferenced(s);
    const double t0 = std::floor(unix_now()) - 100;
    const Track t = open_track(s, {{"map_id", v.h.map}, {"fusion", "walk_pf"}});
    const json walked = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, walk(v.h.floor, t0, false).dump()));
    // The receiver's fixes of that walk, arriving late: the filter has run past them, and a late
    // fix must not move it back in time.
    const json late = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, json{{"gnss", walk(v.h.floor, t0, true)["gnss"]}}.dump()));
    EXPECT_EQ(late["fused"].size(), 0u) << late.dump();
    EXPECT_EQ(late["latest"], walked["fused"].back());
}

TEST(ServerTracksGnss, GnssInAnyOrderIsTakenInTimeOrder) {
    ServerProcess s({"--quiet"});
    const Venue v = georeferenced(s);
    const double t0 = std::floor(unix_now()) - 100;
    const Track t = open_track(s, {{"map_id", v.h.map}, {"fusion", "walk_pf"}});
    json body = walk(v.h.floor, t0, true);
    std::reverse(body["gnss"].begin(), body["gnss"].end());  // as the other lists: sorted, not refused
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, body.dump()));
    EXPECT_EQ(at_half_seconds(got["fused"], t0), kGnssTaken) << got.dump();
}

TEST(ServerTracksGnss, AFloorWithoutAGeoreferenceIgnoresGnss) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);  // no geo
    const double t0 = std::floor(unix_now()) - 100;
    const Track t = open_track(s, {{"map_id", h.map}, {"fusion", "walk_pf"}});
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, walk(h.floor, t0, true).dump()));
    ASSERT_EQ(got["fused"].size(), static_cast<std::size_t>(kSteps + 1)) << got.dump();
    EXPECT_EQ(at_half_seconds(got["fused"], t0), 0);
    EXPECT_LT(std::abs(got["fused"].back()["y"].get<double>() - 5.0), 2.0) << got["fused"].back().dump();
}

TEST(ServerTracksGnss, GnssAloneBeginsNoTrack) {
    ServerProcess s({"--quiet"});
    const Venue v = georeferenced(s);
    const double t0 = std::floor(unix_now()) - 100;
    const Track t = open_track(s, {{"map_id", v.h.map}, {"fusion", "walk_pf"}});
    const json alone = body_of(track_call(s, "POST", steps_path(t.id), {t.token},
                                          json{{"gnss", {gnss_at(t0, 5.0, 5.0, 3.0), gnss_at(t0 + 20, 6.0, 5.0, 3.0)}}}.dump()));
    EXPECT_EQ(alone["fused"].size(), 0u) << alone.dump();
    EXPECT_EQ(alone["stored"], 0);
    // Still no filter: steps after it have nothing to start from.
    const Response steps = track_call(s, "POST", steps_path(t.id), {t.token},
                                      json{{"steps", {{{"t", t0 + 21}, {"length_m", 0.7}, {"heading_deg", 90.0}}}}}.dump());
    EXPECT_EQ(steps.status, 422) << steps.raw;
    EXPECT_EQ(steps.body["error"]["code"], "cannot_fuse");
}

TEST(ServerTracksGnss, AKalmanTrackDropsAFixBeyondItsGate) {
    ServerProcess s({"--quiet"});
    const Venue v = georeferenced(s);
    const double t0 = std::floor(unix_now()) - 100;
    const Track t = open_track(s, {{"map_id", v.h.map}, {"fusion", "kalman_trilateration"}});
    // Standing at (5, 5), sure of it to a few metres: a receiver fix 40 m off is 4 σ (σ 10 m) and
    // more, beyond the 99 % gate (χ² 9.21); one 4 m off, 10 s later, is taken.
    json body = {{"fixes", {fix_at(t0, v.h.floor, 5.0, 5.0)}},
                 {"gnss", {gnss_at(t0 + 2.5, 5.0, 45.0, 3.0), gnss_at(t0 + 12.5, 5.0, 9.0, 3.0)}}};
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, body.dump()));
    ASSERT_EQ(got["fused"].size(), 2u) << got.dump();
    EXPECT_DOUBLE_EQ(got["fused"][1]["t"].get<double>(), t0 + 12.5);
    const double y = got["fused"][1]["y"].get<double>();
    EXPECT_GT(y, 5.05);  // moved towards y = 9, not to y = 45
    EXPECT_LT(y, 9.0);
}

TEST(ServerTracksGnss, BadGnssIsRefusedAndWritesNothing) {
    ServerProcess s({"--quiet", "--track-retention", "3600"});
    const Venue v = georeferenced(s);
    const Track t = open_track(s, {{"map_id", v.h.map}, {"fusion", "walk_pf"}});
    const double t0 = std::floor(unix_now()) - 100;
    const json fix = fix_at(t0, v.h.floor, 5.0, 5.0);
    const std::string ok = gnss_at(t0 + 1, 5.0, 5.0, 5.0).dump();
    const auto refused = [&](const std::string& gnss, int status, const std::string& code, const std::string& names = "") {
        const std::string body = R"({"fixes": [)" + fix.dump() + R"(], "gnss": )" + gnss + "}";
        const Response r = track_call(s, "POST", steps_path(t.id), {t.token}, body);
        EXPECT_EQ(r.status, status) << gnss << ": " << r.raw;
        EXPECT_EQ(r.body["error"]["code"], code) << gnss;
        const std::string message = r.body["error"]["message"].get<std::string>();
        EXPECT_FALSE(message.empty()) << gnss;
        if (!names.empty()) {
            EXPECT_NE(message.find(names), std::string::npos) << message;
        }
    };
    const std::string tt = std::to_string(t0 + 2);
    const std::string three = "[" + ok + ", " + ok + ", " + ok + ", ";  // gnss[3] is the bad one
    refused(ok, 422, "invalid_field");                                                              // not an array
    refused("[5]", 422, "invalid_field", "gnss[0]");                                                // not an object
    refused(three + R"({"t": )" + tt + R"(, "lon": 7, "accuracy_m": 5}])", 422, "invalid_field", "gnss[3].lat");  // no lat
    refused(three + R"({"lat": 45, "lon": 7, "accuracy_m": 5}])", 422, "invalid_field", "gnss[3].t");             // no t
    refused(three + R"({"t": )" + tt + R"(, "lat": 91, "lon": 7, "accuracy_m": 5}])", 422, "out_of_range", "gnss[3].lat");
    refused(three + R"({"t": )" + tt + R"(, "lat": -90.5, "lon": 7, "accuracy_m": 5}])", 422, "out_of_range", "gnss[3].lat");
    refused(three + R"({"t": )" + tt + R"(, "lat": 45, "lon": 180.5, "accuracy_m": 5}])", 422, "out_of_range", "gnss[3].lon");
    refused(three + R"({"t": )" + tt + R"(, "lat": 45, "lon": 7, "accuracy_m": 0}])", 422, "out_of_range", "gnss[3].accuracy_m");
    refused(three + R"({"t": )" + tt + R"(, "lat": 45, "lon": 7, "accuracy_m": -1}])", 422, "out_of_range", "gnss[3].accuracy_m");
    refused(three + R"({"t": )" + tt + R"(, "lat": 45, "lon": 7, "accuracy_m": 1e5}])", 422, "out_of_range", "gnss[3].accuracy_m");
    refused(three + R"({"t": )" + tt + R"(, "lat": 45, "lon": 7}])", 422, "invalid_field", "gnss[3].accuracy_m");
    refused(three + R"({"t": )" + tt + R"(, "lat": "45", "lon": 7, "accuracy_m": 5}])", 422, "invalid_field", "gnss[3].lat");
    refused(three + R"({"t": )" + tt + R"(, "lat": null, "lon": 7, "accuracy_m": 5}])", 422, "invalid_field", "gnss[3].lat");
    refused(three + R"({"t": )" + tt + R"(, "lat": 45, "lon": 7, "accuracy_m": 5, "alt": 3}])", 422, "invalid_field", "gnss[3]");
    refused(R"([{"t": )" + tt + R"(, "lat": NaN, "lon": 7, "accuracy_m": 5}])", 400, "invalid_json");
    refused(R"([{"t": 1e300, "lat": 45, "lon": 7, "accuracy_m": 5}])", 422, "invalid_field", "gnss[0].t");  // far in the future
    // Older than the track keeps fixes (--track-retention 3600 s): a clock gone back.
    refused(R"([{"t": )" + std::to_string(t0 - 7200) + R"(, "lat": 45, "lon": 7, "accuracy_m": 5}])", 422, "invalid_field", "gnss[0].t");
    json many = json::array();
    for (int i = 0; i < 1001; ++i) many.push_back(gnss_at(t0 + 1 + i * 0.05, 5.0, 5.0, 5.0));
    refused(many.dump(), 413, "batch_too_large");
    EXPECT_EQ(body_of(track_call(s, "GET", "/v1/tracks/" + std::to_string(t.id), {t.token}))["fixes"], 0);
    // 1,000 is the most: taken (its first fix starts the track, the rest fused or thinned).
    many.erase(many.end() - 1);
    const std::string body = R"({"fixes": [)" + fix.dump() + R"(], "gnss": )" + many.dump() + "}";
    EXPECT_EQ(track_call(s, "POST", steps_path(t.id), {t.token}, body).status, 200);
}

}  // namespace
}  // namespace server_tracks_gnss_test
