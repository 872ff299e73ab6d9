// End to end: a simulated walk replayed against a real local server gives fixes from the
// server's matcher, and the same figures as the in-process evaluation of that walk.
#include <httplib.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace replay_test {
namespace {

using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

TEST(Replay, ServerFixesGiveTheSameTracksAsTheInProcessEvaluation) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string walk = s.dir() + "/walk.jsonl";
    const auto sim = run_command({LOCUS_CLI_BIN, "sim", "--scenario", "ground", "--seed", "3", "--out", walk});
    ASSERT_EQ(sim.status, 0) << sim.err;

    const std::vector<std::string> replay = {LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap",
                                             std::to_string(h.radiomap), "--rule", "all", "--upload-survey", walk};
    const auto first = run_command(replay);
    ASSERT_EQ(first.status, 0) << first.err;
    const json out = json::parse(first.out);
    EXPECT_GT(out.at("fixes").get<int>(), 3);
    EXPECT_EQ(out.at("no_match"), 0);
    EXPECT_GT(out.at("steps").get<int>(), 10);

    const auto local = run_command({LOCUS_CLI_BIN, "sim", "--scenario", "ground", "--seed", "3", "--evaluate", "--json"});
    ASSERT_EQ(local.status, 0) << local.err;
    std::map<std::string, double> expected;
    for (const auto& o : json::parse(local.out)) expected[o.at("method")] = o.at("mean_error_m");

    // Every method of `sim --evaluate`, plus walk_pf (replay's default), which sim does not run.
    ASSERT_EQ(out.at("tracks").size(), expected.size() + 1);
    for (const auto& t : out.at("tracks")) {
        const std::string method = t.at("method");
        if (method == "walk_pf") {
            ASSERT_FALSE(t.at("points").empty());
            EXPECT_LT(t.at("mean_error_m").get<double>(), 10.0);
            continue;
        }
        ASSERT_TRUE(expected.count(method)) << method;
        EXPECT_NEAR(t.at("mean_error_m").get<double>(), expected[method], 1e-6) << method;
        ASSERT_FALSE(t.at("points").empty());
        EXPECT_TRUE(t.at("points")[0].contains("error_m"));
    }

    // Replaying again uploads nothing twice: the RPs keep their scan counts.
    const auto rps_before = body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/export")).at("rps");
    ASSERT_EQ(run_command(replay).status, 0);
    EXPECT_EQ(body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/export")).at("rps"), rps_before);
}

TEST(Replay, OneRuleAsCsv) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string walk = s.dir() + "/walk.jsonl";
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "sim", "--scenario", "basement", "--seed", "2", "--out", walk}).status, 0);
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap", std::to_string(h.radiomap),
                                "--rule", "midpoint_threshold", "--format", "csv", "--upload-survey", walk});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.rfind("method,t,x,y,error_m\n", 0), 0u) << r.out.substr(0, 200);
    EXPECT_NE(r.out.find("\nmidpoint_threshold,"), std::string::npos);
    EXPECT_EQ(r.out.find("\nkalman,"), std::string::npos);
}

TEST(Replay, UnknownRuleIsRefused) {
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", "http://127.0.0.1:1", "--radiomap", "1", "--rule",
                                "average", "/dev/null"});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("unknown --rule"), std::string::npos) << r.err;
}

TEST(Replay, AWalkWithAnchorsGetsTheRangingMethods) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string walk = s.dir() + "/open_area.jsonl";
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "sim", "--scenario", "open_area", "--seed", "4", "--out", walk}).status, 0);
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap", std::to_string(h.radiomap),
                                "--rule", "all", "--walls", "file", "--upload-survey", walk});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto local = run_command({LOCUS_CLI_BIN, "sim", "--scenario", "open_area", "--seed", "4", "--evaluate", "--json"});
    ASSERT_EQ(local.status, 0) << local.err;
    std::map<std::string, double> expected;
    for (const auto& o : json::parse(local.out)) expected[o.at("method")] = o.at("mean_error_m");
    int ranging = 0;
    const json out = json::parse(r.out);  // kept: a range-for over a temporary's member dangles
    for (const auto& t : out.at("tracks")) {
        const std::string method = t.at("method");
        if (method != "trilateration" && method != "multilateration" && method != "kalman_trilateration" && method != "kalman_ranging" &&
            method != "ekf_ranging")
            continue;
        ++ranging;
        // The walk file's anchors and readings give the very tracks of the walk in memory.
        ASSERT_TRUE(expected.count(method)) << method;
        EXPECT_NEAR(t.at("mean_error_m").get<double>(), expected[method], 1e-6) << method;
    }
    EXPECT_EQ(ranging, 5);
}

// The names from before the rename still work: the scenario seed004 is open_area, the flags
// --seed-r-sigma and --seed-q-sigma are --trilateration-r-sigma and --trilateration-q-sigma (which
// change kalman_trilateration's track, and only it), and --rule kalman_seed is kalman_trilateration.
TEST(Replay, TheDeprecatedNamesStillWork) {
    const auto scores = [](const std::vector<std::string>& extra) {
        std::vector<std::string> args = {LOCUS_CLI_BIN, "sim", "--seed", "4", "--evaluate", "--json"};
        args.insert(args.end(), extra.begin(), extra.end());
        const auto r = run_command(args);
        EXPECT_EQ(r.status, 0) << r.err;
        std::map<std::string, double> out;
        for (const auto& o : json::parse(r.out)) {
            EXPECT_EQ(o.at("scenario"), "open_area");
            out[o.at("method")] = o.at("mean_error_m");
        }
        return out;
    };
    const auto old_names = scores({"--scenario", "seed004", "--seed-r-sigma", "1.2", "--seed-q-sigma", "0.6"});
    const auto new_names = scores({"--scenario", "open_area", "--trilateration-r-sigma", "1.2", "--trilateration-q-sigma", "0.6"});
    const auto defaults = scores({"--scenario", "open_area"});
    EXPECT_EQ(old_names, new_names);
    ASSERT_TRUE(defaults.count("kalman_trilateration"));
    EXPECT_NE(new_names.at("kalman_trilateration"), defaults.at("kalman_trilateration"));
    EXPECT_EQ(new_names.at("kalman_ranging"), defaults.at("kalman_ranging"));

    ServerProcess s;
    const std::string walk = s.dir() + "/ground.jsonl";
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "sim", "--scenario", "ground", "--seed", "1", "--out", walk}).status, 0);
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap", "1", "--rule", "kalman_seed", walk});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("--rule kalman_trilateration needs a walk with anchors"), std::string::npos) << r.err;
}

TEST(Replay, ARangingRuleNeedsAnchors) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string walk = s.dir() + "/ground.jsonl";
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "sim", "--scenario", "ground", "--seed", "1", "--out", walk}).status, 0);
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap", std::to_string(h.radiomap),
                                "--rule", "kalman_ranging", walk});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("needs a walk with anchors"), std::string::npos) << r.err;
}

json feature(const std::string& kind, json geometry, json properties = json::object()) {
    properties["feature"] = kind;
    return {{"type", "Feature"}, {"geometry", std::move(geometry)}, {"properties", std::move(properties)}};
}
json box(double x0, double y0, double x1, double y1) {
    return {{"type", "Polygon"}, {"coordinates", {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}}}};
}
json line(std::vector<std::pair<double, double>> pts) {
    json c = json::array();
    for (const auto& [x, y] : pts) c.push_back({x, y});
    return {{"type", "LineString"}, {"coordinates", c}};
}

// The ground scenario's west half as the server's plan: the corridor is walled off at x = 15,
// where the walk file's corridor runs on to x = 28 (the walk ends in office 4, x > 21).
json west_half_of_ground() {
    json f = json::array();
    f.push_back(feature("space", box(0, 6.2, 12, 10.3), {{"name", "hall"}}));
    f.push_back(feature("space", box(0, 4, 15, 6.2), {{"name", "corridor"}, {"kind", "corridor"}}));
    f.push_back(feature("space", box(0, 0, 7, 4), {{"name", "office 1"}}));
    f.push_back(feature("space", box(7, 0, 14, 4), {{"name", "office 2"}}));
    f.push_back(feature("wall", line({{0, 4}, {15, 4}})));
    f.push_back(feature("wall", line({{7, 0}, {7, 4}})));
    f.push_back(feature("wall", line({{0, 6.2}, {12, 6.2}})));
    f.push_back(feature("wall", line({{15, 4}, {15, 6.2}})));
    f.push_back(feature("door", line({{2.5, 4}, {3.5, 4}})));
    f.push_back(feature("door", line({{9.5, 4}, {10.5, 4}})));
    f.push_back(feature("door", line({{4, 6.2}, {7, 6.2}})));
    return {{"type", "FeatureCollection"}, {"features", f}};
}

double max_x(const json& replay_out, const std::string& method) {
    for (const auto& t : replay_out.at("tracks"))
        if (t.at("method") == method) {
            double m = -1e9;
            for (const auto& p : t.at("points")) m = std::max(m, p.at("x").get<double>());
            return m;
        }
    ADD_FAILURE() << "no " << method << " track";
    return 0.0;
}

TEST(Replay, FiltersMapMatchOnTheServersPlanWhenTheFloorHasOne) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string walk = s.dir() + "/walk.jsonl";
    // A fixed compass offset alone (--heading-walk 0): this walk's PDR (seed 3) then
    // runs through the office wall past x = 17 m, which is what the map matching is checked on.
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "sim", "--scenario", "ground", "--seed", "3", "--heading-walk", "0", "--out", walk}).status, 0);
    const auto replay = [&](const std::string& walls) {
        return run_command({LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap", std::to_string(h.radiomap), "--rule",
                            "all", "--upload-survey", "--walls", walls, walk});
    };

    // No plan yet: auto falls back to the walk file's rooms, and says so; server refuses.
    const auto before = replay("auto");
    ASSERT_EQ(before.status, 0) << before.err;
    EXPECT_EQ(json::parse(before.out).at("walls"), "file");
    EXPECT_NE(before.err.find("has no plan"), std::string::npos) << before.err;
    const auto refused = replay("server");
    EXPECT_NE(refused.status, 0);
    EXPECT_NE(refused.err.find("floor " + std::to_string(h.floor)), std::string::npos) << refused.err;
    // On the file's rooms the filters follow the walk down the corridor past x = 15.
    EXPECT_GT(max_x(json::parse(before.out), "particle"), 17.0);
    EXPECT_GT(max_x(json::parse(before.out), "kalman"), 17.0);

    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(h.floor) + "/plan", west_half_of_ground()).status, 200);
    for (const std::string walls : {"auto", "server"}) {
        const auto r = replay(walls);
        ASSERT_EQ(r.status, 0) << r.err;
        const json out = json::parse(r.out);
        EXPECT_EQ(out.at("walls"), "server");
        EXPECT_EQ(out.at("floor_id"), h.floor);
        EXPECT_NE(r.err.find("plan from the server: 4 spaces, 4 walls, 3 doors"), std::string::npos) << r.err;
        // Every particle stays on the server's plan, so no point of the track passes the wall
        // at x = 15 though the person walks on to x = 22.5; the Kalman filter stops there too.
        EXPECT_LT(max_x(out, "particle"), 15.0);
        EXPECT_LT(max_x(out, "kalman"), 15.0);
        // The rules know no walls.
        EXPECT_GT(max_x(out, "pdr"), 17.0);
    }
    // --walls file ignores the server's plan.
    const auto file = replay("file");
    ASSERT_EQ(file.status, 0) << file.err;
    EXPECT_EQ(json::parse(file.out).at("walls"), "file");
    EXPECT_EQ(json::parse(file.out).at("tracks"), json::parse(before.out).at("tracks"));
}

TEST(Replay, UnknownWallsSourceIsRefused) {
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", "http://127.0.0.1:1", "--radiomap", "1", "--walls",
                                "ceiling", "/dev/null"});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("--walls"), std::string::npos) << r.err;
}

TEST(SimOnServerPlan, EvaluatesOnTheFloorsPlanAsOnTheConvertedScenario) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::vector<std::string> base = {LOCUS_CLI_BIN, "sim", "--scenario", "basement", "--seed", "5", "--evaluate", "--json"};
    const auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = base;
        args.insert(args.end(), extra.begin(), extra.end());
        return run_command(args);
    };
    const std::string floor = std::to_string(h.floor);

    // The floor has no plan yet: refused, naming the floor.
    const auto none = with({"--server", s.url(), "--floor", floor});
    EXPECT_NE(none.status, 0);
    EXPECT_NE(none.err.find("floor " + floor + " has no plan"), std::string::npos) << none.err;
    // --server and --floor go together.
    const auto half = with({"--server", s.url()});
    EXPECT_NE(half.status, 0);
    EXPECT_NE(half.err.find("--floor"), std::string::npos) << half.err;
    // --walls names another source than the floor's plan.
    const auto both = with({"--server", s.url(), "--floor", floor, "--walls", "plan"});
    EXPECT_NE(both.status, 0);
    EXPECT_NE(both.err.find("--walls and --floor"), std::string::npos) << both.err;

    // --put-plan stores the scenario's rooms and doors as the floor's plan, then uses it.
    const auto put = with({"--server", s.url(), "--floor", floor, "--put-plan"});
    ASSERT_EQ(put.status, 0) << put.err;
    const auto stored = body_of(s.get("/v1/floors/" + floor + "/plan"));
    std::map<std::string, int> kinds;
    for (const auto& f : stored.at("features")) ++kinds[f.at("properties").at("feature").get<std::string>()];
    EXPECT_EQ(kinds["space"], 7);
    EXPECT_EQ(kinds["door"], 6);
    EXPECT_GT(kinds["wall"], 7);

    const auto local = with({"--walls", "plan"});
    const auto rooms = with({});
    ASSERT_EQ(local.status, 0) << local.err;
    ASSERT_EQ(rooms.status, 0) << rooms.err;
    std::map<std::string, double> on_plan, on_rooms;
    for (const auto& o : json::parse(local.out)) on_plan[o.at("method")] = o.at("mean_error_m");
    for (const auto& o : json::parse(rooms.out)) on_rooms[o.at("method")] = o.at("mean_error_m");
    for (const auto& o : json::parse(put.out)) {
        EXPECT_EQ(o.at("walls"), "server");
        EXPECT_DOUBLE_EQ(o.at("mean_error_m").get<double>(), on_plan.at(o.at("method"))) << o.at("method");
    }
    // Rules ignore the map; the Kalman filter is map-matched on a plan only.
    EXPECT_DOUBLE_EQ(on_plan.at("proportional"), on_rooms.at("proportional"));
    EXPECT_NE(on_plan.at("kalman"), on_rooms.at("kalman"));
}

// `--live`: the fused track goes to the server as a live track, its fixes in time order on the
// radio map's floor, and is closed at the end.
TEST(Replay, LivePostsTheFusedTrackAsALiveTrack) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string walk = s.dir() + "/walk.jsonl";
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "sim", "--scenario", "basement", "--seed", "2", "--out", walk}).status, 0);
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap", std::to_string(h.radiomap), "--rule",
                                "proportional", "--upload-survey", "--live", s.url(), "--live-map", std::to_string(h.map),
                                "--live-speed", "0", walk});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    const auto id = out.at("live_track").at("id").get<std::int64_t>();
    httplib::Client c("127.0.0.1", s.port());
    const auto got = c.Get("/v1/tracks/" + std::to_string(id) + "?limit=1000",
                           httplib::Headers{{"X-Track-Token", out["live_track"]["token"].get<std::string>()}});
    ASSERT_TRUE(got);
    ASSERT_EQ(got->status, 200) << got->body;
    const json track = json::parse(got->body);
    EXPECT_EQ(track["state"], "closed");
    std::size_t points = 0;
    for (const auto& t : out["tracks"])
        if (t["method"] == "proportional") points = t["points"].size();
    EXPECT_EQ(track["fixes"].get<std::size_t>(), points);
    ASSERT_FALSE(track["trail"].empty());
    EXPECT_EQ(track["trail"][0]["floor_id"], h.floor);
    EXPECT_EQ(run_command({LOCUS_CLI_BIN, "replay", "--server", s.url(), "--radiomap", "1", "--live", s.url(), walk}).status == 0, false);
}

}  // namespace
}  // namespace replay_test
