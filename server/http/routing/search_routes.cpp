// GET /v1/maps/{id}/search?q=…&limit=: the map's directory (rooms, POIs, plan spaces and the
// people and departments tagged on them), best first, each hit with where it is and the
// `route_to` a client posts as the `to` of POST /v1/maps/{id}/route.
#include <cmath>
#include <string>
#include <string_view>

#include "http/app.hpp"
#include "http/validation.hpp"
#include "locus/directory/text.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

inline constexpr std::size_t kMaxQueryLength = 200;  // code points, after trimming
inline constexpr std::int64_t kDefaultLimit = 10, kMaxLimit = 100;

std::string_view trimmed(std::string_view s) {
    const auto first = s.find_first_not_of(" \t\r\n\f\v");
    if (first == std::string_view::npos) return {};
    return s.substr(first, s.find_last_not_of(" \t\r\n\f\v") - first + 1);
}

std::string query_of(const httplib::Request& req) {
    if (!req.has_param("q")) throw invalid_query("'q' is required: the words to look for");
    const std::string raw = req.get_param_value("q");
    const std::string_view q = trimmed(raw);
    if (q.empty()) throw invalid_query("'q' must not be empty");
    if (!directory::is_utf8(q)) throw invalid_query("'q' must be UTF-8 text");
    const std::size_t length = directory::code_points(q);
    if (length > kMaxQueryLength)
        throw invalid_query("'q' is " + std::to_string(length) + " characters long; at most " + std::to_string(kMaxQueryLength));
    return std::string(q);
}

std::int64_t limit_of(const httplib::Request& req) {
    return req.has_param("limit") ? parse_query_integer(req.get_param_value("limit"), "limit", 1, kMaxLimit) : kDefaultLimit;
}

const char* kind_name(directory::PlaceKind k) {
    switch (k) {
        case directory::PlaceKind::room: return "room";
        case directory::PlaceKind::poi: return "poi";
        case directory::PlaceKind::space: return "space";
    }
    return "room";
}

const char* field_name(directory::Field f) {
    switch (f) {
        case directory::Field::name: return "name";
        case directory::Field::tag: return "tag";
        case directory::Field::category: return "category";
    }
    return "name";
}

json hit_json(const directory::Place& p, const directory::Hit& h) {
    json hit = {{"kind", kind_name(p.kind)}};
    if (p.kind != directory::PlaceKind::space) hit["id"] = p.id;
    hit["name"] = p.name;
    if (!p.category.empty()) hit["category"] = p.category;
    hit["matched"] = field_name(h.matched);
    if (h.matched == directory::Field::tag) hit["tag"] = p.tags.at(h.tag);
    hit["tags"] = p.tags;
    hit["floor_id"] = p.floor_id;
    hit["level"] = p.level;
    hit["building_id"] = p.building_id;
    hit["x"] = p.at.x;
    hit["y"] = p.at.y;
    hit["score"] = std::round(h.score * 1000.0) / 1000.0;
    if (!p.routed_by_id) hit["route_to"] = {{"floor_id", p.floor_id}, {"x", p.at.x}, {"y", p.at.y}};
    else if (p.kind == directory::PlaceKind::poi) hit["route_to"] = {{"poi_id", p.id}};
    else hit["route_to"] = {{"room_id", p.id}};
    return hit;
}

}  // namespace

void App::install_search_routes() {
    server_.Get(R"(/v1/maps/(\d+)/search)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto map_id = parse_id(req.matches[1].str(), "map");
            const std::string q = query_of(req);
            const auto limit = limit_of(req);
            const auto dir = directory_.of_map(map_id);  // NotFound for an unknown map
            json hits = json::array();
            for (const auto& h : dir->index.search(q, static_cast<std::size_t>(limit)))
                hits.push_back(hit_json(dir->places[h.document], h));
            return std::pair{200, json{{"query", q}, {"hits", hits}}};
        });
    });
}

}  // namespace locus::http
