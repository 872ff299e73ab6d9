// walk_pf's own fusion_options on POST /v1/tracks (server/tracks/fusion_options.hpp; docs/tracks.md):
// the step scale's prior, a fix's σ and the re-drawn share, against the real server. A track
// opened with them keeps and answers them; its filter walks by them (ten 0.7 m steps after one
// fix carry it twice as far at twice the scale); an option of another method, or out of range,
// is refused by name and opens nothing. On a georeferenced floor the headings are compass
// azimuths, turned by the floor's bearing.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_tracks_walk_options_test {
namespace {

using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::track_call;
using locus::testing::unix_now;
using nlohmann::json;

// The walker's fixes pin the compass's rotation: a fix at (2, 10), ten 0.5 m steps east, a fix
// at (7, 10) where they took it, ten more steps east, a fix at (12, 10); then ten more steps
// east with no fix, which end well inside the 30 m floor even at twice the scale. Answers how
// far the track's estimate moved over those last ten steps.
double walked(const ServerProcess& s, const Track& t, std::int64_t floor) {
    const double t0 = std::floor(unix_now()) - 60;
    json steps = json::array(), fixes = json::array();
    for (int leg = 0; leg < 3; ++leg) {
        const double start = t0 + 6.0 * leg;
        fixes.push_back({{"t", start}, {"floor_id", floor}, {"x", 2.0 + 5.0 * leg}, {"y", 10.0}, {"accuracy_m", 1.0}});
        for (int i = 1; i <= 10; ++i) steps.push_back({{"t", start + 0.5 * i}, {"length_m", 0.5}, {"heading_deg", 90.0}});
    }
    const json body = {{"fixes", fixes}, {"steps", steps}};
    const json got = body_of(track_call(s, "POST", "/v1/tracks/" + std::to_string(t.id) + "/steps", {t.token}, body.dump()));
    const json& fused = got["fused"];
    // The fused fixes: one per fix and per step, in time order; the last leg's are the last 11.
    const json& before = fused[fused.size() - 11];
    const json& last = fused.back();
    return std::hypot(last["x"].get<double>() - before["x"].get<double>(), last["y"].get<double>() - before["y"].get<double>());
}

TEST(ServerTracksWalkOptions, AWalkPfTrackWalksByItsOwnStepScale) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const json options = {{"step_scale", 1.0}, {"step_scale_sigma", 0.02}, {"fix_sigma_m", 5.0}, {"reseed_fraction", 0.02},
                          {"reseed_max_fraction", 0.1}};
    const Track own = open_track(s, {{"map_id", h.map}, {"fusion", "walk_pf"}, {"fusion_options", options}});
    const json info = body_of(track_call(s, "GET", "/v1/tracks/" + std::to_string(own.id), {own.token}));
    EXPECT_EQ(info["fusion"], "walk_pf");
    EXPECT_EQ(info["fusion_options"], options);
    // The last ten steps carry the track about scale × 5 m (the fixes before pull the cloud a
    // little).
    json twice = options;
    twice["step_scale"] = 2.0;
    const Track far = open_track(s, {{"map_id", h.map}, {"fusion", "walk_pf"}, {"fusion_options", twice}});
    const double near_m = walked(s, own, h.floor), far_m = walked(s, far, h.floor);
    EXPECT_NEAR(near_m, 5.0, 1.5);
    EXPECT_NEAR(far_m / near_m, 2.0, 0.4) << near_m << " " << far_m;
}

// One fix at (10, 10), σ 0.5 m, then ten 0.7 m steps at heading 90°: the last fused fix.
json ten_steps_at_90(const ServerProcess& s, const Track& t, std::int64_t floor) {
    const double t0 = std::floor(unix_now()) - 60;
    json steps = json::array();
    for (int i = 1; i <= 10; ++i) steps.push_back({{"t", t0 + 0.5 * i}, {"length_m", 0.7}, {"heading_deg", 90.0}});
    const json body = {{"fixes", json::array({{{"t", t0}, {"floor_id", floor}, {"x", 10.0}, {"y", 10.0}, {"accuracy_m", 0.5}}})},
                       {"steps", steps}};
    return body_of(track_call(s, "POST", "/v1/tracks/" + std::to_string(t.id) + "/steps", {t.token}, body.dump()))["fused"].back();
}

// Headings already the floor's (rotation_sigma_deg): after one fix at (10, 10) and ten 0.7 m
// steps east the track is where they lead, (17, 10); without it the filter knows no rotation
// from one fix (measured at (12.5, 13.8) without it).
TEST(ServerTracksWalkOptions, AKnownRotationWalksWhereTheHeadingsLead) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const json options = {{"step_scale", 1.0}, {"step_scale_sigma", 0.02}, {"rotation_sigma_deg", 3.0}, {"rotation_walk_deg", 1.0}};
    const Track t = open_track(s, {{"map_id", h.map}, {"fusion_options", options}});
    const json last = ten_steps_at_90(s, t, h.floor);
    EXPECT_NEAR(last["x"].get<double>(), 17.0, 1.0) << last.dump();
    EXPECT_NEAR(last["y"].get<double>(), 10.0, 1.0) << last.dump();
}

// Without options, on a floor with a georeference the steps' headings are compass azimuths: the
// floor's +y axis points east here (bearing 90°), so ten 0.7 m steps at azimuth 90° from a fix at
// (10, 10) lead along +y, to (10, 17), not along +x as the floor's own headings would. The
// known rotation needs no options; the step scale's is set so that the ten steps are 7 m.
TEST(ServerTracksWalkOptions, OnAGeoreferencedFloorTheHeadingsAreCompassAzimuths) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const json geo = {{"lat", 45.0}, {"lon", 7.0}, {"x", 0.0}, {"y", 0.0}, {"bearing_deg", 90.0}};
    ASSERT_EQ(s.patch("/v1/floors/" + std::to_string(h.floor), {{"geo", geo}}).status, 200);
    const Track t = open_track(s, {{"map_id", h.map}, {"fusion_options", {{"step_scale", 1.0}, {"step_scale_sigma", 0.02}}}});
    const json last = ten_steps_at_90(s, t, h.floor);
    EXPECT_NEAR(last["x"].get<double>(), 10.0, 1.0) << last.dump();
    EXPECT_NEAR(last["y"].get<double>(), 17.0, 1.0) << last.dump();
}

TEST(ServerTracksWalkOptions, OptionsOfAnotherMethodOrOutOfRangeAreRefused) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::vector<std::pair<json, std::string>> bad = {
        {{{"fusion", "walk_pf"}, {"fusion_options", {{"step_scale", 0.0}}}}, "fusion_options.step_scale"},
        {{{"fusion_options", {{"step_scale", 9.0}}}}, "fusion_options.step_scale"},  // the default method, walk_pf
        {{{"fusion", "walk_pf"}, {"fusion_options", {{"fix_sigma_m", "5"}}}}, "fusion_options.fix_sigma_m"},
        {{{"fusion", "walk_pf"}, {"fusion_options", {{"reseed_fraction", 1.5}}}}, "fusion_options.reseed_fraction"},
        {{{"fusion", "walk_pf"}, {"fusion_options", {{"r_sigma_m", 1.0}}}}, "fusion_options.r_sigma_m"},
        {{{"fusion", "walk_pf"}, {"fusion_options", {{"rotation_sigma_deg", 0.0}}}}, "fusion_options.rotation_sigma_deg"},
        {{{"fusion", "walk_pf"}, {"fusion_options", {{"rotation_walk_deg", 45.0}}}}, "fusion_options.rotation_walk_deg"},
        {{{"fusion", "kalman_trilateration"}, {"fusion_options", {{"step_scale", 1.0}}}}, "fusion_options.step_scale"},
        {{{"fusion", "particle"}, {"fusion_options", {{"step_scale", 1.0}}}}, "particle takes none"},
        {{{"fusion_options", {{"subarea", "no"}}}}, "fusion_options.subarea"},
        {{{"fusion_options", {{"subarea", 0}}}}, "fusion_options.subarea"},
        {{{"fusion", "kalman_ranging"}, {"fusion_options", {{"subarea", false}}}}, "fusion_options.subarea"},
    };
    for (const auto& [fields, name] : bad) {
        json req = fields;
        req["map_id"] = h.map;
        const Response r = track_call(s, "POST", "/v1/tracks", {}, req.dump());
        EXPECT_EQ(r.status, 422) << req.dump();
        EXPECT_NE(r.body["error"]["message"].get<std::string>().find(name), std::string::npos) << r.raw;
    }
    // Nothing was opened: the first track is number 1.
    EXPECT_EQ(body_of(track_call(s, "POST", "/v1/tracks", {}, json{{"map_id", h.map}}.dump()), 201)["id"], 1);
}

}  // namespace
}  // namespace server_tracks_walk_options_test
