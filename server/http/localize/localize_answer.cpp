#include "http/localize/localize_answer.hpp"

#include <charconv>
#include <cmath>

#include "http/api_error.hpp"
#include "http/json_text.hpp"
#include "http/radiomaps/radiomap_settings.hpp"
#include "locus/match/localize.hpp"
#include "locus/match/workspace.hpp"

namespace locus::http {

namespace {
// The answer is written directly: it is the other half of every localize request, and a
// JSON tree of ten candidates costs more than the match itself.
class Writer {
public:
    std::string out;
    Writer& raw(std::string_view s) {
        out.append(s);
        return *this;
    }
    Writer& key(std::string_view k) {
        if (!out.empty() && out.back() != '{' && out.back() != '[') out.push_back(',');
        out.push_back('"');
        out.append(k);
        out.append("\":");
        return *this;
    }
    Writer& number(double v) {
        if (!std::isfinite(v)) return raw("null");  // as nlohmann writes it
        char buf[32];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        out.append(buf, r.ptr);
        return *this;
    }
    Writer& integer(long long v) {
        char buf[24];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        out.append(buf, r.ptr);
        return *this;
    }
    Writer& text(const std::string& s) { return raw(json_text(s)); }
};

// A candidate is head, score, tail, matched APs, "}". The head and tail depend on the RP
// only, so a snapshot writes them once (prepare_answers).
Writer& candidate_head(Writer& w, long long rp_id, Point at) {
    return w.raw("{").key("rp_id").integer(rp_id).key("x").number(at.x).key("y").number(at.y).key("score");
}
Writer& candidate_tail(Writer& w, long long floor_id, long long building_id) {
    // The comma by hand: key() cannot see the score before it when the tail is written alone.
    return w.raw(",\"floor_id\":").integer(floor_id).key("building_id").integer(building_id).key("matched_aps");
}
}  // namespace

std::string answer(const localize::Snapshot& snapshot, const LocalizeRequest& request, FloorGeoCache* geo,
                   floors::FloorPlacesCache* places) {
    // answer() runs on the HTTP worker thread that handles the request: that thread is the
    // matcher's caller, so it owns the workspace, warm for every request it serves.
    thread_local match::Workspace workspace;
    const auto setting = resolve(request, snapshot.defaults);
    // A named track's subarea first (docs/tracks.md "Subarea"), the whole map when no RP there
    // shares an AP with the scan.
    std::optional<match::Result> result;
    if (request.track_subarea) {
        match::Options options = setting.options;
        options.near = request.track_subarea;
        result = match::localize(snapshot.index, request.query, setting.algorithm, options, workspace);
    }
    const bool fell_back = request.track_subarea && !result;
    if (!result) result = match::localize(snapshot.index, request.query, setting.algorithm, setting.options, workspace);
    if (!result)
        throw ApiError(422, "no_match",
                       "no reference point shares an access point with the scan" +
                           std::string(setting.options.near ? " within the 'near' subarea" : ""));
    const auto floor = snapshot.rooms_by_floor.find(result->floor_id);
    const Room* room = floor == snapshot.rooms_by_floor.end() ? nullptr : room_at(floor->second, result->at);
    Writer w;
    w.out.reserve(256 + 160 * result->candidates.size());
    w.raw("{");
    w.key("x").number(result->at.x).key("y").number(result->at.y);
    if (const auto earth = geo ? geo->of_floor(result->floor_id) : nullptr) {
        const auto p = earth->to_geodetic(result->at);
        w.key("lat").number(p.lat).key("lon").number(p.lon);
    }
    w.key("floor_id").integer(result->floor_id).key("building_id").integer(result->building_id);
    w.key("room");
    if (room) w.raw("{").key("id").integer(room->id).key("name").text(room->name).raw("}");
    else w.raw("null");
    // The checkpoints near the estimate (as http/places_json.hpp writes them elsewhere).
    w.key("nearby").raw("[");
    if (const auto floor_places = places ? places->of_floor(result->floor_id) : nullptr) {
        bool first = true;
        for (const auto& n : floor_places->nearby(result->at)) {
            if (!first) w.raw(",");
            first = false;
            w.raw("{").key("poi_id").integer(n.poi->id).key("name").text(n.poi->name).key("kind").text(n.poi->kind);
            w.key("distance_m").number(n.distance_m).raw("}");
        }
    }
    w.raw("]");
    w.key("rps").raw("[");
    for (std::size_t i = 0; i < result->rp_ids.size(); ++i) {
        if (i) w.raw(",");
        w.integer(result->rp_ids[i]);
    }
    w.raw("]");
    if (request.track_id) {
        w.key("subarea");
        if (const auto& near = request.track_subarea)
            w.raw("{").key("x").number(near->at.x).key("y").number(near->at.y).key("radius_m").number(near->radius).key("fell_back").raw(fell_back ? "true" : "false").raw("}");
        else w.raw("null");
    }
    w.key("score").number(result->score).key("matched_aps").integer(result->matched_aps);
    w.key("algorithm").raw("\"").raw(result->algorithm).raw("\"");  // one of our own plain names
    w.key("candidates").raw("[");
    for (std::size_t i = 0; i < result->candidates.size(); ++i) {
        const auto& c = result->candidates[i];
        if (i) w.raw(",");
        if (auto it = snapshot.candidate_json.find(c.rp_id); it != snapshot.candidate_json.end()) {
            w.raw(it->second.head);
            w.number(c.score).raw(it->second.tail);
        } else {
            candidate_head(w, c.rp_id, c.at).number(c.score);
            candidate_tail(w, c.floor_id, c.building_id);
        }
        w.integer(c.matched_aps).raw("}");
    }
    w.raw("]}");
    return std::move(w.out);
}

void prepare_answers(localize::Snapshot& snapshot) {
    snapshot.defaults = settings_of_text(snapshot.settings_text);
    snapshot.candidate_json.clear();
    snapshot.candidate_json.reserve(snapshot.index.size());
    for (std::size_t i = 0; i < snapshot.index.size(); ++i) {
        const auto& rp = snapshot.index.rp(i);
        Writer head, tail;
        candidate_head(head, rp.id, rp.at);
        candidate_tail(tail, rp.floor_id, rp.building_id);
        snapshot.candidate_json[rp.id] = {std::move(head.out), std::move(tail.out)};
    }
}

}  // namespace locus::http
