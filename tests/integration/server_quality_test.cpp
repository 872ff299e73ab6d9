// GET /v1/radiomaps/{id}/quality against the real server: an RP whose scans were taken
// elsewhere (its fingerprint is another place's) stands out with the largest held-out error,
// every RP is listed with its position, and bad input is refused.
#include <httplib.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_quality_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

// Two APs at the ends of a 20 m line; a few scans a place, as a survey would take.
void survey(const ServerProcess& s, std::int64_t rp, double at_x) {
    json scans = json::array();
    for (int i = 0; i < 3; ++i)
        scans.push_back({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -40 - 2.0 * at_x + i}},
                         {{"bssid", "aa:00:00:00:00:02"}, {"rss", -40 - 2.0 * (20 - at_x) - i}}});
    body_of(s.post("/v1/rps/" + std::to_string(rp) + "/scans", {{"scans", scans}}), 200);
}

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

// An open GET costing up to ~0.4 s of a core: at most two run at a time, the rest are told to
// come back (503 server_busy, Retry-After) rather than queued, and the slots come free again.
TEST(ServerQuality, ABurstIsBoundedNotQueued) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    json rps = json::array();
    for (int i = 0; i < 2500; ++i) {
        const double x = (i % 50) * 0.6, y = (i / 50) * 0.4;
        json ms = json::array();
        for (int ap = 0; ap < 8; ++ap) {
            const double ax = (ap % 4) * 10.0, ay = (ap / 4) * 20.0;
            const double d = std::hypot(x - ax, y - ay) + 1;
            ms.push_back({{"type", "wifi"}, {"bssid", "aa:00:00:00:00:0" + std::to_string(ap)},
                          {"mean", -40 - 20 * std::log10(d)}, {"variance", 4.0}, {"count", 3}});
        }
        rps.push_back({{"name", "rp-" + std::to_string(i)}, {"x", x}, {"y", y}, {"scans", 3}, {"measurements", ms}});
    }
    const json doc = {{"format", "locus-radiomap/1"}, {"name", "dense"}, {"description", ""}, {"rps", rps}};
    const auto id = body_of(s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", doc), 201).at("id");
    const std::string p = "/v1/radiomaps/" + std::to_string(id.get<long long>()) + "/quality?folds=2&max_queries=5000";

    constexpr int kBurst = 8;
    std::vector<int> status(kBurst);
    std::vector<std::string> code(kBurst), retry(kBurst);
    std::atomic<int> ready{0};
    std::vector<std::thread> threads;
    for (int i = 0; i < kBurst; ++i)
        threads.emplace_back([&, i] {
            httplib::Client c("127.0.0.1", s.port());
            c.set_read_timeout(60, 0);
            ++ready;
            while (ready.load() < kBurst) std::this_thread::yield();
            const auto r = c.Get(p);
            if (!r) return;
            status[i] = r->status;
            retry[i] = r->get_header_value("Retry-After");
            if (r->status != 200) code[i] = json::parse(r->body).at("error").at("code").get<std::string>();
        });
    for (auto& t : threads) t.join();
    int ok = 0, busy = 0;
    for (int i = 0; i < kBurst; ++i) {
        if (status[i] == 200) ++ok;
        else {
            EXPECT_EQ(status[i], 503);
            EXPECT_EQ(code[i], "server_busy");
            EXPECT_EQ(retry[i], "1");
            ++busy;
        }
    }
    EXPECT_GE(ok, 1);
    EXPECT_GE(busy, 1) << "8 simultaneous assessments of 2500 RPs all ran: nothing bounds them";
    EXPECT_EQ(s.get(p).status, 200);  // every slot was given back
}

}  // namespace
}  // namespace server_quality_test
