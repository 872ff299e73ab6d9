// Floors from the barometer on a thin client's track (docs/tracks.md, "Floors from the
// barometer"), against the real server: pressure samples on POST /v1/tracks/{id}/steps take the
// track down a stair to a floor no radio map covers, through the plan's stairs where it has
// them; a radio fix on a floor the barometer rules out moves nothing; a building without
// elevations ignores pressure; and bad pressure is refused with nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hierarchy.hpp"
#include "plan_geojson.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_tracks_baro_test {
namespace {

using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::track_call;
using locus::testing::unix_now;
using nlohmann::json;

// Near sea level air pressure falls by about 0.12 hPa per metre of height (the hypsometric
// equation at 15 °C: p/8434 m): the walk below goes 4.5 m down, 0.54 hPa up.
constexpr double kHpaPerMetre = 1000.0 / 8434.0;
constexpr double kP0 = 1000.0;

struct Building {
    locus::testing::Hierarchy h;
    std::int64_t mezzanine = 0, basement = 0;
};

std::int64_t created(const Response& r) { return body_of(r, 201).at("id").get<std::int64_t>(); }

// Ground (level 0, a radio map), a mezzanine 4.5 m below (level -1, no radio map) and a
// basement 9 m below (level -2, a radio map); with `elevations`, each floor's elevation_m.
Building three_floors(const ServerProcess& s, bool elevations) {
    Building b;
    b.h = locus::testing::make_hierarchy(s);
    const std::string floors = "/v1/buildings/" + std::to_string(b.h.building) + "/floors";
    json mezz = {{"name", "Mezzanine"}, {"level", -1}, {"width", 30.0}, {"height", 20.0}};
    json base = {{"name", "Basement"}, {"level", -2}, {"width", 30.0}, {"height", 20.0}};
    if (elevations) {
        mezz["elevation_m"] = -4.5;
        base["elevation_m"] = -9.0;
        EXPECT_EQ(s.patch("/v1/floors/" + std::to_string(b.h.floor), {{"elevation_m", 0.0}}).status, 200);
    }
    b.mezzanine = created(s.post(floors, mezz));
    b.basement = created(s.post(floors, base));
    (void)created(s.post("/v1/floors/" + std::to_string(b.basement) + "/radiomaps", {{"name", "survey"}}));
    return b;
}

std::string steps_path(std::int64_t track) { return "/v1/tracks/" + std::to_string(track) + "/steps"; }

// A walk east on the ground floor: radio fixes there every 5 s for 20 s, steps every 0.6 s
// until `walk_s`, and the barometer at 5 Hz, steady for 20 s, then 4.5 m down over 10 s (a
// stair, or a lift when the steps have stopped), then steady again (±0.01 hPa of noise).
json walk_down_a_stair(const Building& b, double t0, double walk_s = 40.0) {
    json steps = json::array(), fixes = json::array(), pressure = json::array();
    for (int i = 0; i <= 20; i += 5) fixes.push_back({{"t", t0 + i}, {"floor_id", b.h.floor}, {"x", 5.0 + 1.0 * i}, {"y", 5.0}, {"accuracy_m", 2.0}});
    for (int i = 1; i * 0.6 <= walk_s; ++i) steps.push_back({{"t", t0 + i * 0.6}, {"length_m", 0.6}, {"heading_deg", 90.0}});
    for (int i = 0; i <= 200; ++i) {
        const double s = i * 0.2;
        const double down_m = s < 20 ? 0.0 : (s < 30 ? 4.5 * (s - 20) / 10 : 4.5);
        pressure.push_back({{"t", t0 + s}, {"hpa", kP0 + down_m * kHpaPerMetre + (i % 2 ? 0.01 : -0.01)}});
    }
    return {{"steps", steps}, {"fixes", fixes}, {"pressure", pressure}};
}

TEST(ServerTracksBaro, PressureTakesTheTrackDownAStairToAFloorNoRadioMapCovers) {
    ServerProcess s({"--quiet"});
    const Building b = three_floors(s, true);
    const Track t = open_track(s, {{"map_id", b.h.map}});
    const double t0 = std::floor(unix_now()) - 100;
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, walk_down_a_stair(b, t0).dump()));
    const json& fused = got["fused"];
    ASSERT_FALSE(fused.empty());
    // Before the stair every fix is on the ground floor; once down, on the mezzanine, which no
    // radio fix ever named.
    std::size_t first_down = fused.size();
    for (std::size_t i = 0; i < fused.size(); ++i) {
        const double at = fused[i]["t"].get<double>() - t0;
        if (at < 20.0) {
            EXPECT_EQ(fused[i]["floor_id"], b.h.floor) << "t0+" << at;
        }
        if (at > 32.0) {
            EXPECT_EQ(fused[i]["floor_id"], b.mezzanine) << "t0+" << at;
        }
        if (fused[i]["floor_id"] == b.mezzanine && first_down == fused.size()) first_down = i;
    }
    ASSERT_LT(first_down, fused.size());
    ASSERT_GT(first_down, 0u);
    const double changed_at = fused[first_down]["t"].get<double>() - t0;
    EXPECT_GT(changed_at, 21.0);  // at least 0.5 m down (the estimator's hysteresis) and its median's lag
    EXPECT_LT(changed_at, 32.0);
    // The change is a fix of its own, where the walker was: x and y carry over.
    const json& before = fused[first_down - 1];
    EXPECT_NEAR(fused[first_down]["x"].get<double>(), before["x"].get<double>(), 1.0);
    EXPECT_NEAR(fused[first_down]["y"].get<double>(), before["y"].get<double>(), 1.0);
    const json latest = body_of(track_call(s, "GET", "/v1/tracks/" + std::to_string(t.id), {t.token}))["latest"];
    EXPECT_EQ(latest["floor_id"], b.mezzanine);
}

TEST(ServerTracksBaro, ARadioFixOnAFloorTheBarometerRulesOutMovesNothing) {
    ServerProcess s({"--quiet"});
    const Building b = three_floors(s, true);
    const Track t = open_track(s, {{"map_id", b.h.map}});
    const double t0 = std::floor(unix_now()) - 100;
    const json walked = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, walk_down_a_stair(b, t0).dump()));
    const json last = walked["fused"].back();
    ASSERT_EQ(last["floor_id"], b.mezzanine);
    // The basement's radio map answers once, 15 m away: one vote against the ground-floor fixes
    // and the pressure; the track stays where it was, on the mezzanine.
    const json wrong = {{"fixes", {{{"t", t0 + 41}, {"floor_id", b.basement}, {"x", 25.0}, {"y", 17.0}, {"accuracy_m", 2.0}}}},
                        {"pressure", {{{"t", t0 + 41}, {"hpa", kP0 + 4.5 * kHpaPerMetre}}}}};
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, wrong.dump()));
    ASSERT_EQ(got["fused"].size(), 1u) << got.dump();
    EXPECT_EQ(got["fused"][0]["floor_id"], b.mezzanine);
    EXPECT_NEAR(got["fused"][0]["x"].get<double>(), last["x"].get<double>(), 1e-9);
    EXPECT_NEAR(got["fused"][0]["y"].get<double>(), last["y"].get<double>(), 1e-9);
}

TEST(ServerTracksBaro, WithoutElevationsPressureChangesNoFloor) {
    ServerProcess s({"--quiet"});
    const Building b = three_floors(s, false);
    const Track t = open_track(s, {{"map_id", b.h.map}});
    const double t0 = std::floor(unix_now()) - 100;
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, walk_down_a_stair(b, t0).dump()));
    ASSERT_FALSE(got["fused"].empty());
    for (const json& f : got["fused"]) EXPECT_EQ(f["floor_id"], b.h.floor) << f.dump();
    // Pressure alone is a batch too: nothing to fuse without a floor change, nothing stored.
    const json alone = body_of(track_call(s, "POST", steps_path(t.id), {t.token},
                                          json{{"pressure", {{{"t", t0 + 41}, {"hpa", kP0}}}}}.dump()));
    EXPECT_EQ(alone["fused"].size(), 0u);
    EXPECT_EQ(alone["stored"], 0);
}

TEST(ServerTracksBaro, BadPressureIsRefusedAndWritesNothing) {
    ServerProcess s({"--quiet"});
    const Building b = three_floors(s, true);
    const Track t = open_track(s, {{"map_id", b.h.map}});
    const double t0 = std::floor(unix_now()) - 100;
    const json fix = {{"t", t0}, {"floor_id", b.h.floor}, {"x", 5.0}, {"y", 5.0}, {"accuracy_m", 2.0}};
    const auto refused = [&](const std::string& pressure, int status, const std::string& code) {
        const std::string body = R"({"fixes": [)" + fix.dump() + R"(], "pressure": )" + pressure + "}";
        const Response r = track_call(s, "POST", steps_path(t.id), {t.token}, body);
        EXPECT_EQ(r.status, status) << pressure << ": " << r.raw;
        EXPECT_EQ(r.body["error"]["code"], code) << pressure;
        EXPECT_FALSE(r.body["error"]["message"].get<std::string>().empty()) << pressure;
    };
    const std::string t_ok = std::to_string(t0 + 1);
    refused(R"({"t": 1, "hpa": 1000})", 422, "invalid_field");                          // not an array
    refused("[1000]", 422, "invalid_field");                                            // not an object
    refused(R"([{"t": )" + t_ok + "}]", 422, "invalid_field");                          // no hpa
    refused(R"([{"hpa": 1000}])", 422, "invalid_field");                                // no t
    refused(R"([{"t": )" + t_ok + R"(, "hpa": "1000"}])", 422, "invalid_field");        // a string
    refused(R"([{"t": )" + t_ok + R"(, "hpa": 299.9}])", 422, "out_of_range");          // below any building
    refused(R"([{"t": )" + t_ok + R"(, "hpa": 1200.1}])", 422, "out_of_range");         // above any weather
    refused(R"([{"t": )" + t_ok + R"(, "hpa": 1000, "alt": 3}])", 422, "invalid_field"); // an unknown field
    refused(R"([{"t": 1e300, "hpa": 1000}])", 422, "invalid_field");                    // far in the future
    refused(R"([{"t": )" + t_ok + R"(, "hpa": NaN}])", 400, "invalid_json");
    json many = json::array();
    for (int i = 0; i < 5001; ++i) many.push_back({{"t", t0 + 1 + i * 0.01}, {"hpa", kP0}});
    refused(many.dump(), 413, "batch_too_large");
    EXPECT_EQ(body_of(track_call(s, "GET", "/v1/tracks/" + std::to_string(t.id), {t.token}))["fixes"], 0);
}

// A 30 m x 4 m corridor with a lift at x = `lift_x` linked to the other floor's ("lift").
static json corridor_with_lift(std::int64_t other_floor, double lift_x) {
    using locus::testing::feature;
    return {{"type", "FeatureCollection"},
            {"features",
             {feature("space", locus::testing::rect_polygon(0, 0, 30, 4), {{"name", "Corridor"}, {"kind", "corridor"}}),
              feature("connector", locus::testing::point(lift_x, 2),
                      {{"id", "lift"}, {"kind", "elevator"}, {"links", {{{"floor_id", other_floor}, {"connector", "lift"}}}}})}}};
}

TEST(ServerTracksBaro, WhereThePlanHasALiftTheTrackComesOutAtItsOtherEnd) {
    ServerProcess s({"--quiet"});
    const Building b = three_floors(s, true);
    // The ground floor's lift stands near its east end (x 26), the mezzanine's near its west end
    // (x 6, so that the walker, who may stand a few metres west of the lift, comes out clear of
    // the wall at x 0); the walker walks to x ≈ 25 and rides down.
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(b.h.floor) + "/plan", corridor_with_lift(b.mezzanine, 26)).status, 200);
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(b.mezzanine) + "/plan", corridor_with_lift(b.h.floor, 6)).status, 200);
    const Track t = open_track(s, {{"map_id", b.h.map}});
    const double t0 = std::floor(unix_now()) - 100;
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, walk_down_a_stair(b, t0, 20.0).dump()));
    const json& fused = got["fused"];
    std::size_t first_down = 0;
    while (first_down < fused.size() && fused[first_down]["floor_id"] != b.mezzanine) ++first_down;
    ASSERT_LT(first_down, fused.size());
    ASSERT_GT(first_down, 0u);
    // Standing dx from the ground floor's lift, the walker comes out dx from the mezzanine's.
    const json& before = fused[first_down - 1];
    EXPECT_GT(before["x"].get<double>(), 20.0);
    EXPECT_NEAR(fused[first_down]["x"].get<double>(), 6.0 + (before["x"].get<double>() - 26.0), 1.0);
    EXPECT_NEAR(fused[first_down]["y"].get<double>(), before["y"].get<double>(), 1.0);
    EXPECT_LT(fused[first_down]["x"].get<double>(), 10.0);  // the west end, not where the walker stood
    EXPECT_EQ(fused.back()["floor_id"], b.mezzanine);
}

}  // namespace
}  // namespace server_tracks_baro_test
