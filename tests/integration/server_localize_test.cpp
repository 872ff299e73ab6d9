// Localization over HTTP: a small radio map imported through the API, answers with room and
// candidates, the index following writes, whole-map floor detection, and bad requests.
#include <gtest/gtest.h>
#include <httplib.h>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_localize_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

json m(const std::string& bssid, double mean) {
    return {{"type", "wifi"}, {"bssid", bssid}, {"mean", mean}, {"variance", 4.0}, {"count", 10}};
}

// Three RPs along a corridor, each strongest on "its" AP.
json corridor(const std::string& name, double offset) {
    return {{"name", name},
            {"rps",
             {{{"name", "west"}, {"x", 2.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -40 + offset), m("aa:00:00:00:00:02", -70 + offset)}}},
              {{"name", "middle"}, {"x", 10.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -60 + offset), m("aa:00:00:00:00:02", -60 + offset)}}},
              {{"name", "east"}, {"x", 18.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -70 + offset), m("aa:00:00:00:00:02", -40 + offset)}}}}}};
}

json scan(double ap1, double ap2) {
    return {{"scans", json::array({json::array({{{"bssid", "AA:00:00:00:00:01"}, {"rss", ap1}}, {{"bssid", "aa:00:00:00:00:02"}, {"rss", ap2}}})})}};
}

struct Localize : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::int64_t rm = 0;
    std::string path;
    void SetUp() override {
        ASSERT_EQ(s.post("/v1/floors/" + std::to_string(h.floor) + "/rooms",
                         {{"name", "West wing"}, {"rects", {{{"xmin", 0}, {"ymin", 0}, {"xmax", 6}, {"ymax", 10}}}}})
                      .status,
                  201);
        const auto r = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", corridor("corridor", 0));
        ASSERT_EQ(r.status, 201) << r.raw;
        rm = r.body.at("id").get<std::int64_t>();
        path = "/v1/radiomaps/" + std::to_string(rm) + "/localize";
    }
};

TEST_F(Localize, AnswersTheNearestRpWithRoomAndCandidates) {
    json body = scan(-41, -69);
    body["algorithm"] = "nn";
    const auto r = s.post(path, body);
    ASSERT_EQ(r.status, 200) << r.raw;
    EXPECT_DOUBLE_EQ(r.body.at("x").get<double>(), 2.0);
    EXPECT_DOUBLE_EQ(r.body.at("y").get<double>(), 5.0);
    EXPECT_EQ(r.body.at("floor_id"), h.floor);
    EXPECT_EQ(r.body.at("building_id"), h.building);
    EXPECT_EQ(r.body.at("room").at("name"), "West wing");
    EXPECT_EQ(r.body.at("algorithm"), "nn");
    EXPECT_EQ(r.body.at("matched_aps"), 2);
    EXPECT_NEAR(r.body.at("score").get<double>(), std::sqrt(2.0), 1e-9);  // sqrt(1² + 1²), no penalty
    ASSERT_EQ(r.body.at("candidates").size(), 3u);
    EXPECT_EQ(r.body.at("rps").size(), 1u);
}

TEST_F(Localize, TheAnswerIsJsonWithOneContentType) {
    httplib::Client c("127.0.0.1", s.port());
    const auto r = c.Post(path.c_str(), scan(-41, -69).dump(), "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_EQ(r->get_header_value_count("Content-Type"), 1u);
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/json");
    EXPECT_EQ(r->get_header_value("Content-Length"), std::to_string(r->body.size()));
    EXPECT_EQ(json::parse(r->body).at("algorithm"), "bayes");  // the default
}

TEST_F(Localize, EveryAlgorithmAnswersTheObviousCase) {
    for (const char* algorithm : {"bsb", "nn", "bsbnn", "knn", "wknn", "bayes"}) {
        json body = scan(-70, -40);
        body["algorithm"] = algorithm;
        body["options"] = {{"k", 1}};
        const auto r = s.post(path, body);
        ASSERT_EQ(r.status, 200) << algorithm << ": " << r.raw;
        if (std::string(algorithm) == "bsb") {
            // Every RP shares both APs: BSB ties them all and answers their centroid.
            EXPECT_EQ(r.body.at("rps").size(), 3u);
            EXPECT_NEAR(r.body.at("x").get<double>(), 10.0, 1e-9);
        } else {
            EXPECT_NEAR(r.body.at("x").get<double>(), 18.0, 1e-9) << algorithm;
        }
        EXPECT_TRUE(r.body.at("room").is_null()) << "x=18 is outside every room";
    }
}

TEST_F(Localize, TheIndexFollowsWrites) {
    json body = scan(-41, -69);
    body["algorithm"] = "nn";
    ASSERT_DOUBLE_EQ(body_of(s.post(path, body)).at("x").get<double>(), 2.0);

    const auto rps = body_of(s.get("/v1/radiomaps/" + std::to_string(rm) + "/rps")).at("items");
    ASSERT_EQ(rps[0].at("name"), "west");
    ASSERT_EQ(s.del("/v1/rps/" + std::to_string(rps[0].at("id").get<long long>())).status, 204);
    auto after = s.post(path, body);
    ASSERT_EQ(after.status, 200);
    EXPECT_DOUBLE_EQ(after.body.at("x").get<double>(), 10.0) << "the deleted RP must not be answered";
    EXPECT_EQ(after.body.at("candidates").size(), 2u);

    // A new RP with an upload becomes the answer at once.
    const auto fresh = locus::testing::make_rp(s, rm, "far-west", 0.5, 5.0);
    ASSERT_EQ(s.post("/v1/rps/" + std::to_string(fresh) + "/scans", scan(-41, -69)).status, 200);
    EXPECT_DOUBLE_EQ(body_of(s.post(path, body)).at("x").get<double>(), 0.5);
}

TEST_F(Localize, WholeMapPicksTheFloor) {
    const auto upper = s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                              {{"name", "Upper"}, {"level", 1}, {"width", 30.0}, {"height", 20.0}});
    ASSERT_EQ(upper.status, 201);
    const auto upper_id = upper.body.at("id").get<long long>();
    // The same APs heard 20 dB weaker upstairs.
    ASSERT_EQ(s.post("/v1/floors/" + std::to_string(upper_id) + "/radiomaps/import", corridor("upper", -20)).status, 201);
    json body = scan(-61, -89);
    body["algorithm"] = "nn";
    const auto r = s.post("/v1/maps/" + std::to_string(h.map) + "/localize", body);
    ASSERT_EQ(r.status, 200) << r.raw;
    EXPECT_EQ(r.body.at("floor_id"), upper_id);
    EXPECT_DOUBLE_EQ(r.body.at("x").get<double>(), 2.0);
    body = scan(-41, -69);
    body["algorithm"] = "nn";
    EXPECT_EQ(body_of(s.post("/v1/maps/" + std::to_string(h.map) + "/localize", body)).at("floor_id"), h.floor);
}

TEST_F(Localize, NearRestrictsCandidates) {
    json body = scan(-41, -69);
    body["algorithm"] = "nn";
    body["options"] = {{"near", {{"x", 18.0}, {"y", 5.0}, {"radius", 9.0}}}};
    const auto r = s.post(path, body);
    ASSERT_EQ(r.status, 200) << r.raw;
    EXPECT_DOUBLE_EQ(r.body.at("x").get<double>(), 10.0);
    body["options"] = {{"near", {{"x", 100.0}, {"y", 100.0}, {"radius", 1.0}}}};
    const auto none = s.post(path, body);
    EXPECT_EQ(none.status, 422);
    EXPECT_EQ(none.body["error"]["code"], "no_match");
}

TEST_F(Localize, AScanSharingNoApIsANoMatchNotAPosition) {
    const auto r = s.post(path, {{"scans", json::array({json::array({{{"bssid", "ff:ff:ff:ff:ff:ff"}, {"rss", -50}}})})}});
    EXPECT_EQ(r.status, 422);
    EXPECT_EQ(r.body["error"]["code"], "no_match");
    EXPECT_FALSE(r.body.contains("x"));
}

TEST_F(Localize, MeasurementsAreAcceptedAsMeans) {
    const auto r = s.post(path, {{"algorithm", "nn"},
                                 {"measurements", {{{"bssid", "aa:00:00:00:00:01"}, {"rss", -60}}, {{"bssid", "aa:00:00:00:00:02"}, {"mean", -61}}}}});
    ASSERT_EQ(r.status, 200) << r.raw;
    EXPECT_DOUBLE_EQ(r.body.at("x").get<double>(), 10.0);
}

TEST_F(Localize, EveryOptionIsAccepted) {
    json body = scan(-70, -40);
    body["algorithm"] = "bayes";
    body["options"] = {{"k", 2}, {"tolerance", 0.1}, {"gamma", 3}, {"representation", "positive"}, {"distance", "manhattan"},
                       {"sigma_floor", 4}, {"estimate", "map"}, {"temperature", 2}, {"offset_sigma", 0}, {"outlier_sigmas", 3}, {"bayes_k", 2},
                       {"floor_temperature", 1}, {"floor_knn", 2}, {"floor_knn_weight", 0.5}, {"floor_knn_position", false}, {"floor_aps", 0},
                       {"floor_ap_weight", 0.2}, {"candidates", 2}, {"near", {{"x", 18}, {"y", 5}, {"radius", 50}}}};
    const auto r = s.post(path, body);
    ASSERT_EQ(r.status, 200) << r.raw;
    EXPECT_EQ(r.body.at("candidates").size(), 2u);
    EXPECT_DOUBLE_EQ(r.body.at("x").get<double>(), 18.0);  // MAP estimate: the single best RP
}

// AP 2 reads 0 dBm, a glitch: every RP stores it at -40 dBm or weaker. σ = 5 dB (the 4 dB²
// variance raised to sigma_floor), no offset estimate. Squared standardised residuals
// (AP 1, AP 2): west (0.04, 196), middle (14.44, 144), east (33.64, 64). Uncapped, east has
// the smallest sum; capped at 5σ (25 each), west (25.04) beats middle (39.44) and east (50).
TEST_F(Localize, OutlierCapStopsOneGlitchedReadingFromDecidingTheAnswer) {
    for (const auto& [cap, x] : {std::pair{0.0, 18.0}, std::pair{5.0, 2.0}}) {
        json body = scan(-41, 0);
        body["algorithm"] = "bayes";
        body["options"] = {{"outlier_sigmas", cap}, {"offset_sigma", 0}, {"estimate", "map"}, {"sigma_floor", 5}};
        const auto r = s.post(path, body);
        ASSERT_EQ(r.status, 200) << r.raw;
        EXPECT_DOUBLE_EQ(r.body.at("x").get<double>(), x) << "outlier_sigmas " << cap;
    }
}

TEST_F(Localize, BadRequestsAreRefused) {
    auto expect = [&](const json& body, int status, const std::string& code) {
        const auto r = s.post(path, body);
        EXPECT_EQ(r.status, status) << body.dump() << " -> " << r.raw;
        EXPECT_EQ(r.body["error"]["code"], code) << body.dump();
    };
    expect({{"algorithm", "magic"}, {"scans", scan(-50, -50)["scans"]}}, 422, "invalid_field");
    expect({{"algorithm", "nn"}}, 422, "invalid_field");
    expect({{"scans", json::array()}}, 422, "invalid_field");
    expect({{"scans", scan(-50, 20)["scans"]}}, 422, "out_of_range");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"k", 0}}}}, 422, "out_of_range");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"k", "three"}}}}, 422, "invalid_field");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"distance", "chebyshev"}}}}, 422, "invalid_field");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"near", {{"x", 1}, {"y", 1}, {"radius", -2}}}}}}, 422, "out_of_range");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"speed", 3}}}}, 422, "invalid_field");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"floor_ap_weight", 2}}}}, 422, "out_of_range");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"bayes_k", -1}}}}, 422, "out_of_range");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"outlier_sigmas", -1}}}}, 422, "out_of_range");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", {{"floor_knn_position", "no"}}}}, 422, "invalid_field");
    expect({{"scans", scan(-50, -50)["scans"]}, {"options", 7}}, 422, "invalid_field");
    expect({{"scans", scan(-50, -50)["scans"]}, {"algorithm", 7}}, 422, "invalid_field");
    expect({{"scans", {{{"bssid", "aa"}}}}}, 422, "invalid_field");
    expect({{"scans", json::array({json::object()})}}, 422, "invalid_field");
    expect({{"measurements", {{{"bssid", "aa"}, {"rss", -50}, {"variance", 1}}}}}, 422, "invalid_field");
    const auto raw = s.post_raw(path, "{\"scans\": [[{\"bssid\": \"aa\", \"rss\": NaN}]]}");
    EXPECT_EQ(raw.status, 400);
}

}  // namespace
}  // namespace server_localize_test
