// The REST client's live-track calls.
#include "locus/api/client.hpp"

namespace locus::api {

using nlohmann::json;

namespace {

TrackFix fix_of(const json& j) {
    TrackFix f;
    f.t = j.at("t").get<double>();
    f.floor_id = j.at("floor_id").get<std::int64_t>();
    f.x = j.at("x").get<double>();
    f.y = j.at("y").get<double>();
    f.accuracy_m = j.at("accuracy_m").get<double>();
    if (j.contains("heading_deg")) f.heading_deg = j["heading_deg"].get<double>();
    return f;
}

json fix_json(const TrackFix& f) {
    json j = {{"t", f.t}, {"floor_id", f.floor_id}, {"x", f.x}, {"y", f.y}, {"accuracy_m", f.accuracy_m}};
    if (f.heading_deg) j["heading_deg"] = *f.heading_deg;
    return j;
}

std::string path_of(const TrackKey& k, const std::string& rest = "") { return "/v1/tracks/" + std::to_string(k.id) + rest; }

}  // namespace

OpenedTrack Client::open_track(std::int64_t map_id, const std::string& label) {
    json body = {{"map_id", map_id}};
    if (!label.empty()) body["label"] = label;
    const json j = post("/v1/tracks", body);
    return {{j.at("id").get<std::int64_t>(), j.at("token").get<std::string>()}, j.at("ttl_s").get<double>(), j.at("retention_s").get<double>()};
}

TrackPosted Client::post_fixes(const TrackKey& track, const std::vector<TrackFix>& fixes) {
    json list = json::array();
    for (const auto& f : fixes) list.push_back(fix_json(f));
    const std::string text = json{{"fixes", list}}.dump();
    const json j = send("POST", path_of(track, "/fixes"), &text, {{"X-Track-Token", track.token}});
    TrackPosted out;
    out.stored = j.at("stored").get<std::int64_t>();
    out.duplicates = j.at("duplicates").get<std::int64_t>();
    if (j.contains("latest")) out.latest = fix_of(j["latest"]);
    return out;
}

json Client::post_steps(const TrackKey& track, const json& batch) {
    const std::string text = batch.dump();
    return send("POST", path_of(track, "/steps"), &text, {{"X-Track-Token", track.token}});
}

TrackState Client::track(const TrackKey& track, int trail_limit) {
    const json j = send("GET", path_of(track, "?limit=" + std::to_string(trail_limit)), nullptr, {{"X-Track-Token", track.token}});
    TrackState s;
    s.id = j.at("id").get<std::int64_t>();
    s.map_id = j.at("map_id").get<std::int64_t>();
    s.label = j.at("label").get<std::string>();
    s.state = j.at("state").get<std::string>();
    if (j.contains("latest")) s.latest = fix_of(j["latest"]);
    for (const auto& f : j.at("trail")) s.trail.push_back(fix_of(f));
    return s;
}

void Client::close_track(const TrackKey& track) {
    const std::string text = "{}";
    send("POST", path_of(track, "/close"), &text, {{"X-Track-Token", track.token}});
}

void Client::delete_track(const TrackKey& track) { send("DELETE", path_of(track), nullptr, {{"X-Track-Token", track.token}}); }

TrackShare Client::share_track(const TrackKey& track) {
    const std::string text = "{}";
    const json j = send("POST", path_of(track, "/shares"), &text, {{"X-Track-Token", track.token}});
    return {j.at("id").get<std::int64_t>(), {track.id, j.at("token").get<std::string>()}};
}

void Client::revoke_share(const TrackKey& track, std::int64_t share_id) {
    send("DELETE", path_of(track, "/shares/" + std::to_string(share_id)), nullptr, {{"X-Track-Token", track.token}});
}

json Client::relative(const TrackKey& track, const TrackKey& other) {
    return send("GET", path_of(track, "/relative/" + std::to_string(other.id)), nullptr,
                {{"X-Track-Token", track.token}, {"X-Peer-Token", other.token}});
}

std::vector<TrackPosition> Client::positions(std::int64_t map_id, std::optional<std::int64_t> floor_id) {
    std::string path = "/v1/maps/" + std::to_string(map_id) + "/positions";
    if (floor_id) path += "?floor_id=" + std::to_string(*floor_id);
    std::vector<TrackPosition> out;
    const json answer = get(path);  // kept: a range over a temporary's member would dangle
    for (const auto& p : answer.at("positions"))
        out.push_back({p.at("track_id").get<std::int64_t>(), p.at("label").get<std::string>(), fix_of(p.at("fix")), p.at("age_s").get<double>()});
    return out;
}

}  // namespace locus::api
