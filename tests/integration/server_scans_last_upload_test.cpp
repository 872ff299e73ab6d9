// An RP's last_upload_at over HTTP: set by an applied scan upload, left alone by a repeated
// upload_id, null for an RP no upload reached (created empty, imported).
#include <gtest/gtest.h>

#include <chrono>
#include <ctime>
#include <string>
#include <thread>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_scans_last_upload_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

// UTC now as the store writes it, to whole seconds: ISO-8601 texts of one form compare as
// strings, so [floor(before), floor(after) + 1 s) brackets the server's clock reading.
std::string utc_now(int plus_seconds = 0) {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now()) + plus_seconds;
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
    return buf;
}

json one_scan(const std::string& bssid, double rss) {
    return json::array({json::array({{{"type", "wifi"}, {"bssid", bssid}, {"rss", rss}}})});
}

TEST(ServerScansLastUpload, SetByAnUploadKeptByItsRepeatNullWithout) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const auto rp = locus::testing::make_rp(s, h.radiomap, "rp-1", 1, 1);
    const auto empty = locus::testing::make_rp(s, h.radiomap, "rp-empty", 2, 2);
    const std::string rp_path = "/v1/rps/" + std::to_string(rp);
    EXPECT_TRUE(body_of(s.get(rp_path)).at("last_upload_at").is_null());

    const std::string before = utc_now();
    const json upload = {{"upload_id", "u-1"}, {"scans", one_scan("aa:bb:cc:00:00:01", -50)}};
    body_of(s.post(rp_path + "/scans", upload));
    const std::string after = utc_now(1);
    const json stored = body_of(s.get(rp_path));
    ASSERT_TRUE(stored.at("last_upload_at").is_string()) << stored.dump();
    const auto at = stored.at("last_upload_at").get<std::string>();
    EXPECT_EQ(at.size(), 24u) << at;  // 2026-01-02T03:04:05.678Z
    EXPECT_EQ(at.back(), 'Z');
    EXPECT_GE(at, before);
    EXPECT_LT(at, after);

    // The same upload again changes nothing, the time included, even a second later.
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    const auto repeat = s.post(rp_path + "/scans", upload);
    ASSERT_EQ(repeat.status, 200) << repeat.raw;
    EXPECT_EQ(repeat.body.at("applied"), false);
    EXPECT_EQ(body_of(s.get(rp_path)).at("last_upload_at"), at);

    // A new upload moves it on; a refused one does not.
    body_of(s.post(rp_path + "/scans", {{"upload_id", "u-2"}, {"scans", one_scan("aa:bb:cc:00:00:01", -52)}}));
    const auto later = body_of(s.get(rp_path)).at("last_upload_at").get<std::string>();
    EXPECT_GT(later, at);
    EXPECT_EQ(s.post(rp_path + "/scans", {{"scans", "nope"}}).status / 100, 4);
    EXPECT_EQ(body_of(s.get(rp_path)).at("last_upload_at"), later);

    // Listed too; the RP without scans stays null, and so does an imported copy.
    const json list = body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/rps"));
    for (const auto& item : list.at("items")) {
        if (item.at("id") == rp) {
            EXPECT_EQ(item.at("last_upload_at"), later);
        } else if (item.at("id") == empty) {
            EXPECT_TRUE(item.at("last_upload_at").is_null());
        }
    }
    json doc = body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/export"));
    doc["name"] = "copy";
    const json imported = body_of(s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", doc), 201);
    const json copies = body_of(s.get("/v1/radiomaps/" + std::to_string(imported.at("id").get<long long>()) + "/rps"));
    ASSERT_EQ(copies.at("items").size(), 2u);
    for (const auto& item : copies.at("items")) EXPECT_TRUE(item.at("last_upload_at").is_null()) << item.dump();
    // Not writable: a value sent is ignored.
    const auto patched = s.patch(rp_path, {{"last_upload_at", "2000-01-01T00:00:00.000Z"}});
    EXPECT_EQ(patched.status, 200) << patched.raw;
    EXPECT_EQ(body_of(s.get(rp_path)).at("last_upload_at"), later);
}

}  // namespace
}  // namespace server_scans_last_upload_test
