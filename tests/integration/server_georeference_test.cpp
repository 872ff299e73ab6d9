// Floors on Earth over HTTP against the real server (docs/geo.md): a floor's georeference set by
// PATCH and read back (also after a restart), fitted from control points, and carried as
// lat/lon by localize, track and route answers; every bad input refused with nothing stored.
//
// The Earth positions here never come from the server's code: they are computed by the
// equirectangular rule the IPIN 2023 data's README gives for its venue (the Museum
// Industriekultur, Nuremberg): about the floor maps' calibration centre (49.46115181 N,
// 11.11114911 E), north = Δlat · 6 372 360 m and east = Δlon · 6 390 503 m · cos 49.46115°
// (radians; the WGS84 radii of curvature there), good to about a centimetre over the venue.
#include <httplib.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "hierarchy.hpp"
#include "plan_geojson.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_georeference_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using locus::testing::track_call;
using nlohmann::json;

constexpr double kRad = std::numbers::pi / 180.0;
constexpr double kLat0 = 49.46115181, kLon0 = 11.11114911;
constexpr double kNorthRadius = 6372360.0, kEastRadius = 6390503.0 * 0.6499635;  // cos 49.46115° = 0.6499635
// The known placement: floor point (50, 25) at the centre, +y at 339.264° (20.736° west of north).
constexpr double kAnchorX = 50, kAnchorY = 25, kBearing = 339.264;

struct LatLon {
    double lat, lon;
};

LatLon earth_of(double x, double y) {
    const double b = kBearing * kRad, dx = x - kAnchorX, dy = y - kAnchorY;
    const double east = dx * std::cos(b) + dy * std::sin(b), north = -dx * std::sin(b) + dy * std::cos(b);
    return {kLat0 + north / kNorthRadius / kRad, kLon0 + east / kEastRadius / kRad};
}

// Metres between an answer's lat/lon and where the rule puts floor point (x, y).
double metres_off(const json& j, double x, double y) {
    const LatLon want = earth_of(x, y);
    const double dn = (j.at("lat").get<double>() - want.lat) * kRad * kNorthRadius;
    const double de = (j.at("lon").get<double>() - want.lon) * kRad * kEastRadius;
    return std::hypot(dn, de);
}

json control_point(double x, double y) {
    const LatLon g = earth_of(x, y);
    return {{"x", x}, {"y", y}, {"lat", g.lat}, {"lon", g.lon}};
}

json known_geo() {
    return {{"lat", kLat0}, {"lon", kLon0}, {"x", kAnchorX}, {"y", kAnchorY}, {"bearing_deg", kBearing - 360.0}};
}

struct Venue {
    locus::testing::Hierarchy h;
    std::int64_t floor = 0;  // 100 m × 50 m, level -2
    std::string floor_path;
};

Venue make_venue(const ServerProcess& s) {
    Venue v;
    v.h = locus::testing::make_hierarchy(s);
    v.floor = body_of(s.post("/v1/buildings/" + std::to_string(v.h.building) + "/floors",
                             {{"name", "Basement hall"}, {"level", -2}, {"width", 100.0}, {"height", 50.0}}),
                      201)
                  .at("id")
                  .get<std::int64_t>();
    v.floor_path = "/v1/floors/" + std::to_string(v.floor);
    return v;
}

// The error message of a 422 (or `status`) answer.
std::string refused(const locus::testing::Response& r, int status = 422) {
    EXPECT_EQ(r.status, status) << r.raw;
    if (!r.body.is_object() || !r.body.contains("error")) return "(no error body) " + r.raw;
    return r.body.at("error").at("message").get<std::string>();
}

json m(const std::string& bssid, double mean) {
    return {{"type", "wifi"}, {"bssid", bssid}, {"mean", mean}, {"variance", 4.0}, {"count", 10}};
}

TEST(ServerGeoreference, PatchedGeoIsReadBackAndSurvivesARestart) {
    ServerProcess s;
    const Venue v = make_venue(s);
    const json fresh = body_of(s.get(v.floor_path));
    EXPECT_TRUE(fresh.at("geo").is_null());
    EXPECT_TRUE(fresh.at("elevation_m").is_null());

    const json patched = body_of(s.patch(v.floor_path, {{"geo", known_geo()}, {"elevation_m", -5.7}}));
    const json& g = patched.at("geo");
    EXPECT_DOUBLE_EQ(g.at("lat").get<double>(), kLat0);
    EXPECT_DOUBLE_EQ(g.at("lon").get<double>(), kLon0);
    EXPECT_DOUBLE_EQ(g.at("x").get<double>(), kAnchorX);
    EXPECT_DOUBLE_EQ(g.at("y").get<double>(), kAnchorY);
    EXPECT_NEAR(g.at("bearing_deg").get<double>(), kBearing, 1e-9);  // -20.736 is stored as 339.264
    EXPECT_EQ(g.size(), 5u);
    EXPECT_DOUBLE_EQ(patched.at("elevation_m").get<double>(), -5.7);
    EXPECT_EQ(body_of(s.get(v.floor_path)), patched);
    // Other fields leave it alone; a list shows it too.
    EXPECT_EQ(body_of(s.patch(v.floor_path, {{"name", "Hall"}})).at("geo"), g);
    const json page = body_of(s.get("/v1/buildings/" + std::to_string(v.h.building) + "/floors"));
    bool listed = false;
    for (const auto& f : page.at("items"))
        if (f.at("id") == v.floor) listed = f.at("geo") == g;
    EXPECT_TRUE(listed) << page.dump();

    s.stop();
    s.start();
    EXPECT_EQ(body_of(s.get(v.floor_path)).at("geo"), g);

    // null clears the georeference; elevation_m stays (null leaves it, as for north_offset_deg).
    const json cleared = body_of(s.patch(v.floor_path, {{"geo", nullptr}}));
    EXPECT_TRUE(cleared.at("geo").is_null());
    EXPECT_DOUBLE_EQ(cleared.at("elevation_m").get<double>(), -5.7);
    EXPECT_TRUE(body_of(s.get(v.floor_path)).at("geo").is_null());
}

TEST(ServerGeoreference, CreateTakesGeoAndElevation) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const json f = body_of(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                  {{"name", "Mezzanine"}, {"level", -1}, {"width", 10.0}, {"height", 5.0}, {"elevation_m", -3.2}, {"geo", known_geo()}}),
                           201);
    EXPECT_DOUBLE_EQ(f.at("elevation_m").get<double>(), -3.2);
    EXPECT_NEAR(f.at("geo").at("bearing_deg").get<double>(), kBearing, 1e-9);
}

TEST(ServerGeoreference, FitsControlPointsFromAKnownTransform) {
    ServerProcess s;
    const Venue v = make_venue(s);
    const json body = {{"points", {control_point(0, 0), control_point(100, 0), control_point(100, 50), control_point(0, 50)}}};

    // A dry run answers the fit and stores nothing.
    const json dry = body_of(s.post(v.floor_path + "/georeference?dry_run=true", body));
    EXPECT_FALSE(dry.at("stored").get<bool>());
    EXPECT_FALSE(dry.contains("floor"));
    EXPECT_TRUE(body_of(s.get(v.floor_path)).at("geo").is_null());

    const json fit = body_of(s.post(v.floor_path + "/georeference", body));
    EXPECT_TRUE(fit.at("stored").get<bool>());
    const json& g = fit.at("geo");
    // Anchored at the points' floor centroid (50, 25), which the rule put at the centre.
    EXPECT_NEAR(g.at("x").get<double>(), 50.0, 1e-9);
    EXPECT_NEAR(g.at("y").get<double>(), 25.0, 1e-9);
    EXPECT_NEAR(g.at("lat").get<double>(), kLat0, 2e-7);  // ~2 cm
    EXPECT_NEAR(g.at("lon").get<double>(), kLon0, 3e-7);
    EXPECT_NEAR(g.at("bearing_deg").get<double>(), kBearing, 0.01);
    EXPECT_NEAR(fit.at("scale").get<double>(), 1.0, 2e-4);
    ASSERT_EQ(fit.at("residuals_m").size(), 4u);
    for (const auto& r : fit.at("residuals_m")) EXPECT_LT(r.get<double>(), 0.03);
    EXPECT_LT(fit.at("rms_m").get<double>(), 0.03);
    EXPECT_EQ(fit.at("floor").at("geo"), g);
    EXPECT_EQ(body_of(s.get(v.floor_path)).at("geo"), g);

    // Three points do, and control points drawn at half scale say so: scale 2, the rigid
    // residuals the corners' half distances from the centre, √(50² + 25²)/2 = 27.95 m.
    const json three = body_of(s.post(v.floor_path + "/georeference?dry_run=true",
                                      {{"points", {control_point(0, 0), control_point(100, 0), control_point(0, 50)}}}));
    EXPECT_NEAR(three.at("geo").at("bearing_deg").get<double>(), kBearing, 0.01);
    json half = json::array();
    for (auto [x, y] : {std::pair{0.0, 0.0}, {100.0, 0.0}, {100.0, 50.0}, {0.0, 50.0}}) {
        json p = control_point(x, y);
        p["x"] = 50 + (x - 50) / 2;
        p["y"] = 25 + (y - 25) / 2;
        half.push_back(p);
    }
    const json scaled = body_of(s.post(v.floor_path + "/georeference?dry_run=true", {{"points", half}}));
    EXPECT_NEAR(scaled.at("scale").get<double>(), 2.0, 1e-3);
    EXPECT_NEAR(scaled.at("rms_m").get<double>(), 27.95, 0.05);
    EXPECT_EQ(body_of(s.get(v.floor_path)).at("geo"), g);  // dry runs changed nothing
}

TEST(ServerGeoreference, LocalizeTrackAndRouteAnswersCarryLatLon) {
    ServerProcess s;
    const Venue v = make_venue(s);
    const json survey = {{"name", "hall"},
                         {"rps",
                          {{{"name", "west"}, {"x", 10.0}, {"y", 20.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -40), m("aa:00:00:00:00:02", -75)}}},
                           {{"name", "east"}, {"x", 90.0}, {"y", 30.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -75), m("aa:00:00:00:00:02", -40)}}}}}};
    const auto rm = body_of(s.post(v.floor_path + "/radiomaps/import", survey), 201).at("id").get<std::int64_t>();
    const json scan = {{"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -41}}, {{"bssid", "aa:00:00:00:00:02"}, {"rss", -74}}})})},
                       {"algorithm", "nn"}};
    const std::string by_radiomap = "/v1/radiomaps/" + std::to_string(rm) + "/localize";
    const std::string by_map = "/v1/maps/" + std::to_string(v.h.map) + "/localize";

    // Not georeferenced: no lat/lon.
    const json before = body_of(s.post(by_radiomap, scan));
    EXPECT_EQ(before.at("x"), 10.0);
    EXPECT_FALSE(before.contains("lat"));
    EXPECT_FALSE(before.contains("lon"));

    body_of(s.patch(v.floor_path, {{"geo", known_geo()}}));
    for (const std::string& path : {by_radiomap, by_map}) {
        const json a = body_of(s.post(path, scan));
        ASSERT_EQ(a.at("x"), 10.0) << path;
        ASSERT_EQ(a.at("y"), 20.0) << path;
        EXPECT_LT(metres_off(a, 10, 20), 0.03) << path << " " << a.dump();
        if (path != by_radiomap) continue;
        json without = a;
        without.erase("lat");
        without.erase("lon");
        EXPECT_EQ(without, before);  // nothing else changed
    }

    // A track's fixes, as posted and as read back.
    const json opened = body_of(track_call(s, "POST", "/v1/tracks", {}, json{{"map_id", v.h.map}}.dump()), 201);
    const std::string track = "/v1/tracks/" + std::to_string(opened.at("id").get<std::int64_t>());
    const std::string token = opened.at("token");
    const json fixes = {{"fixes", {{{"t", locus::testing::unix_now()}, {"floor_id", v.floor}, {"x", 70.0}, {"y", 5.0}, {"accuracy_m", 2.0}}}}};
    const json posted = body_of(track_call(s, "POST", track + "/fixes", {token}, fixes.dump()));
    EXPECT_LT(metres_off(posted.at("latest"), 70, 5), 0.03) << posted.dump();
    const json read = body_of(track_call(s, "GET", track, {token}));
    ASSERT_FALSE(read.at("trail").empty());
    EXPECT_LT(metres_off(read.at("trail")[0], 70, 5), 0.03) << read.dump();
    EXPECT_LT(metres_off(read.at("latest"), 70, 5), 0.03);
    const json positions = body_of(s.get("/v1/maps/" + std::to_string(v.h.map) + "/positions"));
    ASSERT_EQ(positions.at("positions").size(), 1u) << positions.dump();
    EXPECT_LT(metres_off(positions.at("positions")[0].at("fix"), 70, 5), 0.03) << positions.dump();

    // Ranging: four transmitters in the hall's corners, heard as a log-distance model (tx_power
    // −40 dBm at 1 m, exponent 2) predicts at (30, 20).
    const double corners[4][2] = {{2, 2}, {98, 2}, {98, 48}, {2, 48}};
    json heard = json::array();
    for (int i = 0; i < 4; ++i) {
        const std::string bssid = "02:00:00:00:00:0" + std::to_string(i + 1);
        body_of(s.post(v.floor_path + "/transmitters", {{"type", "wifi"}, {"bssid", bssid}, {"x", corners[i][0]}, {"y", corners[i][1]},
                                                        {"tx_power", -40.0}, {"path_loss_exponent", 2.0}}),
                201);
        heard.push_back({{"bssid", bssid}, {"rss", -40.0 - 20.0 * std::log10(std::hypot(30 - corners[i][0], 20 - corners[i][1]))}});
    }
    const json ranged = body_of(s.post(by_radiomap, {{"algorithm", "multilateration"}, {"measurements", heard}}));
    EXPECT_NEAR(ranged.at("x").get<double>(), 30.0, 0.05) << ranged.dump();
    EXPECT_LT(metres_off(ranged, ranged.at("x").get<double>(), ranged.at("y").get<double>()), 0.03) << ranged.dump();

    // A route over the hall's plan: both ends and every point of the leg.
    using locus::testing::feature;
    const json plan = {{"type", "FeatureCollection"},
                       {"features", {feature("space", locus::testing::rect_polygon(0, 0, 100, 50), {{"name", "Hall"}})}}};
    ASSERT_EQ(s.put(v.floor_path + "/plan", plan).status, 200);
    const json route = body_of(s.post("/v1/maps/" + std::to_string(v.h.map) + "/route",
                                      {{"from", {{"floor_id", v.floor}, {"x", 5.0}, {"y", 5.0}}},
                                       {"to", {{"floor_id", v.floor}, {"x", 95.0}, {"y", 45.0}}}}));
    for (const char* end : {"from", "to"}) {
        const json& e = route.at(end);
        EXPECT_LT(metres_off(e, e.at("x").get<double>(), e.at("y").get<double>()), 0.03) << end << " " << e.dump();
    }
    const json& leg = route.at("legs").at(0);
    ASSERT_EQ(leg.at("path_lat_lon").size(), leg.at("path").size());
    for (std::size_t i = 0; i < leg.at("path").size(); ++i) {
        const json& p = leg.at("path")[i];
        const json& q = leg.at("path_lat_lon")[i];
        EXPECT_LT(metres_off({{"lat", q[0]}, {"lon", q[1]}}, p[0].get<double>(), p[1].get<double>()), 0.03) << i;
    }

    // Cleared: the answers lose lat/lon at once (the server's cache follows the write). The
    // plan made the hall a room, so the answer to compare with is taken afresh.
    json last = body_of(s.post(by_radiomap, scan));
    ASSERT_TRUE(last.contains("lat"));
    last.erase("lat");
    last.erase("lon");
    body_of(s.patch(v.floor_path, {{"geo", nullptr}}));
    EXPECT_EQ(body_of(s.post(by_radiomap, scan)), last);
    const json plain_route = body_of(s.post("/v1/maps/" + std::to_string(v.h.map) + "/route",
                                            {{"from", {{"floor_id", v.floor}, {"x", 5.0}, {"y", 5.0}}},
                                             {"to", {{"floor_id", v.floor}, {"x", 95.0}, {"y", 45.0}}}}));
    EXPECT_FALSE(plain_route.at("from").contains("lat"));
    EXPECT_FALSE(plain_route.at("legs").at(0).contains("path_lat_lon"));
    EXPECT_FALSE(body_of(track_call(s, "GET", track, {token})).at("latest").contains("lat"));
}

TEST(ServerGeoreference, BadGeoIsRefusedNamingTheFieldAndStoresNothing) {
    ServerProcess s;
    const Venue v = make_venue(s);
    const json stored = body_of(s.patch(v.floor_path, {{"geo", known_geo()}, {"elevation_m", 0.0}}));

    auto with = [](const char* key, json value) {
        json g = known_geo();
        g[key] = std::move(value);
        return json{{"name", "Renamed"}, {"geo", g}};
    };
    json missing = known_geo();
    missing.erase("bearing_deg");
    EXPECT_NE(refused(s.patch(v.floor_path, {{"geo", missing}})).find("geo.bearing_deg"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("lat", 90.5))).find("geo.lat"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("lat", -91))).find("geo.lat"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("lon", 180.01))).find("geo.lon"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("bearing_deg", 400))).find("geo.bearing_deg"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("x", 2e7))).find("geo.x"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("lat", "NaN"))).find("geo.lat"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("lon", "11.1"))).find("geo.lon"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("y", nullptr))).find("geo.y"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, with("alt", 300))).find("geo.alt"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, {{"geo", "49.46,11.11"}})).find("geo"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, {{"geo", json::array({kLat0, kLon0})}})).find("geo"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, {{"geo_lat", 10.0}})).find("geo_lat"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, {{"elevation_m", 20000.0}})).find("elevation_m"), std::string::npos);
    EXPECT_NE(refused(s.patch(v.floor_path, {{"elevation_m", "high"}})).find("elevation_m"), std::string::npos);
    // NaN and infinities are not JSON.
    const std::string nan_body = R"({"geo": {"lat": NaN, "lon": 11.1, "x": 0, "y": 0, "bearing_deg": 0}})";
    auto h = locus::testing::client(s.port());
    const auto nan = h.Patch(v.floor_path.c_str(), nan_body, "application/json");
    ASSERT_TRUE(nan);
    EXPECT_EQ(nan->status, 400) << nan->body;
    const auto inf = h.Patch(v.floor_path.c_str(), R"({"geo": {"lat": 1e999, "lon": 11.1, "x": 0, "y": 0, "bearing_deg": 0}})", "application/json");
    ASSERT_TRUE(inf);
    EXPECT_EQ(inf->status, 400) << inf->body;
    // A create with bad geo makes no floor.
    const std::string floors = "/v1/buildings/" + std::to_string(v.h.building) + "/floors";
    json bad_create = {{"name", "Ghost"}, {"level", 3}, {"width", 1.0}, {"height", 1.0}, {"geo", with("lat", 95).at("geo")}};
    EXPECT_NE(refused(s.post(floors, bad_create)).find("geo.lat"), std::string::npos);
    const json listed = body_of(s.get(floors));
    for (const auto& f : listed.at("items")) EXPECT_NE(f.at("name"), "Ghost");

    EXPECT_EQ(body_of(s.get(v.floor_path)), stored);  // not renamed, geo and elevation as they were
}

TEST(ServerGeoreference, BadControlPointsAreRefusedAndStoreNothing) {
    ServerProcess s;
    const Venue v = make_venue(s);
    const json stored = body_of(s.patch(v.floor_path, {{"geo", known_geo()}}));
    const std::string path = v.floor_path + "/georeference";
    auto points = [](json list) { return json{{"points", std::move(list)}}; };
    const json a = control_point(0, 0), b = control_point(100, 0), c = control_point(0, 50);
    auto changed = [](json p, const char* key, json value) {
        p[key] = std::move(value);
        return p;
    };

    EXPECT_NE(refused(s.post(path, points({a, b}))).find("points"), std::string::npos);
    EXPECT_NE(refused(s.post(path, points(json::array()))).find("points"), std::string::npos);
    EXPECT_NE(refused(s.post(path, json::object())).find("missing field 'points'"), std::string::npos);
    EXPECT_NE(refused(s.post(path, {{"points", "a, b, c"}})).find("points"), std::string::npos);
    // Collinear on the floor (whatever the Earth positions say), and three at one place.
    EXPECT_NE(refused(s.post(path, points({a, control_point(50, 0), b}))).find("collinear"), std::string::npos);
    EXPECT_NE(refused(s.post(path, points({control_point(0, 0), control_point(10, 10), control_point(20, 20)}))).find("collinear"),
              std::string::npos);
    EXPECT_NE(refused(s.post(path, points({a, a, a}))).find("collinear"), std::string::npos);
    json no_lon = b;
    no_lon.erase("lon");
    EXPECT_NE(refused(s.post(path, points({a, no_lon, c}))).find("points[1].lon"), std::string::npos);
    EXPECT_NE(refused(s.post(path, points({changed(a, "lat", 91), b, c}))).find("points[0].lat"), std::string::npos);
    EXPECT_NE(refused(s.post(path, points({a, b, changed(c, "lon", -181)}))).find("points[2].lon"), std::string::npos);
    EXPECT_NE(refused(s.post(path, points({a, b, changed(c, "x", "NaN")}))).find("points[2].x"), std::string::npos);
    EXPECT_NE(refused(s.post(path, points({a, changed(b, "z", 1.0), c}))).find("points[1].z"), std::string::npos);
    EXPECT_NE(refused(s.post(path, points({a, b, 42}))).find("points[2]"), std::string::npos);
    EXPECT_NE(refused(s.post(path, {{"points", {a, b, c}}, {"weights", {1, 1, 1}}})).find("weights"), std::string::npos);
    // Half a degree of latitude away is 55 km: not a campus.
    EXPECT_NE(refused(s.post(path, points({a, b, changed(c, "lat", kLat0 + 0.5)}))).find("points"), std::string::npos);
    EXPECT_EQ(s.post_raw(path, R"({"points": [)").status, 400);
    EXPECT_EQ(s.post_raw(path, R"({"points": [{"x": NaN, "y": 0, "lat": 49, "lon": 11}]})").status, 400);
    EXPECT_NE(refused(s.post(path + "?dry_run=maybe", points({a, b, c})), 400).find("dry_run"), std::string::npos);
    EXPECT_EQ(s.post("/v1/floors/999999/georeference", points({a, b, c})).status, 404);

    EXPECT_EQ(body_of(s.get(v.floor_path)), stored);
}

}  // namespace
}  // namespace server_georeference_test
