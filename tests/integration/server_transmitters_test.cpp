// A floor's transmitters over HTTP against the real server: create in each id form, list, read,
// patch, delete; every bad input (NaN-free JSON but wrong types, out-of-floor positions,
// duplicate ids, unknown fields) answers 4xx naming what is wrong and writes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_transmitters_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

class Transmitters : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server = new ServerProcess();
        h = locus::testing::make_hierarchy(*server);  // floor 30 m × 20 m
    }
    static void TearDownTestSuite() {
        delete server;
        server = nullptr;
    }
    static std::string collection() { return "/v1/floors/" + std::to_string(h.floor) + "/transmitters"; }
    static std::int64_t count() { return body_of(server->get(collection() + "?limit=1000")).at("total").get<std::int64_t>(); }
    static void refused(const json& body, int status, const std::string& code, const std::string& words) {
        const auto before = count();
        const auto r = server->post(collection(), body);
        EXPECT_EQ(r.status, status) << body.dump() << " -> " << r.raw;
        if (r.status == status) {
            EXPECT_EQ(r.body.at("error").at("code"), code) << r.raw;
            EXPECT_NE(r.body.at("error").at("message").get<std::string>().find(words), std::string::npos) << r.raw;
        }
        EXPECT_EQ(count(), before) << "nothing may be written for " << body.dump();
    }
    static inline ServerProcess* server = nullptr;
    static inline locus::testing::Hierarchy h;
};

TEST_F(Transmitters, CreateReadPatchDeleteRoundTrip) {
    const json ap = {{"name", "AP lobby"}, {"type", "wifi"}, {"bssid", "AA-BB-CC-00-11-22"}, {"x", 3.5}, {"y", 4.0},
                     {"z", 2.5}, {"tx_power", -38.0}, {"path_loss_exponent", 2.4}, {"wall_attenuation", 5.0}};
    const auto r = server->post(collection(), ap);
    const json created = body_of(r, 201);
    const auto id = created.at("id").get<std::int64_t>();
    EXPECT_EQ(created.at("bssid"), "aa:bb:cc:00:11:22");  // one normal form, as scans use
    EXPECT_EQ(created.at("floor_id"), h.floor);
    EXPECT_DOUBLE_EQ(created.at("tx_power").get<double>(), -38.0);
    const std::string item = "/v1/transmitters/" + std::to_string(id);
    EXPECT_EQ(body_of(server->get(item)), created);

    const json patched = body_of(server->patch(item, {{"x", 10.0}, {"path_loss_exponent", 3.0}}));
    EXPECT_DOUBLE_EQ(patched.at("x").get<double>(), 10.0);
    EXPECT_DOUBLE_EQ(patched.at("y").get<double>(), 4.0);
    EXPECT_DOUBLE_EQ(patched.at("path_loss_exponent").get<double>(), 3.0);

    const json page = body_of(server->get(collection()));
    bool listed = false;
    for (const auto& t : page.at("items")) listed = listed || t.at("id") == id;
    EXPECT_TRUE(listed);

    EXPECT_EQ(server->del(item).status, 204);
    EXPECT_EQ(server->get(item).status, 404);
}

TEST_F(Transmitters, BeaconsByTheirParts) {
    const json ib = body_of(server->post(collection(), {{"ibeacon", {{"uuid", "F7826DA64FA24E988024BC5B71E0893E"},
                                                                    {"major", 7}, {"minor", 65535}}},
                                                        {"x", 1.0}, {"y", 1.0}, {"tx_power", -59.0}}),
                            201);
    EXPECT_EQ(ib.at("type"), "ble");
    EXPECT_EQ(ib.at("bssid"), "f7826da6-4fa2-4e98-8024-bc5b71e0893e:7:65535");
    EXPECT_DOUBLE_EQ(ib.at("path_loss_exponent").get<double>(), 2.0);  // the default
    const json ed = body_of(server->post(collection(), {{"eddystone", {{"namespace", "EDD1EBEAC04E5DEFA017"},
                                                                      {"instance", "0123456789AB"}}},
                                                        {"x", 2.0}, {"y", 1.0}, {"tx_power", -62.0}}),
                            201);
    EXPECT_EQ(ed.at("bssid"), "edd1ebeac04e5defa017:0123456789ab");
    // The same beacon again, by its text this time: a duplicate.
    refused({{"type", "ble"}, {"bssid", "EDD1EBEAC04E5DEFA017:0123456789ab"}, {"x", 5.0}, {"y", 5.0}, {"tx_power", -60.0}},
            409, "conflict", "edd1ebeac04e5defa017:0123456789ab");
}

TEST_F(Transmitters, BadInputIsRefusedAndWritesNothing) {
    const json ok = {{"type", "wifi"}, {"bssid", "00:00:00:00:00:01"}, {"x", 1.0}, {"y", 1.0}, {"tx_power", -40.0}};
    auto with = [&](const char* key, json v) {
        json b = ok;
        b[key] = std::move(v);
        return b;
    };
    auto without = [&](const char* key) {
        json b = ok;
        b.erase(key);
        return b;
    };
    refused(with("x", 31.0), 422, "out_of_floor", "not on floor");
    refused(with("y", -0.5), 422, "out_of_floor", "not on floor");
    refused(with("x", "1"), 422, "invalid_field", "'x'");
    refused(with("type", "zigbee"), 422, "invalid_field", "'type'");
    refused(with("bssid", "   "), 422, "invalid_field", "'bssid'");
    refused(with("tx_power", 90.0), 422, "invalid_field", "'tx_power'");
    refused(with("path_loss_exponent", 0.0), 422, "invalid_field", "'path_loss_exponent'");
    refused(with("wall_attenuation", -1.0), 422, "invalid_field", "'wall_attenuation'");
    refused(with("colour", "red"), 422, "invalid_field", "unknown field 'colour'");
    refused(without("tx_power"), 422, "invalid_field", "missing field 'tx_power'");
    refused(without("bssid"), 422, "invalid_field", "missing field 'bssid'");
    refused(with("ibeacon", {{"uuid", "xyz"}, {"major", 1}, {"minor", 1}}), 422, "invalid_field", "not several");
}

TEST_F(Transmitters, BeaconPartsAreChecked) {
    const json base = {{"x", 1.0}, {"y", 1.0}, {"tx_power", -59.0}};
    auto beacon = [&](json parts, const char* form = "ibeacon") {
        json b = base;
        b[form] = std::move(parts);
        return b;
    };
    refused(beacon({{"uuid", "not-a-uuid"}, {"major", 1}, {"minor", 1}}), 422, "invalid_field", "'ibeacon.uuid'");
    refused(beacon({{"uuid", "f7826da64fa24e988024bc5b71e0893e"}, {"major", 70000}, {"minor", 1}}), 422,
            "out_of_range", "'ibeacon.major'");
    refused(beacon({{"uuid", "f7826da64fa24e988024bc5b71e0893e"}, {"major", 1}}), 422, "invalid_field",
            "missing field 'ibeacon.minor'");
    refused(beacon({{"namespace", "12"}, {"instance", "0123456789ab"}}, "eddystone"), 422, "invalid_field",
            "'eddystone.namespace'");
    json wrong_type = beacon({{"uuid", "f7826da64fa24e988024bc5b71e0893e"}, {"major", 1}, {"minor", 1}});
    wrong_type["type"] = "wifi";
    refused(wrong_type, 422, "invalid_field", "'type'");
}

TEST_F(Transmitters, PatchAndPathsAreChecked) {
    const json a = body_of(server->post(collection(), {{"type", "wifi"}, {"bssid", "00:00:00:00:00:0a"}, {"x", 1.0},
                                                       {"y", 1.0}, {"tx_power", -40.0}}),
                           201);
    body_of(server->post(collection(), {{"type", "wifi"}, {"bssid", "00:00:00:00:00:0b"}, {"x", 1.0}, {"y", 1.0},
                                        {"tx_power", -40.0}}),
            201);
    const std::string item = "/v1/transmitters/" + std::to_string(a.at("id").get<std::int64_t>());
    auto r = server->patch(item, {{"y", 25.0}});
    EXPECT_EQ(r.status, 422);
    EXPECT_EQ(r.body["error"]["code"], "out_of_floor");
    r = server->patch(item, {{"bssid", "00-00-00-00-00-0B"}});
    EXPECT_EQ(r.status, 409);
    EXPECT_NE(r.raw.find("00:00:00:00:00:0b"), std::string::npos) << r.raw;
    EXPECT_EQ(body_of(server->get(item)), a) << "a refused patch changes nothing";

    EXPECT_EQ(server->post("/v1/floors/999999/transmitters", {{"type", "wifi"}, {"bssid", "x"}, {"x", 1.0}, {"y", 1.0},
                                                            {"tx_power", -40.0}})
                  .status,
              404);
    EXPECT_EQ(server->get("/v1/floors/999999/transmitters").status, 404);
    EXPECT_EQ(server->get("/v1/transmitters/999999").status, 404);
    EXPECT_EQ(server->post_raw(collection(), "{\"x\": NaN}").status, 400);
}

// Four APs in the corners of a 30 m × 20 m floor and two in the middle, each with its own model.
struct Layout {
    std::string bssid;
    double x, y, tx_power, exponent;
};
const Layout kLayout[] = {{"02:00:00:00:00:01", 2, 2, -40, 2.0},   {"02:00:00:00:00:02", 28, 2, -42, 2.2},
                          {"02:00:00:00:00:03", 28, 18, -38, 2.0}, {"02:00:00:00:00:04", 2, 18, -41, 2.1},
                          {"02:00:00:00:00:05", 10, 10, -40, 2.0}, {"02:00:00:00:00:06", 20, 10, -40, 2.0}};

double rss_at(const Layout& l, double x, double y) {
    return l.tx_power - 10.0 * l.exponent * std::log10(std::max(std::hypot(x - l.x, y - l.y), 0.1));
}

class RangingLocalize : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server = new ServerProcess();
        h = locus::testing::make_hierarchy(*server);
        for (const auto& l : kLayout)
            body_of(server->post("/v1/floors/" + std::to_string(h.floor) + "/transmitters",
                                 {{"type", "wifi"}, {"bssid", l.bssid}, {"x", l.x}, {"y", l.y}, {"tx_power", l.tx_power},
                                  {"path_loss_exponent", l.exponent}}),
                    201);
    }
    static void TearDownTestSuite() {
        delete server;
        server = nullptr;
    }
    static json measurements_at(double x, double y, std::size_t n = std::size(kLayout)) {
        json ms = json::array();
        for (std::size_t i = 0; i < n; ++i) ms.push_back({{"bssid", kLayout[i].bssid}, {"rss", rss_at(kLayout[i], x, y)}});
        ms.push_back({{"bssid", "0e:ee:ee:ee:ee:ee"}, {"rss", -70.0}});  // an AP of no known position
        return ms;
    }
    static inline ServerProcess* server = nullptr;
    static inline locus::testing::Hierarchy h;
};

TEST_F(RangingLocalize, MultilaterationRecoversThePositionOnRadiomapAndMap) {
    for (const auto& [x, y] : {std::pair{7.0, 5.0}, std::pair{15.0, 12.0}, std::pair{25.0, 16.0}}) {
        const json body = {{"algorithm", "multilateration"}, {"measurements", measurements_at(x, y)}};
        for (const std::string& path : {"/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize",
                                       "/v1/maps/" + std::to_string(h.map) + "/localize"}) {
            const json a = body_of(server->post(path, body));
            EXPECT_NEAR(a.at("x").get<double>(), x, 0.01) << path;
            EXPECT_NEAR(a.at("y").get<double>(), y, 0.01) << path;
            EXPECT_EQ(a.at("floor_id"), h.floor);
            EXPECT_EQ(a.at("algorithm"), "multilateration");
            EXPECT_EQ(a.at("transmitters_heard"), std::size(kLayout));
            EXPECT_GT(a.at("uncertainty").at("semi_major").get<double>(), 0.0);
        }
    }
}

TEST_F(RangingLocalize, TrilaterationWithTheSeedsCutoffAndScans) {
    // Near the corner AP and the middle ones: at least three within 10 m.
    const double x = 6.0, y = 10.0;
    json scans = json::array();
    for (int s = 0; s < 5; ++s) scans.push_back(measurements_at(x, y));
    const json a = body_of(server->post("/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize",
                                        {{"algorithm", "trilateration"}, {"scans", scans}}));
    EXPECT_NEAR(a.at("x").get<double>(), x, 0.05);
    EXPECT_NEAR(a.at("y").get<double>(), y, 0.05);
    EXPECT_LT(a.at("transmitters_used").get<int>(), a.at("transmitters_heard").get<int>());  // the 10 m cutoff
    // A cutoff no transmitter passes: no fix, said so.
    const auto r = server->post("/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize",
                                {{"algorithm", "trilateration"}, {"scans", scans}, {"options", {{"cutoff", 1.0}}}});
    EXPECT_EQ(r.status, 422) << r.raw;
    EXPECT_EQ(r.body["error"]["code"], "no_fix");
}

TEST_F(RangingLocalize, OnAMapTheFloorThatHearsMostAnswers) {
    const auto upper = body_of(server->post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                            {{"name", "Upper"}, {"level", 1}, {"width", 30.0}, {"height", 20.0}}),
                               201)
                           .at("id")
                           .get<std::int64_t>();
    const Layout up[] = {{"0a:00:00:00:00:01", 5, 5, -40, 2.0}, {"0a:00:00:00:00:02", 25, 5, -40, 2.0},
                         {"0a:00:00:00:00:03", 15, 15, -40, 2.0}};
    for (const auto& l : up)
        body_of(server->post("/v1/floors/" + std::to_string(upper) + "/transmitters",
                             {{"type", "wifi"}, {"bssid", l.bssid}, {"x", l.x}, {"y", l.y}, {"tx_power", l.tx_power}}),
                201);
    // Upstairs at (12, 8): its three APs, and one of the ground floor's through the ceiling.
    json ms = json::array();
    for (const auto& l : up) ms.push_back({{"bssid", l.bssid}, {"rss", rss_at(l, 12, 8)}});
    ms.push_back({{"bssid", kLayout[4].bssid}, {"rss", -80.0}});
    const json a = body_of(server->post("/v1/maps/" + std::to_string(h.map) + "/localize", {{"algorithm", "multilateration"}, {"measurements", ms}}));
    EXPECT_EQ(a.at("floor_id"), upper);
    EXPECT_EQ(a.at("transmitters_heard"), 3);
    EXPECT_NEAR(a.at("x").get<double>(), 12.0, 0.01);
    EXPECT_NEAR(a.at("y").get<double>(), 8.0, 0.01);
    body_of(server->del("/v1/floors/" + std::to_string(upper)), 204);
}

TEST_F(RangingLocalize, FewerThanThreeKnownIs422WithTheCount) {
    for (const char* algorithm : {"trilateration", "multilateration"}) {
        const auto r = server->post("/v1/maps/" + std::to_string(h.map) + "/localize",
                                    {{"algorithm", algorithm}, {"measurements", measurements_at(5, 5, 2)}});
        EXPECT_EQ(r.status, 422) << r.raw;
        EXPECT_EQ(r.body["error"]["code"], "too_few_transmitters");
        EXPECT_NE(r.body["error"]["message"].get<std::string>().find("hears 2 known transmitters"), std::string::npos) << r.raw;
    }
}

TEST_F(RangingLocalize, BadRequestsNameTheProblem) {
    const std::string path = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize";
    const json ms = measurements_at(5, 5);
    auto expect = [&](const json& body, int status, const std::string& code, const std::string& words) {
        const auto r = server->post(path, body);
        EXPECT_EQ(r.status, status) << body.dump() << " -> " << r.raw;
        EXPECT_EQ(r.body["error"]["code"], code) << r.raw;
        EXPECT_NE(r.body["error"]["message"].get<std::string>().find(words), std::string::npos) << r.raw;
    };
    expect({{"algorithm", "multilateration"}, {"measurements", ms}, {"options", {{"k", 3}}}}, 422, "invalid_field",
           "unknown field 'options.k'");
    expect({{"algorithm", "trilateration"}, {"measurements", ms}, {"options", {{"cutoff", -1}}}}, 422, "out_of_range",
           "options.cutoff");
    expect({{"algorithm", "multilateration"}, {"measurements", ms}, {"options", {{"max_iterations", 0.5}}}}, 422,
           "invalid_field", "options.max_iterations");
    expect({{"algorithm", "multilateration"}}, 422, "invalid_field", "exactly one of");
    expect({{"algorithm", "multilateration"}, {"measurements", {{{"bssid", "a"}, {"rss", 5}}}}}, 422, "out_of_range",
           "measurements[0].rss");
    EXPECT_EQ(server->post("/v1/radiomaps/999999/localize", {{"algorithm", "multilateration"}, {"measurements", ms}}).status, 404);
}

// proximity: the known transmitter heard strongest, its position and its model's range.
TEST_F(RangingLocalize, ProximityAnswersTheStrongestKnownTransmitter) {
    // At (25, 15): the corner AP at (28, 18) is 4.2 m off, the strongest of the six by the models.
    const double x = 25.0, y = 15.0;
    for (const std::string& path : {"/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize",
                                   "/v1/maps/" + std::to_string(h.map) + "/localize"}) {
        const json a = body_of(server->post(path, {{"algorithm", "proximity"}, {"measurements", measurements_at(x, y)}}));
        EXPECT_EQ(a.at("algorithm"), "proximity") << path;
        EXPECT_EQ(a.at("transmitter").at("bssid"), kLayout[2].bssid) << a.dump();
        EXPECT_EQ(a.at("x"), kLayout[2].x);
        EXPECT_EQ(a.at("y"), kLayout[2].y);
        EXPECT_EQ(a.at("floor_id"), h.floor);
        EXPECT_EQ(a.at("transmitters_heard"), std::size(kLayout));  // the unknown AP is not counted
        EXPECT_NEAR(a.at("transmitter").at("rss").get<double>(), rss_at(kLayout[2], x, y), 1e-9);
        // Its model inverted: the distance the reading was made at (the AP's height is unset, so
        // the phone's: no height difference).
        EXPECT_NEAR(a.at("range_m").get<double>(), std::hypot(x - kLayout[2].x, y - kLayout[2].y), 1e-6);
    }
    // One known transmitter is enough; a scan hearing none is refused by name.
    const json one = {{{"bssid", kLayout[0].bssid}, {"rss", -70.0}}, {{"bssid", "0e:ee:ee:ee:ee:ee"}, {"rss", -40.0}}};
    const json a = body_of(server->post("/v1/maps/" + std::to_string(h.map) + "/localize", {{"algorithm", "proximity"}, {"measurements", one}}));
    EXPECT_EQ(a.at("transmitter").at("bssid"), kLayout[0].bssid);
    EXPECT_EQ(a.at("transmitters_heard"), 1);
    const auto none = server->post("/v1/maps/" + std::to_string(h.map) + "/localize",
                                   {{"algorithm", "proximity"}, {"measurements", {{{"bssid", "0e:ee:ee:ee:ee:ee"}, {"rss", -40.0}}}}});
    EXPECT_EQ(none.status, 422) << none.raw;
    EXPECT_EQ(none.body["error"]["code"], "no_known_transmitter");
    EXPECT_NE(none.body["error"]["message"].get<std::string>().find("hears no known transmitter"), std::string::npos) << none.raw;
    // Only phone_height is an option of it.
    const auto cutoff = server->post("/v1/maps/" + std::to_string(h.map) + "/localize",
                                     {{"algorithm", "proximity"}, {"measurements", measurements_at(x, y)}, {"options", {{"cutoff", 5}}}});
    EXPECT_EQ(cutoff.status, 422) << cutoff.raw;
    EXPECT_NE(cutoff.body["error"]["message"].get<std::string>().find("options.cutoff"), std::string::npos) << cutoff.raw;
    // phone_height is taken; these APs have no z, so they stand at the phone's height whatever it
    // is and the range stays the reading's distance.
    const json high = body_of(server->post("/v1/maps/" + std::to_string(h.map) + "/localize",
                                           {{"algorithm", "proximity"}, {"measurements", measurements_at(x, y)}, {"options", {{"phone_height", -10.0}}}}));
    EXPECT_NEAR(high.at("range_m").get<double>(), std::hypot(x - kLayout[2].x, y - kLayout[2].y), 1e-6);
}

// `locus import transmitters`: a file of APs and beacons, checked whole before any write;
// a second import of it updates in place.
TEST(ImportTransmitters, CsvIntoAFloorTwiceAndRefusedWhole) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);  // 30 m × 20 m
    const std::string floor = std::to_string(h.floor);
    const std::string dir = locus::testing::make_temp_dir();
    const std::string good = dir + "/tx.csv";
    {
        std::ofstream f(good);
        f << "name,type,bssid,x,y,z,tx_power,path_loss_exponent,uuid,major,minor,namespace,instance\n"
             "\"AP, lobby\",wifi,AA-BB-CC-00-00-01,2,3,2.5,-40,2.2,,,,,\n"
             "Beacon 7,,,10,5,,-59,,F7826DA6-4FA2-4E98-8024-BC5B71E0893E,1,7,,\n"
             "Eddy,,,12,6,,-62,,,,,EDD1EBEAC04E5DEFA017,0123456789AB\n";
    }
    auto import = [&](const std::string& file) {
        return locus::testing::run_command({LOCUS_CLI_BIN, "import", "transmitters", file, "--server", s.url(), "--floor", floor});
    };
    auto r = import(good);
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_EQ(json::parse(r.out).at("created"), 3);
    const json page = body_of(s.get("/v1/floors/" + floor + "/transmitters"));
    ASSERT_EQ(page.at("total"), 3);
    EXPECT_EQ(page.at("items")[0].at("name"), "AP, lobby");
    EXPECT_EQ(page.at("items")[0].at("bssid"), "aa:bb:cc:00:00:01");
    EXPECT_EQ(page.at("items")[1].at("bssid"), "f7826da6-4fa2-4e98-8024-bc5b71e0893e:1:7");
    EXPECT_EQ(page.at("items")[1].at("type"), "ble");
    EXPECT_EQ(page.at("items")[2].at("bssid"), "edd1ebeac04e5defa017:0123456789ab");

    r = import(good);
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_EQ(json::parse(r.out).at("created"), 0);
    EXPECT_EQ(json::parse(r.out).at("updated"), 3);
    EXPECT_EQ(body_of(s.get("/v1/floors/" + floor + "/transmitters")).at("total"), 3);

    // A bad number on one line and a position off the floor on another: nothing is written.
    for (const std::string& rows : {std::string("wifi,00:00:00:00:00:09,1,1,-40\nwifi,00:00:00:00:00:0a,abc,1,-40\n"),
                                    std::string("wifi,00:00:00:00:00:09,1,1,-40\nwifi,00:00:00:00:00:0a,31,1,-40\n")}) {
        const std::string bad = dir + "/bad.csv";
        {
            std::ofstream f(bad);
            f << "type,bssid,x,y,tx_power\n" << rows;
        }
        r = import(bad);
        EXPECT_NE(r.status, 0);
        EXPECT_NE(r.err.find("line 3"), std::string::npos) << r.err;
        EXPECT_EQ(body_of(s.get("/v1/floors/" + floor + "/transmitters")).at("total"), 3) << "nothing written";
    }
}

// Calibration: a survey generated from known transmitters (two registered with a wrong
// model, one not registered at all) gives back their models and the unknown one's position.
TEST(FitTransmitters, SurveyGivesBackTheModelsAndAPosition) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);  // 30 m × 20 m
    const std::string floor = std::to_string(h.floor);
    struct Truth {
        const char* bssid;
        double x, y, p, n;
    };
    const Truth truth[] = {{"02:00:00:00:20:01", 5, 5, -38, 2.1}, {"02:00:00:00:20:02", 25, 15, -44, 2.8},
                           {"02:00:00:00:20:03", 18, 6, -41, 2.4}};
    json rps = json::array();
    int i = 0;
    for (double x = 1; x < 30; x += 3)
        for (double y = 1; y < 20; y += 3) {
            json ms = json::array();
            int j = 0;
            for (const auto& t : truth) {
                // ±1 dB of deterministic "noise", different per RP and AP.
                const double noise = ((i * 7 + j * 13) % 5 - 2) * 0.5;
                const double d = std::max(std::hypot(x - t.x, y - t.y), 0.1);
                ms.push_back({{"bssid", t.bssid}, {"mean", std::min(t.p - 10 * t.n * std::log10(d) + noise, 0.0)},
                              {"variance", 4.0}, {"count", 5}});
                ++j;
            }
            rps.push_back({{"name", "rp" + std::to_string(i++)}, {"x", x}, {"y", y}, {"scans", 5}, {"measurements", ms}});
        }
    body_of(s.post("/v1/floors/" + floor + "/radiomaps/import", {{"name", "Survey"}, {"rps", rps}}), 201);
    const auto a = body_of(s.post("/v1/floors/" + floor + "/transmitters",
                                  {{"type", "wifi"}, {"bssid", truth[0].bssid}, {"x", 5.0}, {"y", 5.0}, {"tx_power", -60.0}}), 201);
    body_of(s.post("/v1/floors/" + floor + "/transmitters",
                   {{"type", "wifi"}, {"bssid", truth[1].bssid}, {"x", 25.0}, {"y", 15.0}, {"tx_power", -30.0},
                    {"path_loss_exponent", 5.0}}), 201);

    const json dry = body_of(s.post("/v1/floors/" + floor + "/transmitters/fit", json::object()));
    EXPECT_EQ(dry.at("applied"), false);
    ASSERT_EQ(dry.at("transmitters").size(), 3u) << dry.dump();
    for (const auto& f : dry.at("transmitters")) {
        const Truth* t = nullptr;
        for (const auto& c : truth)
            if (f.at("bssid") == c.bssid) t = &c;
        ASSERT_TRUE(t);
        EXPECT_NEAR(f.at("tx_power").get<double>(), t->p, 1.5) << f.dump();
        EXPECT_NEAR(f.at("path_loss_exponent").get<double>(), t->n, 0.25) << f.dump();
        EXPECT_GT(f.at("r2").get<double>(), 0.9) << f.dump();
        EXPECT_LT(f.at("residual_db").get<double>(), 1.5) << f.dump();
        EXPECT_NEAR(f.at("x").get<double>(), t->x, 1.0) << f.dump();
        EXPECT_NEAR(f.at("y").get<double>(), t->y, 1.0) << f.dump();
        EXPECT_EQ(f.at("position"), t == &truth[2] ? "fitted" : "known");
    }
    // Nothing stored without apply.
    EXPECT_EQ(body_of(s.get("/v1/floors/" + floor + "/transmitters")).at("total"), 2);
    EXPECT_DOUBLE_EQ(body_of(s.get("/v1/transmitters/" + std::to_string(a.at("id").get<std::int64_t>()))).at("tx_power").get<double>(), -60.0);

    const json applied = body_of(s.post("/v1/floors/" + floor + "/transmitters/fit?apply=true", json::object()));
    EXPECT_EQ(applied.at("applied"), true);
    const json page = body_of(s.get("/v1/floors/" + floor + "/transmitters"));
    ASSERT_EQ(page.at("total"), 3);
    EXPECT_NEAR(page.at("items")[0].at("tx_power").get<double>(), -38.0, 1.5);
    EXPECT_NEAR(page.at("items")[2].at("x").get<double>(), 18.0, 1.0);
    // And the fitted models locate: a scan at (12, 10) from the same truth.
    json ms = json::array();
    for (const auto& t : truth) ms.push_back({{"bssid", t.bssid}, {"rss", t.p - 10 * t.n * std::log10(std::hypot(12 - t.x, 10 - t.y))}});
    const json fix = body_of(s.post("/v1/maps/" + std::to_string(h.map) + "/localize", {{"algorithm", "multilateration"}, {"measurements", ms}}));
    EXPECT_LT(std::hypot(fix.at("x").get<double>() - 12, fix.at("y").get<double>() - 10), 1.5) << fix.dump();
}

TEST(FitTransmitters, BadRequestsAreRefusedAndWriteNothing) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string floor = std::to_string(h.floor);
    locus::testing::make_rp(s, h.radiomap, "only", 3, 3);
    const auto t = body_of(s.post("/v1/floors/" + floor + "/transmitters",
                                  {{"type", "wifi"}, {"bssid", "02:00:00:00:30:01"}, {"x", 1.0}, {"y", 1.0}, {"tx_power", -40.0}}), 201);
    const std::string id = std::to_string(t.at("id").get<std::int64_t>());
    const std::string path = "/v1/floors/" + floor + "/transmitters/fit";
    auto r = s.post(path + "?apply=true", {{"transmitters", {t.at("id")}}});
    EXPECT_EQ(r.status, 422) << r.raw;
    EXPECT_EQ(r.body["error"]["code"], "too_few_rps");
    EXPECT_NE(r.raw.find("transmitter " + id), std::string::npos) << r.raw;
    r = s.post(path + "?apply=maybe", json::object());
    EXPECT_EQ(r.status, 400) << r.raw;
    r = s.post(path, {{"min_rps", 2}});
    EXPECT_EQ(r.status, 422) << r.raw;
    r = s.post(path, {{"transmitters", {999999}}});
    EXPECT_EQ(r.status, 404) << r.raw;
    r = s.post(path, {{"colour", 1}});
    EXPECT_EQ(r.status, 422) << r.raw;
    EXPECT_EQ(s.post("/v1/floors/999999/transmitters/fit", json::object()).status, 404);
    EXPECT_DOUBLE_EQ(body_of(s.get("/v1/transmitters/" + id)).at("tx_power").get<double>(), -40.0);
}

// A radio map with no survey: the floor's transmitters and its plan's walls.
TEST(GenerateRadioMap, GridFromTransmittersAndWallsLocalizes) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);  // 30 m × 20 m
    const std::string floor = std::to_string(h.floor);
    const auto r0 = s.post("/v1/floors/" + floor + "/radiomaps/generate", {{"name", "Model"}, {"step", 2.0}});
    EXPECT_EQ(r0.status, 422) << r0.raw;
    EXPECT_EQ(r0.body["error"]["code"], "no_transmitters");
    // One wall across the floor at x = 15, 6 dB for the AP that models walls.
    const json plan = {{"type", "FeatureCollection"},
                       {"features", {{{"type", "Feature"},
                                      {"geometry", {{"type", "LineString"}, {"coordinates", {{15, 0}, {15, 20}}}}},
                                      {"properties", {{"feature", "wall"}}}}}}};
    const auto put = s.put("/v1/floors/" + floor + "/plan", plan);
    ASSERT_EQ(put.status, 200) << put.raw;
    const struct {
        const char* bssid;
        double x, y;
    } aps[] = {{"02:00:00:00:40:01", 3, 3}, {"02:00:00:00:40:02", 27, 3}, {"02:00:00:00:40:03", 15, 17}, {"02:00:00:00:40:04", 8, 12}};
    for (const auto& a : aps)
        body_of(s.post("/v1/floors/" + floor + "/transmitters", {{"type", "wifi"}, {"bssid", a.bssid}, {"x", a.x}, {"y", a.y},
                                                                 {"tx_power", -40.0}, {"path_loss_exponent", 2.0}, {"wall_attenuation", 6.0}}),
                201);
    const json g = body_of(s.post("/v1/floors/" + floor + "/radiomaps/generate", {{"name", "Model"}, {"step", 2.0}, {"sigma_db", 3.0}}), 201);
    EXPECT_EQ(g.at("rp_count"), 150);  // 15 × 10
    EXPECT_EQ(g.at("walls"), 1);
    const auto rm = g.at("id").get<std::int64_t>();
    const json rps = body_of(s.get("/v1/radiomaps/" + std::to_string(rm) + "/rps?limit=1000"));
    ASSERT_EQ(rps.at("total"), 150);
    // The RP at (1, 1): AP 1 without a wall; AP 2 at (27, 3) behind the wall at x = 15.
    const auto first = rps.at("items")[0];
    EXPECT_EQ(first.at("generated"), 1);
    const json rp = body_of(s.get("/v1/rps/" + std::to_string(first.at("id").get<std::int64_t>())));
    for (const auto& m : rp.at("measurements")) {
        if (m.at("bssid") == "02:00:00:00:40:01") {
            EXPECT_NEAR(m.at("mean").get<double>(), -40 - 20 * std::log10(std::hypot(2.0, 2.0)), 1e-9);
        }
        if (m.at("bssid") == "02:00:00:00:40:02") {
            EXPECT_NEAR(m.at("mean").get<double>(), -40 - 20 * std::log10(std::hypot(26.0, 2.0)) - 6.0, 1e-9);
        }
        EXPECT_DOUBLE_EQ(m.at("variance").get<double>(), 9.0);
    }
    // A surveyed RP is not generated.
    const auto surveyed = locus::testing::make_rp(s, h.radiomap, "by hand", 3, 3);
    EXPECT_EQ(body_of(s.get("/v1/rps/" + std::to_string(surveyed))).at("generated"), 0);
    // The generated map answers a scan the model predicts at (9, 7) (AP 3 sits on the wall:
    // not behind it).
    json ms = json::array();
    for (const auto& a : aps) {
        const double walls = (a.x > 15) != (9 > 15) ? 6.0 : 0.0;
        ms.push_back({{"bssid", a.bssid}, {"rss", -40 - 20 * std::log10(std::hypot(9 - a.x, 7 - a.y)) - walls}});
    }
    const json fix = body_of(s.post("/v1/radiomaps/" + std::to_string(rm) + "/localize", {{"algorithm", "wknn"}, {"measurements", ms}}));
    EXPECT_LT(std::hypot(fix.at("x").get<double>() - 9, fix.at("y").get<double>() - 7), 1.5) << fix.dump();
}

TEST(GenerateRadioMap, BadRequestsNameTheProblem) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string floor = std::to_string(h.floor);
    body_of(s.post("/v1/floors/" + floor + "/transmitters", {{"type", "wifi"}, {"bssid", "02:00:00:00:50:01"}, {"x", 1.0}, {"y", 1.0}, {"tx_power", -40.0}}), 201);
    const std::string path = "/v1/floors/" + floor + "/radiomaps/generate";
    auto expect = [&](const json& body, int status, const std::string& code, const std::string& words) {
        const auto r = s.post(path, body);
        EXPECT_EQ(r.status, status) << body.dump() << " -> " << r.raw;
        EXPECT_EQ(r.body["error"]["code"], code) << r.raw;
        EXPECT_NE(r.raw.find(words), std::string::npos) << r.raw;
    };
    expect({{"name", "M"}}, 422, "invalid_field", "missing field 'step'");
    expect({{"step", 1.0}}, 422, "invalid_field", "missing field 'name'");
    expect({{"name", "M"}, {"step", 0.0}}, 422, "out_of_range", "'step'");
    expect({{"name", "M"}, {"step", 1.0}, {"min_rss", 5}}, 422, "out_of_range", "'min_rss'");
    expect({{"name", "M"}, {"step", 1.0}, {"grid", 1}}, 422, "invalid_field", "unknown field 'grid'");
    const auto big = body_of(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                    {{"name", "Hall"}, {"level", 1}, {"width", 2000.0}, {"height", 2000.0}}), 201);
    body_of(s.post("/v1/floors/" + std::to_string(big.at("id").get<std::int64_t>()) + "/transmitters",
                   {{"type", "wifi"}, {"bssid", "02:00:00:00:50:01"}, {"x", 1.0}, {"y", 1.0}, {"tx_power", -40.0}}), 201);
    const auto r = s.post("/v1/floors/" + std::to_string(big.at("id").get<std::int64_t>()) + "/radiomaps/generate", {{"name", "M"}, {"step", 1.0}});
    EXPECT_EQ(r.status, 422) << r.raw;
    EXPECT_NE(r.raw.find("at most 100000"), std::string::npos) << r.raw;
    // Nothing was written by any of them; a taken name is 409.
    EXPECT_EQ(body_of(s.get("/v1/floors/" + floor + "/radiomaps")).at("total"), 1);
    body_of(s.post(path, {{"name", "M"}, {"step", 5.0}}), 201);
    EXPECT_EQ(s.post(path, {{"name", "M"}, {"step", 5.0}}).status, 409);
    EXPECT_EQ(s.post("/v1/floors/999999/radiomaps/generate", {{"name", "M"}, {"step", 5.0}}).status, 404);
}

}  // namespace
}  // namespace server_transmitters_test
