// The replays' live track (tools/live_post.hpp, OpenTrack) against the real server: closed at
// the replay's end, and closed too when a request threw before that end.
#include <gtest/gtest.h>

#include <stdexcept>

#include "hierarchy.hpp"
#include "live_post.hpp"
#include "server_process.hpp"
#include "track_call.hpp"

namespace live_post_test {
namespace {

using locus::testing::body_of;
using locus::testing::ServerProcess;
using locus::testing::track_call;
using nlohmann::json;

json state_of(const ServerProcess& s, const locus::api::TrackKey& key) {
    return body_of(track_call(s, "GET", "/v1/tracks/" + std::to_string(key.id), {key.token}))["state"];
}

TEST(OpenTrack, ClosesItsTrackAtTheEndOrWhenARequestThrew) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    locus::api::ClientOptions options;
    options.base_url = s.url();
    locus::api::Client client(options);
    const locus::api::TrackKey ended = client.open_track(h.map).key;
    {
        locus::tools::OpenTrack track(client, ended);
        track.close();
    }
    EXPECT_EQ(state_of(s, ended), "closed");
    const locus::api::TrackKey failed = client.open_track(h.map).key;
    try {
        locus::tools::OpenTrack track(client, failed);
        EXPECT_EQ(state_of(s, failed), "live");
        throw std::runtime_error("a request of the replay failed");
    } catch (const std::runtime_error&) {
    }
    EXPECT_EQ(state_of(s, failed), "closed");
}

}  // namespace
}  // namespace live_post_test
