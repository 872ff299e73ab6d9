#include "locus/api/client.hpp"

#include <httplib.h>

#include "locus/plan/geojson.hpp"

#include <netdb.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <random>
#include <thread>

namespace locus::api {

using nlohmann::json;

struct Client::Connection {
    explicit Connection(const std::string& base_url) : http(base_url) {}
    httplib::Client http;
};

namespace {

std::string collection(const std::string& parent_kind, std::int64_t parent_id, const std::string& kind) {
    return "/v1/" + parent_kind + "/" + std::to_string(parent_id) + "/" + kind;
}

// The server's error body is {"error": {"code", "message"}}; anything else is reported raw.
ApiError error_from(int status, const std::string& body) {
    const json j = json::parse(body, nullptr, false);
    if (j.is_object() && j.contains("error") && j.at("error").is_object()) {
        const json& e = j.at("error");
        return ApiError(status, e.value("code", "error"), e.value("message", body));
    }
    return ApiError(status, status == 429 ? "too_many_requests" : "http_" + std::to_string(status),
                    body.empty() ? "HTTP " + std::to_string(status) : body.substr(0, 500));
}

template <typename T>
std::vector<T> convert(const std::vector<json>& rows) {
    std::vector<T> out;
    out.reserve(rows.size());
    for (const auto& r : rows) out.push_back(r.get<T>());
    return out;
}

template <typename Info>
std::optional<Info> by_name(const std::vector<Info>& items, const std::string& name) {
    for (const auto& i : items)
        if (i.name == name) return i;
    return std::nullopt;
}

// Find, else create; a 409 means someone created it meanwhile, so look again.
template <typename Info, typename List, typename Create>
Info find_or_create(const std::string& name, List list, Create create) {
    if (auto found = by_name(list(), name)) return *found;
    try {
        return create();
    } catch (const ApiError& e) {
        if (e.status() != 409) throw;
        if (auto found = by_name(list(), name)) return *found;
        throw;
    }
}

// Why a connection to base_url fails ("connection refused", "no route to host", ...): httplib
// only says "Connection", so one plain connect() is tried again for its errno.
std::string connect_failure(const std::string& base_url) {
    std::string rest = base_url;
    std::string port = "80";
    if (const auto p = rest.find("://"); p != std::string::npos) {
        if (rest.compare(0, p, "https") == 0) port = "443";
        rest = rest.substr(p + 3);
    }
    rest = rest.substr(0, rest.find('/'));
    std::string host = rest;
    if (!rest.empty() && rest[0] == '[') {  // [v6]:port
        const auto close = rest.find(']');
        host = rest.substr(1, close == std::string::npos ? std::string::npos : close - 1);
        if (close != std::string::npos && close + 1 < rest.size() && rest[close + 1] == ':') port = rest.substr(close + 2);
    } else if (const auto colon = rest.rfind(':'); colon != std::string::npos) {
        host = rest.substr(0, colon);
        port = rest.substr(colon + 1);
    }
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (const int rc = getaddrinfo(host.c_str(), port.c_str(), &hints, &found); rc != 0) return gai_strerror(rc);
    std::string reason = "cannot connect";
    for (addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
        const int fd = ::socket(ai->ai_family, ai->ai_socktype, ai->ai_protocol);
        if (fd < 0) continue;
        timeval tv{2, 0};  // connect() gives up after the send timeout on Linux
        ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
        const int rc = ::connect(fd, ai->ai_addr, ai->ai_addrlen);
        const int err = errno;
        ::close(fd);
        if (rc == 0) {
            reason = "it accepted a connection just now";
            break;
        }
        reason = err == EINPROGRESS || err == EAGAIN ? "connection timed out" : std::strerror(err);
    }
    freeaddrinfo(found);
    if (!reason.empty()) reason[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(reason[0])));
    return reason;
}

}  // namespace

Client::Client(ClientOptions options) : options_(std::move(options)), conn_(std::make_unique<Connection>(options_.base_url)) {
    auto& h = conn_->http;
    if (!h.is_valid()) throw NetworkError("invalid server URL '" + options_.base_url + "'");
    h.set_keep_alive(true);
    // Headers and body go out in separate writes: with Nagle on, the body waits for the
    // server's delayed ACK (~40 ms per request on Linux loopback).
    h.set_tcp_nodelay(true);
    h.set_connection_timeout(options_.connect_timeout);
    h.set_read_timeout(options_.read_timeout);
    h.set_write_timeout(options_.read_timeout);
    httplib::Headers headers;
    if (!options_.api_key.empty()) headers.emplace("Authorization", "Bearer " + options_.api_key);
    h.set_default_headers(headers);
}

Client::~Client() = default;
Client::Client(Client&&) noexcept = default;
Client& Client::operator=(Client&&) noexcept = default;

json Client::send(const char* method, const std::string& path, const std::string* body, const Headers& headers) {
    const std::string verb = method;
    thread_local std::mt19937 rng{std::random_device{}()};
    std::uniform_real_distribution<double> jitter(0.5, 1.0);
    const httplib::Headers extra(headers.begin(), headers.end());  // beside the defaults (the API key)
    for (int attempt = 1;; ++attempt) {
        httplib::Result r = [&] {
            auto& h = conn_->http;
            if (verb == "GET") return h.Get(path, extra);
            if (verb == "POST") return h.Post(path, extra, *body, "application/json");
            if (verb == "PUT") return h.Put(path, extra, *body, "application/json");
            if (verb == "PATCH") return h.Patch(path, extra, *body, "application/json");
            return h.Delete(path, extra);
        }();
        const int status = r ? r->status : 0;
        if (status >= 200 && status < 300) {
            if (status == 204 || r->body.empty()) return json();
            json j = json::parse(r->body, nullptr, false);
            if (j.is_discarded()) throw ApiError(status, "invalid_json", "the server answered " + verb + " " + path + " with non-JSON");
            return j;
        }
        if (!is_retryable(status) || attempt >= options_.retry.max_attempts) {
            const std::string attempts = std::to_string(attempt) + (attempt == 1 ? " attempt" : " attempts");
            if (!r && (r.error() == httplib::Error::Connection || r.error() == httplib::Error::ConnectionTimeout))
                throw NetworkError("cannot connect to " + options_.base_url + " (" +
                                   (r.error() == httplib::Error::ConnectionTimeout ? std::string("connection timed out")
                                                                                   : connect_failure(options_.base_url)) +
                                   ") after " + attempts + "; is locus-server running?");
            if (!r) throw NetworkError(verb + " " + options_.base_url + path + ": " + httplib::to_string(r.error()) +
                                       " (after " + attempts + ")");
            throw error_from(status, r->body);
        }
        // A Retry-After in seconds from a 429/503 is honoured when it asks for longer.
        auto delay = backoff_delay(options_.retry, attempt, jitter(rng));
        if (r && r->has_header("Retry-After")) {
            const std::string ra = r->get_header_value("Retry-After");
            if (!ra.empty() && ra.find_first_not_of("0123456789") == std::string::npos && ra.size() < 4)
                delay = std::max(delay, std::chrono::milliseconds(std::stoi(ra) * 1000));
        }
        ++retries_;
        std::this_thread::sleep_for(delay);
    }
}

json Client::get(const std::string& path) { return send("GET", path, nullptr); }
json Client::post(const std::string& path, const json& body) {
    const std::string text = body.dump();
    return send("POST", path, &text);
}
json Client::put(const std::string& path, const json& body) {
    const std::string text = body.dump();
    return send("PUT", path, &text);
}
json Client::patch(const std::string& path, const json& body) {
    const std::string text = body.dump();
    return send("PATCH", path, &text);
}
void Client::del(const std::string& path) { send("DELETE", path, nullptr); }

bool Client::healthy() {
    auto r = conn_->http.Get("/health");
    return r && r->status == 200;
}

std::vector<json> Client::list_all(const std::string& collection_path, int page_size) {
    std::vector<json> out;
    const char sep = collection_path.find('?') == std::string::npos ? '?' : '&';
    for (std::int64_t offset = 0;;) {
        const json page = get(collection_path + sep + "limit=" + std::to_string(page_size) + "&offset=" + std::to_string(offset));
        const json& items = page.at("items");
        for (const auto& i : items) out.push_back(i);
        offset += static_cast<std::int64_t>(items.size());
        if (items.empty() || offset >= page.value("total", std::int64_t{0})) break;
    }
    return out;
}

MapInfo Client::create_map(const std::string& name, const std::string& description) {
    return post("/v1/maps", {{"name", name}, {"description", description}}).get<MapInfo>();
}
std::vector<MapInfo> Client::maps() { return convert<MapInfo>(list_all("/v1/maps")); }

BuildingInfo Client::create_building(std::int64_t map_id, const std::string& name, const std::string& description) {
    return post(collection("maps", map_id, "buildings"), {{"name", name}, {"description", description}}).get<BuildingInfo>();
}
std::vector<BuildingInfo> Client::buildings(std::int64_t map_id) {
    return convert<BuildingInfo>(list_all(collection("maps", map_id, "buildings")));
}

FloorInfo Client::create_floor(const FloorInfo& f) {
    return post(collection("buildings", f.building_id, "floors"),
                                {{"name", f.name},
                                 {"level", f.level},
                                 {"width", f.width},
                                 {"height", f.height},
                                 {"north_offset_deg", f.north_offset_deg}}).get<FloorInfo>();
}
std::vector<FloorInfo> Client::floors(std::int64_t building_id) {
    return convert<FloorInfo>(list_all(collection("buildings", building_id, "floors")));
}
FloorInfo Client::floor(std::int64_t floor_id) { return get("/v1/floors/" + std::to_string(floor_id)).get<FloorInfo>(); }

RoomInfo Client::create_room(const RoomInfo& room) {
    return post(collection("floors", room.floor_id, "rooms"), {{"name", room.name}, {"rects", room.rects}}).get<RoomInfo>();
}
std::vector<RoomInfo> Client::rooms(std::int64_t floor_id) {
    return convert<RoomInfo>(list_all(collection("floors", floor_id, "rooms")));
}

PoiInfo Client::create_poi(const PoiInfo& poi) {
    return post(collection("floors", poi.floor_id, "pois"),
                              {{"name", poi.name}, {"kind", poi.kind}, {"x", poi.at.x}, {"y", poi.at.y}}).get<PoiInfo>();
}
std::vector<PoiInfo> Client::pois(std::int64_t floor_id) {
    return convert<PoiInfo>(list_all(collection("floors", floor_id, "pois")));
}

RadioMapInfo Client::create_radiomap(std::int64_t floor_id, const std::string& name, const std::string& description) {
    return post(collection("floors", floor_id, "radiomaps"), {{"name", name}, {"description", description}}).get<RadioMapInfo>();
}
std::vector<RadioMapInfo> Client::radiomaps(std::int64_t floor_id) {
    return convert<RadioMapInfo>(list_all(collection("floors", floor_id, "radiomaps")));
}
RadioMapInfo Client::radiomap(std::int64_t radiomap_id) {
    return get("/v1/radiomaps/" + std::to_string(radiomap_id)).get<RadioMapInfo>();
}

RpInfo Client::create_rp(std::int64_t radiomap_id, const std::string& name, double x, double y) {
    return post(collection("radiomaps", radiomap_id, "rps"), {{"name", name}, {"x", x}, {"y", y}}).get<RpInfo>();
}
std::vector<RpInfo> Client::rps(std::int64_t radiomap_id) {
    return convert<RpInfo>(list_all(collection("radiomaps", radiomap_id, "rps")));
}
RpInfo Client::rp(std::int64_t rp_id) { return get("/v1/rps/" + std::to_string(rp_id)).get<RpInfo>(); }

MapInfo Client::ensure_map(const std::string& name, const std::string& description) {
    return find_or_create<MapInfo>(name, [&] { return maps(); }, [&] { return create_map(name, description); });
}
BuildingInfo Client::ensure_building(std::int64_t map_id, const std::string& name, const std::string& description) {
    return find_or_create<BuildingInfo>(name, [&] { return buildings(map_id); },
                                        [&] { return create_building(map_id, name, description); });
}
FloorInfo Client::ensure_floor(const FloorInfo& f) {
    return find_or_create<FloorInfo>(f.name, [&] { return floors(f.building_id); }, [&] { return create_floor(f); });
}
RadioMapInfo Client::ensure_radiomap(std::int64_t floor_id, const std::string& name, const std::string& description) {
    return find_or_create<RadioMapInfo>(name, [&] { return radiomaps(floor_id); },
                                        [&] { return create_radiomap(floor_id, name, description); });
}
RpInfo Client::ensure_rp(std::int64_t radiomap_id, const std::string& name, double x, double y) {
    return find_or_create<RpInfo>(name, [&] { return rps(radiomap_id); }, [&] { return create_rp(radiomap_id, name, x, y); });
}

UploadResult Client::upload(std::int64_t rp_id, const ScanUpload& u) {
    ScanUpload body = u;
    if (!body.upload_id) {
        thread_local std::mt19937_64 rng{std::random_device{}()};
        body.upload_id = "client-" + std::to_string(rng()) + "-" + std::to_string(++upload_counter_);
    }
    const json answer = post("/v1/rps/" + std::to_string(rp_id) + "/scans", body);
    return {answer.value("applied", false), answer.at("rp").get<RpInfo>()};
}

json Client::export_radiomap(std::int64_t radiomap_id) { return get("/v1/radiomaps/" + std::to_string(radiomap_id) + "/export"); }

RadioMapInfo Client::import_radiomap(std::int64_t floor_id, const json& document) {
    return post("/v1/floors/" + std::to_string(floor_id) + "/radiomaps/import", document).get<RadioMapInfo>();
}

namespace {

// The server checked the plan before storing it, so a document the codec refuses is the
// server's fault (or not a Locus server): reported as its answer, like non-JSON.
plan::Plan plan_from_answer(const json& doc, const std::string& path) {
    try {
        return plan::from_geojson(doc);
    } catch (const plan::GeoJsonError& e) {
        throw ApiError(200, "invalid_plan", "the server answered " + path + " with a plan the client cannot read: " + e.what());
    }
}

std::string plan_path(std::int64_t floor_id) { return "/v1/floors/" + std::to_string(floor_id) + "/plan"; }

}  // namespace

std::optional<plan::Plan> Client::plan(std::int64_t floor_id) {
    const std::string path = plan_path(floor_id);
    json doc;
    try {
        doc = get(path);
    } catch (const ApiError& e) {
        if (e.status() != 404) throw;
        // 404 is both "no such floor" and "the floor has no plan": only the floor tells.
        floor(floor_id);  // throws the server's not_found for an unknown floor
        return std::nullopt;
    }
    return plan_from_answer(doc, path);
}

plan::Plan Client::put_plan(std::int64_t floor_id, const plan::Plan& plan) {
    const std::string path = plan_path(floor_id);
    return plan_from_answer(put(path, plan::to_geojson(plan)), path);
}

LocalizeResult Client::localize_radiomap(std::int64_t radiomap_id, const LocalizeRequest& request) {
    return post("/v1/radiomaps/" + std::to_string(radiomap_id) + "/localize", request).get<LocalizeResult>();
}
LocalizeResult Client::localize_map(std::int64_t map_id, const LocalizeRequest& request) {
    return post("/v1/maps/" + std::to_string(map_id) + "/localize", request).get<LocalizeResult>();
}

}  // namespace locus::api
