// A radio map's export carries its floor's transmitters and the import recreates them on the
// target floor (a building moved to another server keeps its calibrated models), against the
// real server; bad transmitters in a document refuse the whole import.
#include <gtest/gtest.h>

#include <string>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_transmitter_export_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

json tx_list(const ServerProcess& s, std::int64_t floor) {
    return body_of(s.get("/v1/floors/" + std::to_string(floor) + "/transmitters?limit=1000"));
}

std::string import_path(std::int64_t floor) { return "/v1/floors/" + std::to_string(floor) + "/radiomaps/import"; }

TEST(TransmitterExport, RoundTripsToAnotherFloorAndKeepsWhatIsThere) {
    ServerProcess s;
    const auto from = locus::testing::make_hierarchy(s, "Old site");
    const auto to = locus::testing::make_hierarchy(s, "New site");
    locus::testing::make_rp(s, from.radiomap, "p1", 2, 3);
    const std::string col = "/v1/floors/" + std::to_string(from.floor) + "/transmitters";
    body_of(s.post(col, {{"name", "AP lobby"}, {"type", "wifi"}, {"bssid", "02:00:00:00:40:01"}, {"x", 3.5}, {"y", 4.0},
                         {"z", 2.5}, {"tx_power", -38.0}, {"path_loss_exponent", 2.4}, {"wall_attenuation", 5.0}}),
            201);
    body_of(s.post(col, {{"ibeacon", {{"uuid", "F7826DA64FA24E988024BC5B71E0893E"}, {"major", 1}, {"minor", 2}}},
                         {"x", 20.0}, {"y", 15.0}, {"tx_power", -59.0}}),
            201);

    json doc = body_of(s.get("/v1/radiomaps/" + std::to_string(from.radiomap) + "/export"));
    doc["name"] = "moved";  // the target floor has a radio map of the source's name
    ASSERT_EQ(doc.at("transmitters").size(), 2u) << doc.dump();
    EXPECT_FALSE(doc.at("transmitters")[0].contains("id"));

    const json imported = body_of(s.post(import_path(to.floor), doc), 201);
    EXPECT_EQ(imported.at("transmitters_created"), 2);
    EXPECT_EQ(imported.at("transmitters_kept"), 0);
    const json before = tx_list(s, from.floor), after = tx_list(s, to.floor);
    ASSERT_EQ(after.at("total"), 2);
    for (std::size_t i = 0; i < 2; ++i) {
        json a = before.at("items")[i], b = after.at("items")[i];
        EXPECT_EQ(b.at("floor_id"), to.floor);
        for (auto* j : {&a, &b}) {
            j->erase("id");
            j->erase("floor_id");
        }
        EXPECT_EQ(a, b);  // every field, the nulls too (z, wall_attenuation of the beacon)
    }
    // The moved map exports the same transmitters again.
    const json again = body_of(s.get("/v1/radiomaps/" + std::to_string(imported.at("id").get<std::int64_t>()) + "/export"));
    EXPECT_EQ(again.at("transmitters"), doc.at("transmitters"));

    // A second import onto a floor that has them keeps the stored ones (a local recalibration wins).
    const auto first = after.at("items")[0].at("id").get<std::int64_t>();
    body_of(s.patch("/v1/transmitters/" + std::to_string(first), {{"tx_power", -45.0}}));
    doc["name"] = "moved again";
    const json twice = body_of(s.post(import_path(to.floor), doc), 201);
    EXPECT_EQ(twice.at("transmitters_created"), 0);
    EXPECT_EQ(twice.at("transmitters_kept"), 2);
    EXPECT_EQ(tx_list(s, to.floor).at("total"), 2);
    EXPECT_DOUBLE_EQ(body_of(s.get("/v1/transmitters/" + std::to_string(first))).at("tx_power").get<double>(), -45.0);

    // A document without transmitters (an older export) still imports.
    json old = doc;
    old.erase("transmitters");
    old["name"] = "older export";
    EXPECT_EQ(body_of(s.post(import_path(to.floor), old), 201).at("transmitters_created"), 0);
}

TEST(TransmitterExport, BadTransmittersRefuseTheWholeImport) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);  // floor 30 m × 20 m
    const json ap = {{"type", "wifi"}, {"bssid", "02:00:00:00:40:01"}, {"x", 3.0}, {"y", 4.0}, {"tx_power", -40.0}};
    const json rps = json::array({{{"name", "a"}, {"x", 1.0}, {"y", 1.0}}});
    auto refused = [&](const json& txs, int status, const std::string& code, const std::string& words) {
        const auto radiomaps = body_of(s.get("/v1/floors/" + std::to_string(h.floor) + "/radiomaps")).at("total");
        const auto r = s.post(import_path(h.floor), {{"name", "m"}, {"rps", rps}, {"transmitters", txs}});
        EXPECT_EQ(r.status, status) << txs.dump() << " -> " << r.raw;
        if (r.status == status) {
            EXPECT_EQ(r.body.at("error").at("code"), code) << r.raw;
            EXPECT_NE(r.body.at("error").at("message").get<std::string>().find(words), std::string::npos) << r.raw;
        }
        EXPECT_EQ(body_of(s.get("/v1/floors/" + std::to_string(h.floor) + "/radiomaps")).at("total"), radiomaps);
        EXPECT_EQ(tx_list(s, h.floor).at("total"), 0);
    };
    refused("lots", 422, "invalid_field", "'transmitters' must be an array");
    refused(json::array({ap, 7}), 422, "invalid_field", "transmitters[1]");
    json far = ap;
    far["x"] = 31.0;
    refused(json::array({far}), 422, "out_of_floor", "transmitters[0]");
    json bad = ap;
    bad["type"] = "lora";
    refused(json::array({bad}), 422, "invalid_field", "transmitters[0]");
    json missing = ap;
    missing.erase("tx_power");
    refused(json::array({missing}), 422, "invalid_field", "tx_power");
    refused(json::array({ap, ap}), 409, "conflict", "transmitters[1]");
    json extra = ap;
    extra["colour"] = "red";
    refused(json::array({extra}), 422, "invalid_field", "colour");
}

}  // namespace
}  // namespace server_transmitter_export_test
