// The store keeps its record through a kill -9 in the middle of concurrent uploads: every
// acknowledged upload is there after the restart, none is applied twice when clients retry.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_durability_test {
namespace {

using locus::testing::ServerProcess;
using nlohmann::json;

struct Upload {
    std::string id;
    std::int64_t rp = 0;
};

json one_scan_upload(const Upload& u) {
    return {{"upload_id", u.id}, {"scans", json::array({json::array({{{"bssid", "aa:bb:cc:00:00:01"}, {"rss", -60}}})})}};
}

TEST(Durability, AcknowledgedUploadsSurviveKill9AndRetriesApplyOnce) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    std::vector<std::int64_t> rps;
    for (int i = 0; i < 4; ++i) rps.push_back(locus::testing::make_rp(s, h.radiomap, "rp" + std::to_string(i), i, i));

    std::mutex mu;
    std::vector<Upload> acknowledged, attempted;
    std::atomic<bool> stop{false};
    std::vector<std::thread> clients;
    for (int t = 0; t < 4; ++t) {
        clients.emplace_back([&, t] {
            for (int i = 0; !stop && i < 100000; ++i) {
                // Built by appending: GCC 12 misfires -Wrestrict on `literal + std::string + literal`.
                Upload u{std::to_string(t), rps[static_cast<std::size_t>((t + i) % 4)]};
                u.id.append("-").append(std::to_string(i));
                {
                    std::lock_guard lock(mu);
                    attempted.push_back(u);
                }
                const auto r = s.post("/v1/rps/" + std::to_string(u.rp) + "/scans", one_scan_upload(u));
                if (r.status != 200) break;  // the server is gone
                std::lock_guard lock(mu);
                acknowledged.push_back(u);
            }
        });
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    s.kill9();
    stop = true;
    for (auto& c : clients) c.join();
    ASSERT_GT(acknowledged.size(), 20u) << "too few uploads before the kill to say anything";

    s.start();
    // Every acknowledged upload is stored: sent again, it is recognised and not applied.
    for (const auto& u : acknowledged) {
        const auto r = s.post("/v1/rps/" + std::to_string(u.rp) + "/scans", one_scan_upload(u));
        ASSERT_EQ(r.status, 200) << r.raw;
        EXPECT_FALSE(r.body.at("applied").get<bool>()) << u.id << " was acknowledged but lost";
    }
    // Clients retry what had no answer; each upload then counts exactly once.
    std::map<std::int64_t, std::set<std::string>> per_rp;
    for (const auto& u : attempted) {
        ASSERT_EQ(s.post("/v1/rps/" + std::to_string(u.rp) + "/scans", one_scan_upload(u)).status, 200);
        per_rp[u.rp].insert(u.id);
    }
    for (const auto rp : rps) {
        const json got = s.get("/v1/rps/" + std::to_string(rp)).body;
        const auto expected = static_cast<std::int64_t>(per_rp[rp].size());
        EXPECT_EQ(got.at("scans").get<std::int64_t>(), expected) << "rp " << rp;
        ASSERT_EQ(got.at("measurements").size(), 1u);
        EXPECT_EQ(got.at("measurements")[0].at("count").get<std::int64_t>(), expected) << "rp " << rp;
    }
}

}  // namespace
}  // namespace server_durability_test
