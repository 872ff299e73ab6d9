// `locus plan from-image|import|export` and `locus route` as a user runs them: the real
// binaries, a real server on loopback with a temp database. The drawing of the PUT Mobile
// Computing floor (LOCUS_DATA_DIR/putmc, skipped when absent) must come out as a plan whose
// corridors join every surveyed point.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <filesystem>
#include <map>
#include <fstream>
#include <queue>
#include <sstream>

#include "hierarchy.hpp"
#include "locus/plan/check.hpp"
#include "locus/plan/geojson.hpp"
#include "locus/plan/route.hpp"
#include "locus/plan/walk_grid.hpp"
#include "plan_geojson.hpp"
#include "server_process.hpp"
#include "text_file.hpp"
#include "build_paths.hpp"

namespace cli_plan_test {
namespace {

using locus::testing::body_of;
using locus::testing::feature;
using locus::testing::line;
using locus::testing::make_temp_dir;
using locus::testing::point;
using locus::testing::polygon;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;
namespace plan = locus::plan;

using locus::testing::slurp;
using locus::testing::contains;

const std::string kData = LOCUS_DATA_DIR;

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A lab and a corridor with a door between them.
json two_rooms() {
    return {{"type", "FeatureCollection"},
            {"features",
             {feature("space", polygon({{0, 0}, {5, 0}, {5, 4}, {0, 4}, {0, 0}}), {{"name", "Lab 1"}, {"tags", {"Dr. Rossi"}}}),
              feature("space", polygon({{5, 0}, {10, 0}, {10, 4}, {5, 4}, {5, 0}}), {{"name", "Corridor"}, {"kind", "corridor"}}),
              feature("wall", line({{5, 0}, {5, 4}})), feature("door", point(5, 2), {{"name", "Lab 1 door"}})}}};
}

std::string plan_path(std::int64_t floor) { return "/v1/floors/" + std::to_string(floor) + "/plan"; }

TEST(CliPlan, ImportThenExportGivesThePlanBackAndImportTakesTheExportUnchanged) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string dir = make_temp_dir(), file = dir + "/plan.geojson", out = dir + "/out.geojson";
    write(file, two_rooms().dump());
    const std::string floor = std::to_string(h.floor);

    auto r = run_command({LOCUS_CLI_BIN, "plan", "import", file, "--floor", floor, "--server", s.url()});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "floor " + floor + ": plan version 1 stored (2 spaces, 1 walls, 1 doors, 0 connectors)")) << r.err;

    r = run_command({LOCUS_CLI_BIN, "plan", "export", "--floor", floor, "--server", s.url(), "--out", out});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "version 1, 4 features")) << r.err;
    const json exported = json::parse(slurp(out));
    EXPECT_EQ(exported, body_of(s.get(plan_path(h.floor))));
    // The same plan as the file, in the codec's normal form, but for the rooms the server
    // made for its named spaces (the plan keeps them in step): each names one now.
    auto stored = plan::from_geojson(exported);
    for (auto& space : stored.spaces) {
        EXPECT_TRUE(space.room_id.has_value()) << space.name;
        space.room_id.reset();
    }
    EXPECT_EQ(plan::to_geojson(stored), plan::to_geojson(plan::from_geojson(two_rooms())));

    // Export to stdout is the same document; importing it stores the same features again.
    r = run_command({LOCUS_CLI_BIN, "plan", "export", "--floor", floor, "--server", s.url()});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(json::parse(r.out), exported);
    r = run_command({LOCUS_CLI_BIN, "plan", "import", out, "--floor", floor, "--server", s.url()});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "plan version 2 stored")) << r.err;
    EXPECT_EQ(body_of(s.get(plan_path(h.floor))).at("features"), exported.at("features"));
}

TEST(CliPlan, ABadFileIsRefusedNamingTheFeatureAndNothingIsWritten) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string dir = make_temp_dir(), floor = std::to_string(h.floor);

    // A ring that crosses itself: the codec reads it, check_plan refuses it, before any request.
    json bowtie = two_rooms();
    bowtie["features"][0]["geometry"] = polygon({{0, 0}, {5, 0}, {5, 4}, {2, -1}, {0, 4}, {0, 0}});
    write(dir + "/bowtie.geojson", bowtie.dump());
    auto r = run_command({LOCUS_CLI_BIN, "plan", "import", dir + "/bowtie.geojson", "--floor", floor, "--server", s.url()});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "spaces[0] 'Lab 1'")) << r.err;
    EXPECT_TRUE(contains(r.err, "intersect")) << r.err;

    // A feature of no known kind: the codec's message names it.
    json odd = two_rooms();
    odd["features"][2]["properties"]["feature"] = "window";
    write(dir + "/odd.geojson", odd.dump());
    r = run_command({LOCUS_CLI_BIN, "plan", "import", dir + "/odd.geojson", "--floor", floor, "--server", s.url()});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "features[2]")) << r.err;

    write(dir + "/text.geojson", "not json");
    r = run_command({LOCUS_CLI_BIN, "plan", "import", dir + "/text.geojson", "--floor", floor, "--server", s.url()});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "is not JSON")) << r.err;
    EXPECT_EQ(s.get(plan_path(h.floor)).status, 404);  // nothing was stored

    // A sound file for a floor that does not exist: the server's answer, plainly.
    write(dir + "/good.geojson", two_rooms().dump());
    r = run_command({LOCUS_CLI_BIN, "plan", "import", dir + "/good.geojson", "--floor", "999", "--server", s.url()});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "the server refused the plan of floor 999 (not_found)")) << r.err;
    r = run_command({LOCUS_CLI_BIN, "plan", "export", "--floor", floor, "--server", s.url()});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "has no plan")) << r.err;
}

TEST(CliRoute, PrintsNumberedStepsLengthAndTime) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    ASSERT_EQ(s.put(plan_path(h.floor), two_rooms()).status, 200);
    const std::string floor = std::to_string(h.floor), map = std::to_string(h.map);
    auto r = run_command({LOCUS_CLI_BIN, "route", "--server", s.url(), "--map", map, "--from", floor + ":1,2", "--to", floor + ":9,2"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "1. ")) << r.out;
    EXPECT_TRUE(contains(r.out, "2. ")) << r.out;
    EXPECT_TRUE(contains(r.out, "total: 8 m, about 6 s")) << r.out;
    // The lines are the server's steps, in order.
    const json answer = body_of(s.post("/v1/maps/" + map + "/route",
                                       {{"from", {{"floor_id", h.floor}, {"x", 1}, {"y", 2}}}, {"to", {{"floor_id", h.floor}, {"x", 9}, {"y", 2}}}}));
    std::string expected;
    int n = 0;
    for (const auto& step : answer.at("steps")) expected += std::to_string(++n) + ". " + step.at("text").get<std::string>() + "\n";
    EXPECT_EQ(r.out.substr(0, expected.size()), expected);

    r = run_command({LOCUS_CLI_BIN, "route", "--server", s.url(), "--map", map, "--from", floor + ":1,2", "--to", floor + ":9,2", "--json"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(json::parse(r.out).at("steps"), answer.at("steps"));

    // Off the plan: the server's no_route message, and a non-zero exit.
    r = run_command({LOCUS_CLI_BIN, "route", "--server", s.url(), "--map", map, "--from", floor + ":1,2", "--to", floor + ":60,50"});
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(contains(r.err, "no route: ")) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CliRoute, TheReadmesRouteOnTheDemoMap) {
    // README, first minutes: the ground floor's Lab is room 4, the first floor's Server room 8.
    ServerProcess s{{"--demo"}};
    EXPECT_EQ(body_of(s.get("/v1/rooms/4")).at("name"), "Lab");
    EXPECT_EQ(body_of(s.get("/v1/rooms/8")).at("name"), "Server room");
    auto r = run_command({LOCUS_CLI_BIN, "route", "--server", s.url(), "--map", "1", "--from", "room:4", "--to", "room:8"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.out, ". Take the stairs up to level 1\n")) << r.out;
    r = run_command({LOCUS_CLI_BIN, "route", "--server", s.url(), "--map", "1", "--from", "room:4", "--to", "room:8", "--step-free"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.out, ". Take the elevator up to level 1\n")) << r.out;
    EXPECT_TRUE(contains(r.out, "\ntotal: ")) << r.out;
}

TEST(CliRoute, APlaceItCannotReadIsNamedWithTheFormsItTakes) {
    const std::string url = "http://127.0.0.1:1";  // never reached: the place is read first
    for (const std::string bad : {"lobby", "room:", "room:x", "poi:-3", "3:1", "3:1,", "3:a,b", "0:1,2", "hall:2", "3:1,2,3"}) {
        const auto r = run_command({LOCUS_CLI_BIN, "route", "--server", url, "--map", "1", "--from", bad, "--to", "room:1"});
        EXPECT_NE(r.status, 0) << bad;
        EXPECT_TRUE(contains(r.err, "--from '" + bad + "'")) << r.err;
        EXPECT_TRUE(contains(r.err, "a place is room:ID, poi:ID or FLOOR_ID:X,Y")) << r.err;
    }
}

// ---- the real drawing -------------------------------------------------------------------

struct SurveyPoint {
    int id;
    double x, y;  // metres in the image's frame: x right, y down from the top-left
};

TEST(CliPlanFromImage, ThePutmcDrawingGivesACheckedPlanWhoseCorridorsJoinEverySurveyedPoint) {
    const std::string dir_in = kData + "/putmc/map";
    if (!std::filesystem::exists(dir_in + "/floorplan.png"))
        GTEST_SKIP() << dir_in << "/floorplan.png not found: the shared data folder is absent";
    const double px_per_m = std::stod(slurp(dir_in + "/scale.map"));
    std::vector<SurveyPoint> survey;
    {
        std::ifstream in(dir_in + "/positions.map");
        SurveyPoint p{};
        while (in >> p.id >> p.x >> p.y) survey.push_back(p);
    }
    ASSERT_EQ(survey.size(), 114u);

    const std::string out = make_temp_dir() + "/putmc.geojson";
    std::ostringstream scale;
    scale.precision(12);
    scale << px_per_m;
    const auto r = run_command({LOCUS_CLI_BIN, "plan", "from-image", dir_in + "/floorplan.png", "--px-per-m", scale.str(), "--out", out});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "3049 × 1049 px")) << r.err;
    // As it is, the server takes it.
    {
        ServerProcess s;
        const auto h = locus::testing::make_hierarchy(s);
        const auto imported = run_command({LOCUS_CLI_BIN, "plan", "import", out, "--floor", std::to_string(h.floor), "--server", s.url()});
        EXPECT_EQ(imported.status, 0) << imported.err;
        EXPECT_TRUE(contains(imported.err, "plan version 1 stored")) << imported.err;
    }
    const plan::Plan p = plan::from_geojson(json::parse(slurp(out)));
    const auto problems = plan::check_plan(p);
    EXPECT_TRUE(problems.empty()) << problems.front().feature << ": " << problems.front().problem;
    EXPECT_GE(p.spaces.size(), 1u);
    EXPECT_GE(p.walls.size(), 100u);

    // Survey points into plan metres (y up from the image's bottom edge), snapped to the walk
    // grid, all in one 8-connected component of legal moves.
    const double height_m = 1049.0 / px_per_m;
    const auto grid = plan::build_walk_grid(p);
    std::vector<int> component(static_cast<std::size_t>(grid.cell_count()), -1);
    int components = 0;
    for (int c = 0; c < grid.cell_count(); ++c) {
        if (!grid.free(c) || component[static_cast<std::size_t>(c)] >= 0) continue;
        std::queue<int> q;
        q.push(c);
        component[static_cast<std::size_t>(c)] = components;
        while (!q.empty()) {
            const int u = q.front();
            q.pop();
            for (int d = 0; d < 8; ++d) {
                if (!(grid.moves[static_cast<std::size_t>(u)] & (1u << d))) continue;
                const int v = u + plan::kDirRow[d] * grid.cols + plan::kDirCol[d];
                if (component[static_cast<std::size_t>(v)] < 0) component[static_cast<std::size_t>(v)] = components, q.push(v);
            }
        }
        ++components;
    }
    auto to_plan = [&](const SurveyPoint& s) { return locus::Point{s.x, height_m - s.y}; };
    std::map<int, int> per_component;
    for (const auto& s : survey) {
        const int cell = grid.snap(to_plan(s), nullptr, false);
        EXPECT_GE(cell, 0) << "survey point " << s.id << " is not within " << plan::kSnapRadius << " m of free space";
        if (cell >= 0) ++per_component[component[static_cast<std::size_t>(cell)]];
    }
    EXPECT_EQ(per_component.size(), 1u) << "the survey points fall into " << per_component.size() << " separate parts";

    // Routes between far-apart points exist and are no shorter than the straight line. A route
    // starting inside a space may not reach the grid through a wall (route.hpp), and a few
    // survey points were recorded on a wall line, inside the outline of its stroke: those are
    // counted (a handful at most) and routes run between the snapped cells, as a phone's
    // position would be snapped.
    std::vector<plan::FloorSpec> floors{{1, 0, p}};
    const auto building = plan::build_building(std::move(floors));
    int on_walls = 0;
    for (const auto& s : survey)
        if (plan::route(building, {1, to_plan(s)}, {1, to_plan(s)}).status == plan::RouteStatus::start_off_plan) ++on_walls;
    EXPECT_LE(on_walls, 2) << "survey points a route cannot start from";
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t i = 0; i < survey.size(); ++i)
        for (std::size_t j = i + 1; j < survey.size(); ++j) pairs.push_back({i, j});
    auto far = [&](const std::pair<std::size_t, std::size_t>& a) {
        return std::hypot(survey[a.first].x - survey[a.second].x, survey[a.first].y - survey[a.second].y);
    };
    std::sort(pairs.begin(), pairs.end(), [&](const auto& a, const auto& b) { return far(a) > far(b); });
    auto snapped = [&](const SurveyPoint& s) { return grid.centre(grid.snap(to_plan(s), nullptr, false)); };
    for (std::size_t k = 0; k < 10; ++k) {
        const auto [i, j] = pairs[k * 7];  // ten of the farthest pairs, not all with the same ends
        const auto a = snapped(survey[i]), b = snapped(survey[j]);
        const auto route = plan::route(building, {1, a}, {1, b});
        ASSERT_EQ(route.status, plan::RouteStatus::ok) << survey[i].id << " → " << survey[j].id << ": " << plan::to_string(route.status);
        EXPECT_GE(route.length_m, std::hypot(b.x - a.x, b.y - a.y) - 1e-6);
        EXPECT_GE(route.length_m, 40.0) << survey[i].id << " → " << survey[j].id;
    }
}

}  // namespace
}  // namespace cli_plan_test
