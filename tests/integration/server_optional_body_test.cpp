// Action routes whose body is optional take a POST with no body at all (`curl -X POST`, no
// Content-Length): RFC 9112 §6.3 reads that as an empty body. Routes that need a body keep
// answering 411.
#include <gtest/gtest.h>

#include "hierarchy.hpp"
#include "raw_connection.hpp"
#include "server_process.hpp"

namespace server_optional_body_test {
namespace {

using locus::testing::RawConnection;
using locus::testing::ServerProcess;
using nlohmann::json;

// A POST with no body and no length, as `curl -X POST URL` sends it.
locus::testing::RawAnswer bare_post(int port, const std::string& path, const std::string& headers = {}) {
    RawConnection c(port);
    EXPECT_TRUE(c.send("POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers + "\r\n"));
    auto answer = c.read_answer();
    EXPECT_TRUE(answer.has_value()) << path;
    return answer.value_or(locus::testing::RawAnswer{});
}

TEST(OptionalBody, ActionsTakeAPostWithNoBody) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const auto opened = s.post("/v1/tracks", {{"map_id", h.map}});
    ASSERT_EQ(opened.status, 201) << opened.raw;
    const std::string track = "/v1/tracks/" + std::to_string(opened.body.at("id").get<long long>());
    const std::string token = "X-Track-Token: " + opened.body.at("token").get<std::string>() + "\r\n";

    const auto share = bare_post(s.port(), track + "/shares", token);
    EXPECT_EQ(share.status, 201) << share.body;
    EXPECT_EQ(json::parse(share.body).at("token").get<std::string>().rfind("shr_", 0), 0u) << share.body;

    const auto closed = bare_post(s.port(), track + "/close", token);
    EXPECT_EQ(closed.status, 200) << closed.body;
    EXPECT_EQ(json::parse(closed.body).at("state"), "closed") << closed.body;

    // The tune and the fit answer for themselves (here: not enough survey to work with), not 411.
    for (const std::string& path : {"/v1/radiomaps/" + std::to_string(h.radiomap) + "/tune",
                                   "/v1/floors/" + std::to_string(h.floor) + "/transmitters/fit?apply=true"}) {
        const auto a = bare_post(s.port(), path);
        EXPECT_NE(a.status, 411) << path << ": " << a.body;
        EXPECT_EQ(a.body.find("length_required"), std::string::npos) << path << ": " << a.body;
    }
}

TEST(OptionalBody, RoutesThatNeedABodyStill411) {
    ServerProcess s;
    const auto a = bare_post(s.port(), "/v1/maps");
    EXPECT_EQ(a.status, 411) << a.body;
    EXPECT_EQ(s.get("/v1/maps").body.at("total"), 0);
}

}  // namespace
}  // namespace server_optional_body_test
