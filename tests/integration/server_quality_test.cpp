// GET /v1/radiomaps/{id}/quality against the real server: an RP whose scans were taken
// elsewhere (its fingerprint is another place's) stands out with the largest held-out error,
// every RP is listed with its position, and bad input is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hierarchy.hpp"
#include "server_process.hpp"

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

namespace {

// Two APs at the ends of a 20 m line; a few scans a place, as a survey would take.
void survey(const ServerProcess& s, std::int64_t rp, double at_x) {
    json scans = json::array();
    for (int i = 0; i < 3; ++i)
        scans.push_back({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -40 - 2.0 * at_x + i}},
                         {{"bssid", "aa:00:00:00:00:02"}, {"rss", -40 - 2.0 * (20 - at_x) - i}}});
    body_of(s.post("/v1/rps/" + std::to_string(rp) + "/scans", {{"scans", scans}}), 200);
}

}  // namespace

TEST(ServerQuality, AnRpSurveyedElsewhereHasTheLargestError) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    std::vector<std::int64_t> ids;
    for (int x = 0; x <= 20; x += 4) {
        ids.push_back(locus::testing::make_rp(s, h.radiomap, "line-" + std::to_string(x), x, 5));
        survey(s, ids.back(), x);
    }
    const auto odd = locus::testing::make_rp(s, h.radiomap, "odd", 28, 18);
    survey(s, odd, 8);  // its scans are the fingerprint of (8, 5)

    const json q = body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/quality"));
    ASSERT_EQ(q["rps"].size(), ids.size() + 1);
    EXPECT_EQ(q["queries"], ids.size() + 1);
    EXPECT_EQ(q["settings"]["source"], "built-in");
    double sum = 0, worst = -1;
    std::int64_t worst_id = 0;
    for (const auto& r : q["rps"]) {
        ASSERT_TRUE(r["error_m"].is_number()) << r.dump();
        const double e = r["error_m"].get<double>();
        sum += e;
        if (e > worst) worst = e, worst_id = r["id"].get<std::int64_t>();
        EXPECT_TRUE(r["floor_ok"].get<bool>());
        EXPECT_DOUBLE_EQ(r["horizontal_m"].get<double>(), e);  // one floor: no penalty
        if (r["id"] == odd) {
            EXPECT_EQ(r["x"], 28.0);
            EXPECT_EQ(r["name"], "odd");
        }
    }
    EXPECT_EQ(worst_id, odd);
    // Placed near (8, 5) among the line's RPs: at least the distance to the line, 13 m.
    EXPECT_GT(worst, 13.0);
    EXPECT_NEAR(q["mean_error_m"].get<double>(), sum / static_cast<double>(q["rps"].size()), 1e-9);
}

TEST(ServerQuality, BadInputIsRefused) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string p = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/quality";
    EXPECT_EQ(s.get("/v1/radiomaps/999/quality").status, 404);
    EXPECT_EQ(s.get(p + "?folds=1").status, 400);
    EXPECT_EQ(s.get(p + "?folds=x").status, 400);
    EXPECT_EQ(s.get(p + "?max_queries=5").status, 400);
    const auto one = s.get(p);  // no RP yet: nothing to hold out
    EXPECT_EQ(one.status, 422);
    EXPECT_EQ(one.body["error"]["code"], "cannot_assess");
    locus::testing::make_rp(s, h.radiomap, "a", 1, 1);
    locus::testing::make_rp(s, h.radiomap, "b", 2, 2);
    EXPECT_EQ(s.get(p).status, 422);  // RPs without a measurement are no scan
}
