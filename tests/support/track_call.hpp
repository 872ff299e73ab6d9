#pragma once
// A request to a track route with the tokens it needs: the track's (X-Track-Token), a peer's
// (X-Peer-Token, GET /v1/tracks/{a}/relative/{b}) and the API key (the positions routes).
#include <string>
#include <utility>

#include "server_process.hpp"

namespace locus::testing {

struct TrackTokens {
    TrackTokens(std::string track_token = "", std::string peer_token = "") : track(std::move(track_token)), peer(std::move(peer_token)) {}
    std::string track, peer, api_key;
};
TrackTokens with_api_key(const std::string& api_key);

// GET, DELETE, or else POST with `body` as JSON; a status of 0 when the server did not answer.
Response track_call(const ServerProcess& s, const std::string& method, const std::string& path, const TrackTokens& tokens = {},
                    const std::string& body = "");

}  // namespace locus::testing
