// POST /v1/radiomaps/{id}/densify against the real server: a sparse survey filled between its
// RPs from the floor's transmitters, generated RPs marked, surveyed ones left alone; bad input
// answers 4xx naming the problem and adds nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_densify_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

json rps_of(const ServerProcess& s, std::int64_t rm) {
    return body_of(s.get("/v1/radiomaps/" + std::to_string(rm) + "/rps?limit=1000"));
}

std::string densify(std::int64_t rm) { return "/v1/radiomaps/" + std::to_string(rm) + "/densify"; }

void add_ap(const ServerProcess& s, std::int64_t floor, const std::string& bssid, double x, double y) {
    body_of(s.post("/v1/floors/" + std::to_string(floor) + "/transmitters",
                   {{"type", "wifi"}, {"bssid", bssid}, {"x", x}, {"y", y}, {"tx_power", -40.0}, {"path_loss_exponent", 2.0}}),
            201);
}

TEST(Densify, FillsBetweenTheSurveyWithTheModelAndKeepsSurveyedRps) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);  // floor 30 m × 20 m
    add_ap(s, h.floor, "02:00:00:00:50:01", 0.0, 0.0);
    add_ap(s, h.floor, "02:00:00:00:50:02", 30.0, 20.0);
    for (const auto& [x, y] : {std::pair{2.0, 2.0}, {10.0, 2.0}, {2.0, 8.0}, {10.0, 8.0}})
        locus::testing::make_rp(s, h.radiomap, "survey " + std::to_string(x) + "," + std::to_string(y), x, y);
    const json surveyed_before = rps_of(s, h.radiomap);

    const json d = body_of(s.post(densify(h.radiomap), {{"step", 2.0}, {"sigma_db", 3.0}}));
    // Nodes 2, 4, …, 10 × 2, 4, 6, 8: 20, of which 4 are the surveyed RPs.
    EXPECT_EQ(d.at("surveyed_rps"), 4);
    EXPECT_EQ(d.at("added_rps"), 16);
    EXPECT_EQ(d.at("transmitters"), 2);
    const json after = rps_of(s, h.radiomap);
    ASSERT_EQ(after.at("total"), 20);
    int generated = 0;
    for (const auto& rp : after.at("items")) {
        const double x = rp.at("x").get<double>(), y = rp.at("y").get<double>();
        EXPECT_GE(x, 2.0 - 1e-9);
        EXPECT_LE(x, 10.0 + 1e-9);
        EXPECT_GE(y, 2.0 - 1e-9);
        EXPECT_LE(y, 8.0 + 1e-9);
        if (rp.at("generated") != 1) continue;
        ++generated;
        const json full = body_of(s.get("/v1/rps/" + std::to_string(rp.at("id").get<std::int64_t>())));
        ASSERT_EQ(full.at("measurements").size(), 2u) << full.dump();
        for (const auto& m : full.at("measurements")) {
            const double ax = m.at("bssid") == "02:00:00:00:50:01" ? 0.0 : 30.0, ay = ax == 0.0 ? 0.0 : 20.0;
            EXPECT_NEAR(m.at("mean").get<double>(), -40 - 20 * std::log10(std::hypot(x - ax, y - ay)), 1e-9);
            EXPECT_DOUBLE_EQ(m.at("variance").get<double>(), 9.0);
        }
    }
    EXPECT_EQ(generated, 16);
    // The surveyed RPs are as they were: same rows, not generated, no measurements added.
    for (const auto& before : surveyed_before.at("items")) {
        const json now = body_of(s.get("/v1/rps/" + std::to_string(before.at("id").get<std::int64_t>())));
        EXPECT_EQ(now.at("generated"), 0);
        EXPECT_EQ(now.at("measurements").size(), 0u);
        EXPECT_EQ(now.at("x"), before.at("x"));
    }
    // A second densify finds nothing missing.
    EXPECT_EQ(body_of(s.post(densify(h.radiomap), {{"step", 2.0}})).at("added_rps"), 0);
    EXPECT_EQ(rps_of(s, h.radiomap).at("total"), 20);
}

// The fill's box is the survey's, widened by half a step: with RPs on the floor's edges it had
// put modelled RPs outside the building.
TEST(Densify, StaysOnTheFloor) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);  // floor 30 m × 20 m
    add_ap(s, h.floor, "02:00:00:00:50:01", 15.0, 10.0);
    locus::testing::make_rp(s, h.radiomap, "corner", 0.0, 0.0);
    locus::testing::make_rp(s, h.radiomap, "far corner", 30.0, 20.0);
    EXPECT_GT(body_of(s.post(densify(h.radiomap), {{"step", 3.0}})).at("added_rps").get<int>(), 0);
    const json rps = rps_of(s, h.radiomap);  // kept: a range-for over a temporary's member dangles
    for (const auto& rp : rps.at("items")) {
        EXPECT_GE(rp.at("x").get<double>(), 0.0) << rp.dump();
        EXPECT_LE(rp.at("x").get<double>(), 30.0) << rp.dump();
        EXPECT_GE(rp.at("y").get<double>(), 0.0) << rp.dump();
        EXPECT_LE(rp.at("y").get<double>(), 20.0) << rp.dump();
    }
}

TEST(Densify, BadRequestsNameTheProblemAndAddNothing) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    locus::testing::make_rp(s, h.radiomap, "a", 1, 1);
    auto refused = [&](std::int64_t rm, const json& body, int status, const std::string& code, const std::string& words) {
        const auto before = rps_of(s, h.radiomap).at("total");
        const auto r = s.post(densify(rm), body);
        EXPECT_EQ(r.status, status) << body.dump() << " -> " << r.raw;
        if (r.status == status) {
            EXPECT_EQ(r.body.at("error").at("code"), code) << r.raw;
            EXPECT_NE(r.body.at("error").at("message").get<std::string>().find(words), std::string::npos) << r.raw;
        }
        EXPECT_EQ(rps_of(s, h.radiomap).at("total"), before);
    };
    refused(h.radiomap, json::object(), 422, "invalid_field", "step");
    refused(h.radiomap, {{"step", 2.0}}, 422, "too_few_rps", "has 1 RP");
    locus::testing::make_rp(s, h.radiomap, "b", 29, 19);
    refused(h.radiomap, {{"step", 2.0}}, 422, "no_transmitters", "no transmitters");
    add_ap(s, h.floor, "02:00:00:00:50:01", 0.0, 0.0);
    refused(h.radiomap, {{"step", 0.0}}, 422, "out_of_range", "step");
    refused(h.radiomap, {{"step", "2"}}, 422, "invalid_field", "step");
    refused(h.radiomap, {{"step", 1e9}}, 422, "out_of_range", "step");
    refused(h.radiomap, {{"step", 2.0}, {"colour", 1}}, 422, "invalid_field", "colour");
    refused(h.radiomap, {{"step", 2.0}, {"sigma_db", -1.0}}, 422, "out_of_range", "sigma_db");
    refused(999999, {{"step", 2.0}}, 404, "not_found", "999999");
    const auto r = s.post(densify(h.radiomap), json::array({2.0}));
    EXPECT_GE(r.status, 400) << r.raw;
    EXPECT_LT(r.status, 500) << r.raw;
}

}  // namespace
}  // namespace server_densify_test
