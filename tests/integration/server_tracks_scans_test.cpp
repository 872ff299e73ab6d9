// A walk_pf track's scans against the real server: the phone's RSS offset learnt online
// (docs/tracks.md, "GNSS and the phone's offset") and the map's BLE beacons as fixes
// (docs/tracks.md, "Beacons").
//
// The offset: a radio map surveyed with one phone, a track whose phone
// reads every AP 8 dB weaker. The track learns the offset from its own scans (`rss_offset_db`
// in the /steps answer approaches +8 dB as the estimator's prior lets it), a phone that reads as
// the survey's learns about 0, a retried or refused batch teaches nothing, and a track of another
// method has no offset. (The radio map's default matcher, bayes, also fits a per-scan offset of
// its own, docs/matchers.md, so on this clean map the offset moves the answers little: the test
// reads the offset itself.)
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_tracks_scans_test {
namespace {

using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::track_call;
using locus::testing::unix_now;
using nlohmann::json;

constexpr double kPhoneOffsetDb = -8.0;  // the track's phone reads this much below the survey's

struct Ap {
    const char* bssid;
    double x, y;
};
// Six APs round the 30 m × 20 m floor.
const std::vector<Ap> kAps = {{"02:00:00:00:00:01", 0, 0},  {"02:00:00:00:00:02", 30, 0},  {"02:00:00:00:00:03", 0, 20},
                              {"02:00:00:00:00:04", 30, 20}, {"02:00:00:00:00:05", 15, 0}, {"02:00:00:00:00:06", 15, 20}};

// Log-distance path loss: −35 dBm at 1 m, falling 25 dB a decade.
double rss_at(const Ap& ap, double x, double y) { return -35.0 - 25.0 * std::log10(std::max(1.0, std::hypot(x - ap.x, y - ap.y))); }

// A scan at (x, y) as a phone reading `offset_db` off the survey's reads it, with a small
// deterministic wobble per AP (±0.5 dB).
json readings_at(double x, double y, double offset_db, int wobble) {
    json out = json::array();
    for (std::size_t a = 0; a < kAps.size(); ++a) {
        const double w = ((static_cast<int>(a) + wobble) % 3 - 1) * 0.5;
        out.push_back({{"type", "wifi"}, {"bssid", kAps[a].bssid}, {"rss", rss_at(kAps[a], x, y) + offset_db + w}});
    }
    return out;
}

// The survey: an RP every 5 m (7 × 5), five scans each.
void survey(const ServerProcess& s, const locus::testing::Hierarchy& h) {
    for (int i = 0; i <= 6; ++i) {
        for (int j = 0; j <= 4; ++j) {
            const double x = 5.0 * i, y = 5.0 * j;
            const std::string name = std::to_string(i) + "_" + std::to_string(j);
            const std::int64_t rp = locus::testing::make_rp(s, h.radiomap, name, x, y);
            json scans = json::array();
            for (int k = 0; k < 5; ++k) scans.push_back(readings_at(x, y, 0.0, k));
            // The upload's id appended, not prepended: GCC 12's -Wrestrict misfires on "u" + std::string.
            std::string upload = std::to_string(rp);
            upload += "-survey";
            ASSERT_EQ(s.post("/v1/rps/" + std::to_string(rp) + "/scans", {{"upload_id", upload}, {"scans", scans}}).status, 200);
        }
    }
}

// Where the track's phone scans: the RPs round the floor's edge, one scan a second. An AP 8 dB
// weaker there reads as one farther off, so the map places the scan inwards.
struct Spot {
    double x, y;
};
std::vector<Spot> loop_spots(int n) {
    std::vector<Spot> ring;
    for (int i = 0; i < 6; ++i) ring.push_back({5.0 * i, 0.0});
    for (int j = 0; j < 4; ++j) ring.push_back({30.0, 5.0 * j});
    for (int i = 6; i > 0; --i) ring.push_back({5.0 * i, 20.0});
    for (int j = 4; j > 0; --j) ring.push_back({0.0, 5.0 * j});
    std::vector<Spot> out;
    for (int i = 0; i < n; ++i) out.push_back(ring[static_cast<std::size_t>(i) % ring.size()]);
    return out;
}

// Scans at `spots`, one a second from t0 + first, by a phone reading `offset_db` off the survey's.
json scans_body(const std::vector<Spot>& spots, double t0, int first, double offset_db = kPhoneOffsetDb) {
    json scans = json::array();
    for (std::size_t i = 0; i < spots.size(); ++i)
        scans.push_back({{"t", t0 + first + static_cast<double>(i)}, {"readings", readings_at(spots[i].x, spots[i].y, offset_db, static_cast<int>(i))}});
    return {{"scans", scans}};
}

// What match::DeviceOffset would hold after n looks of exactly `look_db` each: their mean shrunk
// by its prior of 5 looks of 0 dB (shared/include/locus/match/device_offset.hpp).
double shrunk(double look_db, int n) { return look_db * n / (n + 5.0); }

std::string steps_path(std::int64_t track) { return "/v1/tracks/" + std::to_string(track) + "/steps"; }

TEST(ServerTracksOffset, AWalkPfTrackLearnsItsPhonesOffset) {
    // The walk's scans are posted back to back, faster than a phone's 10 localizations a second.
    ServerProcess s({"--quiet", "--client-rate", "1000", "--client-burst", "1000"});
    const auto h = locus::testing::make_hierarchy(s);
    survey(s, h);
    const Track t = open_track(s, {{"map_id", h.map}});
    const double t0 = std::floor(unix_now()) - 200;
    const std::vector<Spot> spots = loop_spots(72);
    // Three batches of 24 scans: the offset grows towards +8 dB, as far as the prior lets it
    // (6.6, 7.3, 7.5 dB after looks of exactly 8; each look is a median against the answer's RPs,
    // not the spot's own, so within 1 dB of that).
    std::vector<double> learnt;
    for (int b = 0; b < 3; ++b) {
        const std::vector<Spot> part(spots.begin() + 24 * b, spots.begin() + 24 * (b + 1));
        const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, scans_body(part, t0, 24 * b).dump()));
        ASSERT_TRUE(got.contains("rss_offset_db")) << got.dump();
        ASSERT_EQ(got["scan_fixes"].size(), 24u);
        learnt.push_back(got["rss_offset_db"].get<double>());
        EXPECT_NEAR(learnt.back(), shrunk(-kPhoneOffsetDb, 24 * (b + 1)), 1.0) << "after batch " << b;
    }
    EXPECT_GT(learnt[1], learnt[0]);
    EXPECT_GT(learnt[2], learnt[1]);
    EXPECT_LT(learnt[2], 8.5);
    // The last batch again is a retry: its scans are answered, but teach nothing twice.
    const std::vector<Spot> tail(spots.begin() + 48, spots.end());
    const json again = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, scans_body(tail, t0, 48).dump()));
    EXPECT_EQ(again["fused"].size(), 0u);
    EXPECT_EQ(again["scan_fixes"].size(), 24u);
    EXPECT_DOUBLE_EQ(again["rss_offset_db"].get<double>(), learnt[2]);
}

TEST(ServerTracksOffset, APhoneThatReadsAsTheSurveysLearnsNoOffset) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    survey(s, h);
    const Track t = open_track(s, {{"map_id", h.map}});
    const double t0 = std::floor(unix_now()) - 200;
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, scans_body(loop_spots(48), t0, 0, 0.0).dump()));
    EXPECT_NEAR(got["rss_offset_db"].get<double>(), 0.0, 1.0) << got.dump();
}

TEST(ServerTracksOffset, ARefusedBatchTeachesNothing) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    survey(s, h);
    const Track t = open_track(s, {{"map_id", h.map}});
    const std::int64_t id = t.id;
    const std::string token = t.token;
    const double t0 = std::floor(unix_now()) - 200;
    const json first = body_of(track_call(s, "POST", steps_path(id), {token}, scans_body(loop_spots(12), t0, 0).dump()));
    const double learnt = first["rss_offset_db"].get<double>();
    EXPECT_GT(learnt, 1.0);
    // Twelve more good scans and one no RP hears: 422 no_match, and the offset stays as it was.
    json bad = scans_body(loop_spots(12), t0, 12);
    bad["scans"].push_back({{"t", t0 + 30}, {"readings", {{{"bssid", "0a:00:00:00:00:99"}, {"rss", -60}}}}});
    const Response refused = track_call(s, "POST", steps_path(id), {token}, bad.dump());
    EXPECT_EQ(refused.status, 422) << refused.raw;
    EXPECT_EQ(refused.body["error"]["code"], "no_match");
    const json empty = body_of(track_call(s, "POST", steps_path(id), {token},
                                          json{{"steps", {{{"t", t0 + 11.5}, {"length_m", 0.5}, {"heading_deg", 0.0}}}}}.dump()));
    EXPECT_DOUBLE_EQ(empty["rss_offset_db"].get<double>(), learnt);
}

TEST(ServerTracksOffset, AKalmanTrackHasNoOffset) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const json opened = body_of(track_call(s, "POST", "/v1/tracks", {}, json{{"map_id", h.map}, {"fusion", "kalman_trilateration"}}.dump()), 201);
    const double t0 = std::floor(unix_now()) - 100;
    const json fix = {{"t", t0}, {"floor_id", h.floor}, {"x", 5.0}, {"y", 5.0}, {"accuracy_m", 2.0}};
    const json got = body_of(track_call(s, "POST", steps_path(opened.at("id").get<std::int64_t>()), {opened.at("token").get<std::string>()},
                                        json{{"fixes", {fix}}}.dump()));
    EXPECT_FALSE(got.contains("rss_offset_db")) << got.dump();
}

// The map's beacon: a BLE transmitter placed at the floor's far corner.
constexpr const char* kBeacon = "0b:00:00:00:00:01";
constexpr double kBeaconX = 28.0, kBeaconY = 18.0;

void place_beacon(const ServerProcess& s, std::int64_t floor) {
    const json body = {{"type", "ble"}, {"bssid", kBeacon}, {"x", kBeaconX}, {"y", kBeaconY}, {"tx_power", -59}};
    ASSERT_EQ(s.post("/v1/floors/" + std::to_string(floor) + "/transmitters", body).status, 201);
}

json ble_scan(double t, const char* bssid, double rss) {
    return {{"t", t}, {"readings", {{{"type", "ble"}, {"bssid", bssid}, {"rss", rss}}}}};
}

// A track started by a WiFi scan at (5, 5), read as the survey's phone reads.
Track started_track(const ServerProcess& s, const locus::testing::Hierarchy& h, double t0) {
    const Track t = open_track(s, {{"map_id", h.map}});
    const json start = {{"scans", {{{"t", t0}, {"readings", readings_at(5.0, 5.0, 0.0, 0)}}}}};
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, start.dump()));
    EXPECT_EQ(got["fused"].size(), 1u) << got.dump();
    return t;
}

// The surveyed floor with its beacon, and a track started at (5, 5).
struct ServerTracksBeacons : ::testing::Test {
    ServerProcess s{{"--quiet"}};
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    double t0 = std::floor(unix_now()) - 100;
    Track t;
    void SetUp() override {
        survey(s, h);
        place_beacon(s, h.floor);
        t = started_track(s, h, t0);
    }
};

TEST_F(ServerTracksBeacons, AStrongReadingOfTheMapsBeaconIsAFixAtIt) {
    // Heard at -60 dBm: a fix at the beacon (σ 6 m), so the estimate moves towards it, on its
    // floor; the BLE scan needs no RP that hears the beacon (the radio map holds none).
    const json near = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, json{{"scans", {ble_scan(t0 + 1, kBeacon, -60)}}}.dump()));
    ASSERT_EQ(near["fused"].size(), 1u) << near.dump();
    const json& f = near["fused"][0];
    EXPECT_EQ(f["floor_id"], h.floor);
    EXPECT_GT(f["x"].get<double>(), 8.0) << f.dump();  // from (5, 5) towards (28, 18)
    EXPECT_GT(f["y"].get<double>(), 6.0) << f.dump();
    EXPECT_EQ(near["scan_fixes"].size(), 0u);  // a beacon is no matched scan
    // Heard again a second later: the same look, not another fix; the track is unmoved.
    const json again = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, json{{"scans", {ble_scan(t0 + 2, kBeacon, -58)}}}.dump()));
    EXPECT_EQ(again["fused"].size(), 0u) << again.dump();
    // Past the interval it counts again.
    const json later = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, json{{"scans", {ble_scan(t0 + 3.5, kBeacon, -58)}}}.dump()));
    EXPECT_EQ(later["fused"].size(), 1u) << later.dump();
}

TEST_F(ServerTracksBeacons, AWeakReadingOrAnotherDeviceIsNoFixAndNoError) {
    const json scans = {{"scans", {ble_scan(t0 + 1, kBeacon, -80), ble_scan(t0 + 2, "0b:00:00:00:00:77", -50)}}};
    const json got = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, scans.dump()));
    EXPECT_EQ(got["fused"].size(), 0u) << got.dump();
    // A WiFi scan no RP hears is still refused, as before.
    const json wifi = {{"scans", {{{"t", t0 + 3}, {"readings", {{{"type", "wifi"}, {"bssid", "0a:00:00:00:00:99"}, {"rss", -60}}}}}}}};
    const Response refused = track_call(s, "POST", steps_path(t.id), {t.token}, wifi.dump());
    EXPECT_EQ(refused.status, 422) << refused.raw;
    EXPECT_EQ(refused.body["error"]["code"], "no_match");
}

TEST_F(ServerTracksBeacons, ABeaconNeitherStartsATrackNorMovesItToAnotherFloor) {
    // A track with no fix yet: the beacon is heard, and nothing starts.
    const Track fresh = open_track(s, {{"map_id", h.map}});
    const json none = body_of(track_call(s, "POST", steps_path(fresh.id), {fresh.token}, json{{"scans", {ble_scan(t0 + 1, kBeacon, -55)}}}.dump()));
    EXPECT_EQ(none["fused"].size(), 0u) << none.dump();
    EXPECT_FALSE(none.contains("latest")) << none.dump();
    // A beacon upstairs heard strongly (through a stairwell) by the running track: it stays put.
    const auto upper = body_of(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                      {{"name", "Upper"}, {"level", 1}, {"width", 30.0}, {"height", 20.0}}),
                               201)
                           .at("id")
                           .get<std::int64_t>();
    const json up = {{"type", "ble"}, {"bssid", "0b:00:00:00:00:02"}, {"x", 5.0}, {"y", 5.0}, {"tx_power", -59}};
    ASSERT_EQ(s.post("/v1/floors/" + std::to_string(upper) + "/transmitters", up).status, 201);
    const json heard = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, json{{"scans", {ble_scan(t0 + 1, "0b:00:00:00:00:02", -50)}}}.dump()));
    EXPECT_EQ(heard["fused"].size(), 0u) << heard.dump();
    EXPECT_EQ(heard["latest"]["floor_id"], h.floor);
}

// The subarea: a walk_pf track's scans are matched among the RPs round its filter's estimate.
// Two RPs 26 m apart read alike (a corridor's two ends under the same APs): matched on the whole
// map a scan of theirs lands between them; on a track standing at the west end it is the west
// RP. A scan only the east RP hears is matched on the whole map (no RP round the track hears it),
// and the answer says so. A track opened with `fusion_options.subarea: false` matches on the
// whole map throughout.
class ServerTracksSubarea : public ::testing::Test {
protected:
    void SetUp() override {
        h = locus::testing::make_hierarchy(s);
        const auto mean = [](const char* bssid, double rss) { return json{{"type", "wifi"}, {"bssid", bssid}, {"mean", rss}, {"variance", 4.0}, {"count", 10}}; };
        const json twins = {{"name", "twins"},
                            {"rps",
                             {{{"name", "west"}, {"x", 2.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {mean("aa:00:00:00:00:01", -50), mean("aa:00:00:00:00:02", -60)}}},
                              {{"name", "east"}, {"x", 28.0}, {"y", 5.0}, {"scans", 10},
                               {"measurements", {mean("aa:00:00:00:00:01", -50), mean("aa:00:00:00:00:02", -60), mean("aa:00:00:00:00:03", -55)}}}}}};
        ASSERT_EQ(s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", twins).status, 201);
    }
    // A track standing at the west RP (one fix), then answers a scan both RPs read alike.
    json alike_scan_on(const Track& t) {
        body_of(track_call(s, "POST", steps_path(t.id), {t.token},
                           json{{"fixes", {{{"t", t0}, {"floor_id", h.floor}, {"x", 2.0}, {"y", 5.0}, {"accuracy_m", 1.0}}}}}.dump()));
        return body_of(track_call(s, "POST", steps_path(t.id), {t.token}, json{{"scans", {{{"t", t0 + 1}, {"readings", alike}}}}}.dump()));
    }
    ServerProcess s{{"--quiet"}};
    locus::testing::Hierarchy h;
    const json alike = json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -50}}, {{"bssid", "aa:00:00:00:00:02"}, {"rss", -60}}});
    // Recent: a localize naming the track reaches as far as the walker could have walked since.
    const double t0 = std::floor(unix_now()) - 3;
};

TEST_F(ServerTracksSubarea, ATracksScansAreMatchedRoundWhereItIs) {
    const json whole = body_of(s.post("/v1/maps/" + std::to_string(h.map) + "/localize", {{"scans", {alike}}}));
    EXPECT_GT(whole["x"].get<double>(), 5.0) << whole.dump();  // between the twins, not at the west one
    const Track t = open_track(s, {{"map_id", h.map}});
    const json near = alike_scan_on(t);
    ASSERT_EQ(near["scan_fixes"].size(), 1u) << near.dump();
    const json& fix = near["scan_fixes"][0];
    EXPECT_DOUBLE_EQ(fix["x"].get<double>(), 2.0) << near.dump();
    // Round the filter's estimate (near the west RP), 3 m + 2σ + 1.5 m/s × 1 s at least.
    EXPECT_NEAR(fix["subarea"]["x"].get<double>(), 2.0, 1.5) << near.dump();
    EXPECT_GT(fix["subarea"]["radius_m"].get<double>(), 4.5) << near.dump();
    EXPECT_LT(fix["subarea"]["radius_m"].get<double>(), 26.0) << near.dump();
    EXPECT_EQ(fix["subarea"]["fell_back"], false) << near.dump();
    const json east_only = json::array({{{"bssid", "aa:00:00:00:00:03"}, {"rss", -55}}});
    const json far = body_of(track_call(s, "POST", steps_path(t.id), {t.token}, json{{"scans", {{{"t", t0 + 2}, {"readings", east_only}}}}}.dump()));
    ASSERT_EQ(far["scan_fixes"].size(), 1u) << far.dump();
    EXPECT_DOUBLE_EQ(far["scan_fixes"][0]["x"].get<double>(), 28.0) << far.dump();
    EXPECT_EQ(far["scan_fixes"][0]["subarea"]["fell_back"], true) << far.dump();
}

// A localize on the map naming the track (and sent with its token) is matched in the track's
// subarea too, and says where; the whole map when the track has no fix yet.
TEST_F(ServerTracksSubarea, ALocalizeNamingTheTrackUsesItsSubarea) {
    const Track t = open_track(s, {{"map_id", h.map}});
    const std::string path = "/v1/maps/" + std::to_string(h.map) + "/localize";
    const auto localize = [&](const json& readings, const std::string& token) {
        return track_call(s, "POST", path, {token}, json{{"scans", {readings}}, {"track_id", t.id}}.dump());
    };
    const json before = body_of(localize(alike, t.token));
    EXPECT_GT(before["x"].get<double>(), 5.0) << before.dump();  // no fix yet: the whole map
    EXPECT_TRUE(before["subarea"].is_null()) << before.dump();
    alike_scan_on(t);  // the track now stands at the west RP
    const json near = body_of(localize(alike, t.token));
    EXPECT_DOUBLE_EQ(near["x"].get<double>(), 2.0) << near.dump();
    EXPECT_EQ(near["subarea"]["fell_back"], false) << near.dump();
    EXPECT_GT(near["subarea"]["radius_m"].get<double>(), 3.0) << near.dump();
    const json east = body_of(localize(json::array({{{"bssid", "aa:00:00:00:00:03"}, {"rss", -55}}}), t.token));
    EXPECT_DOUBLE_EQ(east["x"].get<double>(), 28.0) << east.dump();
    EXPECT_EQ(east["subarea"]["fell_back"], true) << east.dump();
    // Without the track, as before: no "subarea" in the answer.
    const json plain = body_of(s.post(path, {{"scans", {alike}}}));
    EXPECT_FALSE(plain.contains("subarea")) << plain.dump();
}

TEST_F(ServerTracksSubarea, ALocalizeNamingATrackWrongIsRefusedByName) {
    const Track t = open_track(s, {{"map_id", h.map}});
    const std::string path = "/v1/maps/" + std::to_string(h.map) + "/localize";
    const auto call = [&](const json& body, const std::string& token, const std::string& on = "") {
        return track_call(s, "POST", on.empty() ? path : on, {token}, body.dump());
    };
    const json scan = {{"scans", {alike}}};
    const auto with = [&](const json& extra) {
        json b = scan;
        b.update(extra);
        return b;
    };
    EXPECT_EQ(call(with({{"track_id", t.id}}), "").status, 401);
    EXPECT_EQ(call(with({{"track_id", t.id}}), "trk_wrong").status, 403);
    EXPECT_EQ(call(with({{"track_id", t.id + 100}}), t.token).status, 403);  // unknown: as a wrong token
    for (const json& bad : {json("1"), json(0), json(-3), json(1.5), json::array({1}), json(nullptr)}) {
        const Response r = call(with({{"track_id", bad}}), t.token);
        EXPECT_EQ(r.status, 422) << bad.dump();
        EXPECT_NE(r.raw.find("track_id"), std::string::npos) << r.raw;
    }
    const Response both = call(with({{"track_id", t.id}, {"options", {{"near", {{"x", 1.0}, {"y", 1.0}, {"radius", 5.0}}}}}}), t.token);
    EXPECT_EQ(both.status, 422) << both.raw;
    EXPECT_NE(both.raw.find("options.near"), std::string::npos) << both.raw;
    const auto rm = body_of(s.get("/v1/floors/" + std::to_string(h.floor) + "/radiomaps"));
    const std::string on_radiomap = "/v1/radiomaps/" + rm["items"][0]["id"].dump() + "/localize";
    const Response radiomap = call(with({{"track_id", t.id}}), t.token, on_radiomap);
    EXPECT_EQ(radiomap.status, 422) << radiomap.raw;
    // A track on another map.
    const auto other = body_of(s.post("/v1/maps", {{"name", "elsewhere"}}), 201).at("id").get<std::int64_t>();
    const Track there = open_track(s, {{"map_id", other}});
    const Response foreign = call(with({{"track_id", there.id}}), there.token);
    EXPECT_EQ(foreign.status, 422) << foreign.raw;
    EXPECT_NE(foreign.raw.find("is on map"), std::string::npos) << foreign.raw;
    // A closed track.
    ASSERT_EQ(track_call(s, "POST", "/v1/tracks/" + std::to_string(t.id) + "/close", {t.token}).status, 200);
    const Response closed = call(with({{"track_id", t.id}}), t.token);
    EXPECT_EQ(closed.status, 409) << closed.raw;
    EXPECT_EQ(closed.body["error"]["code"], "track_closed") << closed.raw;
}

TEST_F(ServerTracksSubarea, ATrackMayTurnItOff) {
    const Track t = open_track(s, {{"map_id", h.map}, {"fusion_options", {{"subarea", false}}}});
    const json info = body_of(track_call(s, "GET", "/v1/tracks/" + std::to_string(t.id), {t.token}));
    EXPECT_EQ(info["fusion_options"], json({{"subarea", false}})) << info.dump();
    const json got = alike_scan_on(t);
    ASSERT_EQ(got["scan_fixes"].size(), 1u) << got.dump();
    EXPECT_GT(got["scan_fixes"][0]["x"].get<double>(), 5.0) << got.dump();  // the whole map's answer
    EXPECT_TRUE(got["scan_fixes"][0]["subarea"].is_null()) << got.dump();
    // A localize naming it matches on the whole map too.
    const json named = body_of(track_call(s, "POST", "/v1/maps/" + std::to_string(h.map) + "/localize", {t.token},
                                          json{{"scans", {alike}}, {"track_id", t.id}}.dump()));
    EXPECT_GT(named["x"].get<double>(), 5.0) << named.dump();
    EXPECT_TRUE(named["subarea"].is_null()) << named.dump();
    // Turned on by name is the default: the west RP.
    const Track on = open_track(s, {{"map_id", h.map}, {"fusion_options", {{"subarea", true}}}});
    EXPECT_DOUBLE_EQ(alike_scan_on(on)["scan_fixes"][0]["x"].get<double>(), 2.0);
}

}  // namespace
}  // namespace server_tracks_scans_test
