#pragma once
// A request to a track route with the tokens it needs: the track's (X-Track-Token), a peer's
// (X-Peer-Token, GET /v1/tracks/{a}/relative/{b}) and the API key (the positions routes); and
// a live track opened on POST /v1/tracks.
#include <cstdint>
#include <nlohmann/json.hpp>
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

// A live track as POST /v1/tracks answers it: its id and the token its own routes take.
struct Track {
    std::int64_t id = 0;
    std::string token;
    // The track's path, and its routes: path("/steps"), path("/fixes").
    std::string path(const std::string& rest = "") const;
};
// Opens a live track: POST /v1/tracks with `body` (map_id and whatever else the route takes:
// label, fusion, fusion_options, ...) and `tokens` (an API key where the server wants one);
// fails the test unless it answers 201 (body_of).
Track open_track(const ServerProcess& s, const nlohmann::json& body, const TrackTokens& tokens = {});

}  // namespace locus::testing
