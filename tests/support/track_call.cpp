#include "track_call.hpp"

#include <httplib.h>

namespace locus::testing {

TrackTokens with_api_key(const std::string& api_key) {
    TrackTokens t;
    t.api_key = api_key;
    return t;
}

Response track_call(const ServerProcess& s, const std::string& method, const std::string& path, const TrackTokens& tokens,
                    const std::string& body) {
    httplib::Client c = client(s.port());
    httplib::Headers h;
    if (!tokens.track.empty()) h.emplace("X-Track-Token", tokens.track);
    if (!tokens.peer.empty()) h.emplace("X-Peer-Token", tokens.peer);
    if (!tokens.api_key.empty()) h.emplace("Authorization", "Bearer " + tokens.api_key);
    return to_response(method == "GET"      ? c.Get(path.c_str(), h)
                       : method == "DELETE" ? c.Delete(path.c_str(), h)
                                            : c.Post(path.c_str(), h, body, "application/json"));
}

std::string Track::path(const std::string& rest) const { return "/v1/tracks/" + std::to_string(id) + rest; }

Track open_track(const ServerProcess& s, const nlohmann::json& body, const TrackTokens& tokens) {
    const nlohmann::json b = body_of(track_call(s, "POST", "/v1/tracks", tokens, body.dump()), 201);
    return {b.at("id").get<std::int64_t>(), b.at("token").get<std::string>()};
}

}  // namespace locus::testing
