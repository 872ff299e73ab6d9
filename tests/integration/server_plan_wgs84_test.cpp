// A floor's plan in RFC 7946 form: GET ?crs=wgs84 on a georeferenced floor, PUT of that form,
// the floor-metres default saying so, and what is refused. The WGS84 answer passes the
// outside checker @mapbox/geojsonhint (package.json) with no message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_plan_wgs84_test {
namespace {

using locus::testing::body_of;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;

const std::string kHint = std::string(LOCUS_SOURCE_DIR) + "/node_modules/.bin/geojsonhint";

struct PlanWgs84 : ::testing::Test {
    ServerProcess s{{"--demo"}};
    void SetUp() override {
        // The demo's ground floor placed at the IPIN 2023 venue, +y 20° west of north.
        const auto r = s.patch("/v1/floors/1", {{"geo", {{"lat", 49.46115}, {"lon", 11.11115}, {"x", 0}, {"y", 0}, {"bearing_deg", 340}}}});
        ASSERT_EQ(r.status, 200) << r.raw;
    }
};

TEST_F(PlanWgs84, TheDefaultSaysFloorMetres) {
    const json plan = body_of(s.get("/v1/floors/1/plan"));
    EXPECT_EQ(plan.at("crs"), "locus:floor-metres");
    EXPECT_EQ(body_of(s.get("/v1/floors/1/plan?crs=floor-metres")), plan);
}

TEST_F(PlanWgs84, TheWgs84FormIsRfc7946AndLandsAtTheVenue) {
    const json plan = body_of(s.get("/v1/floors/1/plan?crs=wgs84"));
    EXPECT_FALSE(plan.contains("crs"));
    const json bbox = plan.at("bbox");
    ASSERT_EQ(bbox.size(), 4u);
    // 30 m × 15 m about the anchor: a few ten-thousandths of a degree.
    EXPECT_NEAR(bbox[1].get<double>(), 49.46115, 0.0005);
    EXPECT_NEAR(bbox[0].get<double>(), 11.11115, 0.0005);
    EXPECT_GT(bbox[2].get<double>(), bbox[0].get<double>());
    for (const auto& f : plan.at("features"))
        if (f["geometry"]["type"] == "Point") {
            EXPECT_GE(f["geometry"]["coordinates"][0].get<double>(), bbox[0].get<double>());
            EXPECT_LE(f["geometry"]["coordinates"][1].get<double>(), bbox[3].get<double>());
        }
    if (!std::filesystem::exists(kHint)) GTEST_SKIP() << kHint << " is not installed (npm ci): the outside check was not run";
    const std::string file = s.dir() + "/plan-wgs84.geojson";
    std::ofstream(file) << plan.dump();
    const auto hint = run_command({kHint, file});
    EXPECT_EQ(hint.status, 0) << hint.out << hint.err;
    EXPECT_EQ(hint.out + hint.err, "") << "geojsonhint has something to say";
}

TEST_F(PlanWgs84, APlanPutInWgs84IsStoredInFloorMetres) {
    const json metres = body_of(s.get("/v1/floors/1/plan"));
    const json wgs84 = body_of(s.get("/v1/floors/1/plan?crs=wgs84"));
    const auto put = s.put("/v1/floors/1/plan?crs=wgs84", wgs84);
    ASSERT_EQ(put.status, 200) << put.raw;
    EXPECT_FALSE(put.body.contains("crs")) << "answered in the form it was sent";
    const json after = body_of(s.get("/v1/floors/1/plan"));
    EXPECT_EQ(after.at("version"), metres.at("version").get<int>() + 1);
    ASSERT_EQ(after.at("features").size(), metres.at("features").size());
    for (std::size_t i = 0; i < metres["features"].size(); ++i) {
        const json& a = metres["features"][i]["geometry"];
        const json& b = after["features"][i]["geometry"];
        if (a["type"] != "Point") continue;
        EXPECT_NEAR(a["coordinates"][0].get<double>(), b["coordinates"][0].get<double>(), 0.02) << i;
        EXPECT_NEAR(a["coordinates"][1].get<double>(), b["coordinates"][1].get<double>(), 0.02) << i;
    }
}

TEST_F(PlanWgs84, WhatCannotBeReadIsRefusedAndChangesNothing) {
    const json before = body_of(s.get("/v1/floors/1/plan"));
    const auto not_geo = s.get("/v1/floors/2/plan?crs=wgs84");
    EXPECT_EQ(not_geo.status, 422) << not_geo.raw;
    EXPECT_EQ(not_geo.body["error"]["code"], "not_georeferenced");
    EXPECT_EQ(s.get("/v1/floors/1/plan?crs=mercator").status, 400);

    json wgs84 = body_of(s.get("/v1/floors/1/plan?crs=wgs84"));
    json bad = wgs84;
    bad["features"][0]["geometry"]["coordinates"][0][0] = json::array({11.1, 91.0});
    const auto refused = s.put("/v1/floors/1/plan?crs=wgs84", bad);
    EXPECT_EQ(refused.status, 422) << refused.raw;
    EXPECT_NE(refused.raw.find("features[0]"), std::string::npos) << refused.raw;
    json unknown = before;
    unknown["crs"] = "EPSG:3857";
    EXPECT_EQ(s.put("/v1/floors/1/plan", unknown).status, 422);
    const auto on_plain_floor = s.put("/v1/floors/2/plan?crs=wgs84", wgs84);
    EXPECT_EQ(on_plain_floor.body["error"]["code"], "not_georeferenced") << on_plain_floor.raw;
    EXPECT_EQ(body_of(s.get("/v1/floors/1/plan")).at("version"), before.at("version"));
}

}  // namespace
}  // namespace server_plan_wgs84_test
