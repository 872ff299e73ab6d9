// `locus track` against the real server: two PUTMC walks replayed at once as two live tracks
// on one floor (paced, a hundred times real time), each track holding one fix per scan of its walk at
// the walk's true points (y flipped onto the floor), closed after the last fix; a map with
// no floor and a missing walk are refused with a message and nothing posted.
#include <httplib.h>
#include <gtest/gtest.h>

#include <string>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace cli_track_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using locus::testing::run_command;
using nlohmann::json;

const std::string kWalk = std::string(LOCUS_TEST_FIXTURES) + "/putmc/trajs/tiny_walk";

std::int64_t created(const locus::testing::Response& r) { return body_of(r, 201).at("id").get<std::int64_t>(); }

json track(const ServerProcess& s, std::int64_t id, const std::string& token) {
    httplib::Client c("127.0.0.1", s.port());
    c.set_read_timeout(5, 0);
    auto r = c.Get(("/v1/tracks/" + std::to_string(id) + "?limit=1000").c_str(), {{"X-Track-Token", token}});
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, 200) << r->body;
    return json::parse(r->body, nullptr, false);
}

TEST(CliTrack, TwoWalksAtOnceBecomeTwoLiveTracks) {
    ServerProcess s;
    const auto map = created(s.post("/v1/maps", {{"name", "PUT"}}));
    const auto building = created(s.post("/v1/maps/" + std::to_string(map) + "/buildings", {{"name", "CM"}}));
    const double height = 40.0;
    const auto floor = created(s.post("/v1/buildings/" + std::to_string(building) + "/floors",
                                      {{"name", "1"}, {"level", 1}, {"width", 100.0}, {"height", height}}));

    const auto r = run_command({LOCUS_CLI_BIN, "track", "--server", s.url(), "--map", std::to_string(map), "--speed", "100", kWalk, kWalk});
    ASSERT_EQ(r.status, 0) << r.err;
    std::vector<json> lines;
    std::size_t from = 0;
    for (std::size_t nl; (nl = r.out.find('\n', from)) != std::string::npos; from = nl + 1)
        lines.push_back(json::parse(r.out.substr(from, nl - from)));
    ASSERT_EQ(lines.size(), 2u) << r.out;
    EXPECT_NE(lines[0].at("id"), lines[1].at("id"));
    for (const auto& l : lines) {
        EXPECT_EQ(l.at("fixes").get<int>(), 3);  // the fixture walk's three scans
        const json t = track(s, l.at("id").get<std::int64_t>(), l.at("token").get<std::string>());
        EXPECT_EQ(t.at("state"), "closed") << t.dump();
        ASSERT_EQ(t.at("trail").size(), 3u) << t.dump();
        // The last scan is at PUTMC point 2, (68.45, 22.48) with y down: 40 − 22.48 on the floor.
        const auto& last = t.at("latest");
        EXPECT_EQ(last.at("floor_id").get<std::int64_t>(), floor);
        EXPECT_NEAR(last.at("x").get<double>(), 68.45168629973317, 1e-6);
        EXPECT_NEAR(last.at("y").get<double>(), height - 22.48080166395504, 1e-6);
    }
}

TEST(CliTrack, RefusesAMapWithNoFloorAndAMissingWalk) {
    ServerProcess s;
    const auto map = created(s.post("/v1/maps", {{"name", "Empty"}}));
    auto r = run_command({LOCUS_CLI_BIN, "track", "--server", s.url(), "--map", std::to_string(map), "--speed", "0", kWalk});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("no floor"), std::string::npos) << r.err;
    r = run_command({LOCUS_CLI_BIN, "track", "--server", s.url(), "--map", std::to_string(map), "/nonexistent/walk"});
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(r.out, "");
}

}  // namespace
}  // namespace cli_track_test
