// The ranging localize's cached transmitters follow every write over HTTP: a moved, an added
// and a deleted transmitter change the next answer on the same running server.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_ranging_cache_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

struct Ap {
    std::string bssid;
    double x, y;
};
double rss(const Ap& a, double x, double y) { return -40 - 20 * std::log10(std::max(std::hypot(x - a.x, y - a.y), 0.1)); }

TEST(RangingCache, AnswersFollowTransmitterWrites) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);  // floor 30 m × 20 m
    const Ap aps[] = {{"02:00:00:00:60:01", 2, 2}, {"02:00:00:00:60:02", 28, 2}, {"02:00:00:00:60:03", 15, 18},
                      {"02:00:00:00:60:04", 2, 18}};
    const std::string col = "/v1/floors/" + std::to_string(h.floor) + "/transmitters";
    std::int64_t ids[4] = {};
    for (int i = 0; i < 3; ++i)
        ids[i] = body_of(s.post(col, {{"type", "wifi"}, {"bssid", aps[i].bssid}, {"x", aps[i].x}, {"y", aps[i].y}, {"tx_power", -40.0}}), 201)
                     .at("id")
                     .get<std::int64_t>();
    json ms = json::array();
    for (const auto& a : aps) ms.push_back({{"bssid", a.bssid}, {"rss", rss(a, 12, 9)}});
    const std::string path = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize";
    const json body = {{"algorithm", "multilateration"}, {"measurements", ms}};
    json a = body_of(s.post(path, body));
    EXPECT_EQ(a.at("transmitters_heard"), 3);
    EXPECT_NEAR(a.at("x").get<double>(), 12, 0.01);

    // Added: now four are heard.
    ids[3] = body_of(s.post(col, {{"type", "wifi"}, {"bssid", aps[3].bssid}, {"x", aps[3].x}, {"y", aps[3].y}, {"tx_power", -40.0}}), 201)
                 .at("id")
                 .get<std::int64_t>();
    EXPECT_EQ(body_of(s.post(path, body)).at("transmitters_heard"), 4);
    // Moved: the same scan no longer fits (12, 9) exactly.
    body_of(s.patch("/v1/transmitters/" + std::to_string(ids[0]), {{"x", 20.0}, {"y", 10.0}}));
    a = body_of(s.post(path, body));
    EXPECT_GT(std::hypot(a.at("x").get<double>() - 12, a.at("y").get<double>() - 9), 0.5) << a.dump();
    // Deleted: three heard again.
    EXPECT_EQ(s.del("/v1/transmitters/" + std::to_string(ids[0])).status, 204);
    EXPECT_EQ(body_of(s.post(path, body)).at("transmitters_heard"), 3);
}

}  // namespace
}  // namespace server_ranging_cache_test
