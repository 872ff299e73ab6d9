// End to end: a simulated walk replayed against a real local server gives fixes from the
// server's matcher, and the same figures as the in-process evaluation of that walk.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "hierarchy.hpp"
#include "server_process.hpp"

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

    ASSERT_EQ(out.at("tracks").size(), expected.size());
    for (const auto& t : out.at("tracks")) {
        const std::string method = t.at("method");
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
