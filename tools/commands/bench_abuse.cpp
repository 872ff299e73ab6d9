// `locus bench abuse`: can one hostile client without the API key take a running server on
// loopback away from its phones? For --seconds, from one source address (--hostile-address,
// 127.0.0.2 by default), it runs at once:
// - bombs: localize and scan-upload bodies that are small compressed and huge decoded
//   (gzip of 512 MiB of whitespace, about 500 KB), and bodies in a coding the server does not
//   take (br);
// - a track flood: opening tracks back to back and keeping each alive with a fix;
// - a stream flood: event streams on its tracks, held open;
// - a route flood: route, search and map-wide localize requests back to back.
// Meanwhile --phones well-behaved phones, each from its own address (127.0.0.3 and up), open a
// track, then once per --phone-interval localize a scan and post the fix to their track.
//
// `--scenario route-build` instead: the setup (with --api-key) adds a map of two large floors
// (--big-floor-m square, eight stairs between them, under the server's default route-graph
// bound), which also drops every map's kept route graph; the hostile client then asks for
// routes across that map back to back (the first builds its graph), while the phones route
// between two rooms of --map once per --phone-interval (its graph rebuilt first). The map is
// deleted at the end.
//
// `--scenario streams`: --stream-holders clients (127.0.1.1 and up, no key) each open a track
// and hold as many event streams on it as the server lets them; then a phone opens a track and
// its own stream, which must be answered 200 (the holders' shares fill the server's cap, so it
// takes the place of the biggest holder's oldest).
//
// `--scenario fixes`: the hostile client opens two tracks and posts 1,000-fix batches to them
// back to back while the phones localize and post as above; with --db, how much the server's
// SQLite file and its WAL grew.
//
// `--scenario bodies`: --body-connections connections of the hostile client post 8 MiB
// localize bodies of empty scans back to back; `--scenario slow-bodies`: each connection sends
// all but the last bytes of one, then a byte every 4 s. The phones localize as above.
//
// `--scenario slow-readers`: the setup adds a map with a 5.6 MB plan; each connection asks for
// it and reads 1 KB every 5 s. The map is deleted at the end.
//
// `--scenario steps-scans`: the hostile client opens --scan-tracks tracks and posts /steps
// batches of 1,000 WiFi scans (the radio map's own RPs' means, each a scan to localize) to
// them back to back; reported: the scans the server localized for it per second (its
// `scan_fixes`), its answers, and with --server-pid the server's CPU time per second of the run.
//
// Prints one JSON object: what the phones saw (localize or route latency, refused track opens
// and fixes) and what the hostile client got (answers by status), with the server's peak
// resident memory above idle when --server-pid names it. Exits non-zero if a phone was refused
// or the hostile client ever got a 5xx. Loopback only; bounded in time (≤ 120 s) and
// connections. The setup sends --api-key; the phones and the hostile client never do.
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <deque>
#include <string_view>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench_connection.hpp"
#include "bench_load.hpp"
#include "command_registry.hpp"
#include "compressed_body.hpp"
#include "proc_status.hpp"
#include "survey_connect.hpp"

namespace locus_cli_bench_abuse {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Args {
    ServerArgs server;
    std::int64_t map = 0, radiomap = 0;
    int phones = 100;
    double seconds = 20.0, phone_interval = 1.0;
    std::string hostile_address = "127.0.0.2";
    int server_pid = 0;
    int max_streams = 200;  // streams the hostile client tries to hold at once
    std::string scenario = "all";
    int stream_holders = 10;  // streams: clients filling the server's streams
    std::string db;  // fixes: the server's SQLite file, whose growth is reported
    int body_connections = 24;  // bodies, slow-bodies: the hostile client's connections
    double big_floor_m = 290.0;  // route-build: the big map's floors' side (180 MB, under the default bound)
    int scan_tracks = 4;  // steps-scans: the hostile client's tracks
};

// Answers by status, counted from several threads.
class StatusCounts {
public:
    void add(std::optional<int> status) {
        std::lock_guard lock(mu_);
        ++counts_[status ? std::to_string(*status) : "no_answer"];
    }
    json to_json() const {
        std::lock_guard lock(mu_);
        return counts_;
    }
    bool any_server_error() const {
        std::lock_guard lock(mu_);
        return std::any_of(counts_.begin(), counts_.end(), [](const auto& c) { return c.first[0] == '5'; });
    }

private:
    mutable std::mutex mu_;
    std::map<std::string, int> counts_;
};

// "127.0.0.3" + i: the i-th phone's own loopback address.
std::string phone_address(int i) {
    const int n = 3 + i;
    return "127.0." + std::to_string(n / 256) + "." + std::to_string(n % 256);
}

struct OpenedTrack {
    std::string id, token;
};

std::optional<OpenedTrack> open_track(BenchConnection& c, const std::string& request) {
    std::string body;
    const auto status = c.round_trip(request, &body);
    if (status != 201) return std::nullopt;
    const json j = json::parse(body, nullptr, false);
    if (!j.is_object() || !j.contains("id") || !j.contains("token")) return std::nullopt;
    return OpenedTrack{std::to_string(j["id"].get<long long>()), j["token"].get<std::string>()};
}

std::string fix_request(const OpenedTrack& t, std::int64_t floor_id, double x, double y, const std::string& host_port) {
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    const json body = {{"fixes", json::array({{{"t", now}, {"floor_id", floor_id}, {"x", x}, {"y", y}, {"accuracy_m", 3.0}}})}};
    return http_request("POST", "/v1/tracks/" + t.id + "/fixes", host_port, body.dump(), "X-Track-Token: " + t.token + "\r\n");
}

// An event stream held open: the head is read for its status, the rest left in the socket.
struct HeldStream {
    int fd = -1;
    ~HeldStream() {
        if (fd >= 0) ::close(fd);
    }
};

std::optional<int> open_stream(const Target& target, const std::string& source, const std::string& path, HeldStream& held) {
    held.fd = open_socket(target.host, target.port, source);
    if (held.fd < 0) return std::nullopt;
    const std::string request = http_request("GET", path, target.host_port);
    if (::send(held.fd, request.data(), request.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(request.size())) return std::nullopt;
    std::string head;
    char c[4096];
    while (head.find("\r\n\r\n") == std::string::npos && head.size() < 65536) {
        pollfd p{held.fd, POLLIN, 0};
        if (::poll(&p, 1, 10'000) <= 0) return std::nullopt;
        const ssize_t n = ::recv(held.fd, c, sizeof c, 0);
        if (n <= 0) break;
        head.append(c, static_cast<std::size_t>(n));
    }
    if (!head.starts_with("HTTP/1.1 ") || head.size() < 12) return std::nullopt;
    return std::stoi(head.substr(9, 3));
}

// --phones well-behaved phones, each from its own address: open a track, then once per
// --phone-interval localize a scan on --radiomap and post the fix to the track.
class LocalizingPhones {
public:
    LocalizingPhones(const Args& a, const Target& target, std::int64_t floor_id)
        : a_(a),
          target_(target),
          floor_id_(floor_id),
          bodies_(localize_bodies(a.server, a.radiomap, "", "wknn")),
          localize_path_("/v1/radiomaps/" + std::to_string(a.radiomap) + "/localize"),
          open_request_(http_request("POST", "/v1/tracks", target.host_port, json{{"map_id", a.map}}.dump())),
          localize_ms_(static_cast<std::size_t>(a.phones)) {}

    // Until running() says no; returns once every phone has stopped.
    void run(const std::function<bool()>& running) {
        const auto deadline = Clock::now() + std::chrono::seconds(130);  // past the longest --seconds
        std::vector<std::thread> phones;
        for (int p = 0; p < a_.phones; ++p)
            phones.emplace_back([&, p] {
                BenchConnection c(target_.host, target_.port, phone_address(p));
                // Spread over the first interval, as phones arrive.
                std::this_thread::sleep_for(std::chrono::duration<double>(a_.phone_interval * p / std::max(1, a_.phones)));
                const auto track = open_track(c, open_request_);
                if (!track) {
                    ++opens_refused_;
                    return;
                }
                ++opens_ok_;
                auto next = Clock::now();
                for (std::size_t i = static_cast<std::size_t>(p); running(); i += static_cast<std::size_t>(a_.phones)) {
                    const auto s = Clock::now();
                    std::string body;
                    const auto status = c.round_trip(http_request("POST", localize_path_, target_.host_port, bodies_[i % bodies_.size()]), &body);
                    if (status != 200) {
                        ++localize_errors_;
                    } else {
                        localize_ms_[static_cast<std::size_t>(p)].push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
                        const json fix = json::parse(body, nullptr, false);
                        const auto posted =
                            c.round_trip(fix_request(*track, floor_id_, fix.value("x", 0.0), fix.value("y", 0.0), target_.host_port));
                        (posted == 200 || posted == 201 ? fixes_ok_ : fixes_refused_)++;
                    }
                    next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a_.phone_interval));
                    while (running() && Clock::now() < std::min(next, deadline)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
                }
            });
        for (auto& t : phones) t.join();
    }

    int refused() const { return opens_refused_ + fixes_refused_ + localize_errors_; }
    // The localize bodies the phones send (each RP of --radiomap queried with its own means).
    const std::vector<std::string>& bodies() const { return bodies_; }
    json to_json() const {
        std::vector<double> all;
        for (const auto& v : localize_ms_) all.insert(all.end(), v.begin(), v.end());
        json localize = latency_percentiles(all);
        localize["max_ms"] = all.empty() ? 0.0 : *std::max_element(all.begin(), all.end());
        localize["requests"] = all.size() + static_cast<std::size_t>(localize_errors_.load());
        localize["errors"] = localize_errors_.load();
        return {{"n", a_.phones},
                {"localize", localize},
                {"track_opens", {{"ok", opens_ok_.load()}, {"refused", opens_refused_.load()}}},
                {"fixes", {{"ok", fixes_ok_.load()}, {"refused", fixes_refused_.load()}}}};
    }

private:
    const Args& a_;
    Target target_;
    std::int64_t floor_id_;
    std::vector<std::string> bodies_;
    std::string localize_path_, open_request_;
    std::vector<std::vector<double>> localize_ms_;
    std::atomic<int> opens_ok_{0}, opens_refused_{0}, fixes_ok_{0}, fixes_refused_{0}, localize_errors_{0};
};

// Two rooms of the map's first floor that has a plan and two rooms: the phones' route.
json room_route(api::Client& setup, std::int64_t map_id) {
    for (const auto& b : setup.buildings(map_id))
        for (const auto& f : setup.floors(b.id)) {
            const auto rooms = setup.rooms(f.id);
            if (rooms.size() >= 2 && setup.plan(f.id))
                return {{"from", {{"room_id", rooms.front().id}}}, {"to", {{"room_id", rooms.back().id}}}};
        }
    throw CommandError("map " + std::to_string(map_id) + " has no floor with a plan and two rooms to route between");
}

// A floor plan: one side × side hall with eight stairs linked to the same stairs of `other`.
json big_plan(double side, std::int64_t other) {
    json ring = json::array();
    for (const auto& [x, y] : {std::pair{0.0, 0.0}, {side, 0.0}, {side, side}, {0.0, side}, {0.0, 0.0}}) ring.push_back(json::array({x, y}));
    json features = json::array();
    features.push_back({{"type", "Feature"},
                        {"properties", {{"feature", "space"}, {"name", "Hall"}}},
                        {"geometry", {{"type", "Polygon"}, {"coordinates", json::array({ring})}}}});
    for (int k = 0; k < 8; ++k) {
        const std::string id = "s" + std::to_string(k);
        features.push_back({{"type", "Feature"},
                            {"properties", {{"feature", "connector"}, {"id", id}, {"kind", "stairs"}, {"links", {{{"floor_id", other}, {"connector", id}}}}}},
                            {"geometry", {{"type", "Point"}, {"coordinates", {side * (k + 1) / 9.0, side * ((k * 5) % 8 + 1) / 9.0}}}}});
    }
    return {{"type", "FeatureCollection"}, {"features", features}};
}

void run_route_build(const Args& a) {
    const Target target = loopback_target(a.server.client_options().base_url, "bench abuse");
    api::Client setup(a.server.client_options());
    const std::string hp = target.host_port;
    const json phone_body = room_route(setup, a.map);
    const std::string phone_route = http_request("POST", "/v1/maps/" + std::to_string(a.map) + "/route", hp, phone_body.dump());

    const auto big = setup.create_map("bench abuse route-build " + std::to_string(::getpid()) + " " +
                                      std::to_string(std::chrono::system_clock::now().time_since_epoch().count()));
    const auto building = setup.create_building(big.id, "Big");
    std::int64_t floors[2];
    for (int i = 0; i < 2; ++i) {
        api::FloorInfo f;
        f.building_id = building.id;
        f.name = "Floor " + std::to_string(i);
        f.level = i;
        f.width = f.height = a.big_floor_m;
        floors[i] = setup.create_floor(f).id;
    }
    for (int i = 0; i < 2; ++i) setup.put("/v1/floors/" + std::to_string(floors[i]) + "/plan", big_plan(a.big_floor_m, floors[1 - i]));
    const double far = a.big_floor_m * 0.95;
    const std::string hostile_route = http_request(
        "POST", "/v1/maps/" + std::to_string(big.id) + "/route", hp,
        json{{"from", {{"floor_id", floors[0]}, {"x", 1.0}, {"y", 1.0}}}, {"to", {{"floor_id", floors[1]}, {"x", far}, {"y", far}}}}.dump());

    const long long idle_rss_kb = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
    auto running = [&] { return Clock::now() < deadline; };
    StatusCounts hostile_routes;
    std::atomic<double> first_answer_s{-1.0};
    std::thread hostile([&] {
        BenchConnection c(target.host, target.port, a.hostile_address);
        while (running()) {
            hostile_routes.add(c.round_trip(hostile_route));
            double unset = -1.0;
            first_answer_s.compare_exchange_strong(unset, std::chrono::duration<double>(Clock::now() - t0).count());
        }
    });
    // The phones start once the hostile client's build is under way.
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    std::vector<std::vector<double>> route_ms(static_cast<std::size_t>(a.phones));
    std::atomic<int> route_errors{0};
    std::vector<std::thread> phones;
    for (int p = 0; p < a.phones; ++p)
        phones.emplace_back([&, p] {
            BenchConnection c(target.host, target.port, phone_address(p));
            std::this_thread::sleep_for(std::chrono::duration<double>(a.phone_interval * p / std::max(1, a.phones)));
            auto next = Clock::now();
            while (running()) {
                const auto s = Clock::now();
                if (c.round_trip(phone_route) == 200)
                    route_ms[static_cast<std::size_t>(p)].push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
                else
                    ++route_errors;
                next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.phone_interval));
                std::this_thread::sleep_until(std::min(next, deadline));
            }
        });
    for (auto& t : phones) t.join();
    hostile.join();
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    setup.del("/v1/maps/" + std::to_string(big.id));

    std::vector<double> all;
    for (auto& v : route_ms) all.insert(all.end(), v.begin(), v.end());
    json route = latency_percentiles(all);
    route["max_ms"] = all.empty() ? 0.0 : all.back();
    route["requests"] = all.size() + static_cast<std::size_t>(route_errors.load());
    route["errors"] = route_errors.load();
    json out = {{"scenario", "route-build"},
                {"seconds", elapsed},
                {"big_map", {{"floors", 2}, {"side_m", a.big_floor_m}, {"stairs", 8}}},
                {"phones", {{"n", a.phones}, {"route", route}}},
                {"hostile", {{"address", a.hostile_address}, {"routes", hostile_routes.to_json()}, {"first_answer_s", first_answer_s.load()}}}};
    if (a.server_pid) {
        const long long peak = proc_status_kb(a.server_pid, "VmHWM:");
        out["server"] = {{"rss_idle_mb", idle_rss_kb / 1024.0}, {"peak_mb", peak / 1024.0}, {"peak_above_idle_mb", (peak - idle_rss_kb) / 1024.0}};
    }
    std::cout << out.dump() << "\n";
    if (route_errors > 0 || hostile_routes.any_server_error())
        throw CommandError(std::to_string(route_errors.load()) + " phone routes refused" +
                           (hostile_routes.any_server_error() ? "; the hostile client got a 5xx" : ""));
}

void run_streams(const Args& a) {
    const Target target = loopback_target(a.server.client_options().base_url, "bench abuse");
    const std::string open_request = http_request("POST", "/v1/tracks", target.host_port, json{{"map_id", a.map}}.dump());
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
    // Each holder opens streams on its own track until refused (or --hostile-streams in all).
    std::vector<std::unique_ptr<HeldStream>> held;
    json holders = json::array();
    std::size_t total = 0;
    for (int h = 0; h < a.stream_holders && Clock::now() < deadline; ++h) {
        const std::string address = "127.0." + std::to_string(1 + h / 250) + "." + std::to_string(1 + h % 250);
        BenchConnection c(target.host, target.port, address);
        const auto track = open_track(c, open_request);
        if (!track) throw CommandError("holder " + address + " could not open a track");
        StatusCounts answers;
        int n = 0;
        while (total < static_cast<std::size_t>(a.max_streams) && Clock::now() < deadline) {
            auto s = std::make_unique<HeldStream>();
            const auto status = open_stream(target, address, "/v1/tracks/" + track->id + "/events?token=" + track->token, *s);
            answers.add(status);
            if (status != 200) break;
            held.push_back(std::move(s));
            ++n;
            ++total;
        }
        holders.push_back({{"address", address}, {"held", n}, {"answers", answers.to_json()}});
    }
    // The phone: its own track and its own stream.
    BenchConnection phone(target.host, target.port, phone_address(0));
    const auto track = open_track(phone, open_request);
    std::optional<int> status;
    double open_ms = 0.0;
    if (track) {
        HeldStream own;
        const auto s = Clock::now();
        status = open_stream(target, phone_address(0), "/v1/tracks/" + track->id + "/events?token=" + track->token, own);
        open_ms = std::chrono::duration<double, std::milli>(Clock::now() - s).count();
    }
    json out = {{"scenario", "streams"},
                {"seconds", std::chrono::duration<double>(Clock::now() - t0).count()},
                {"holders", holders},
                {"held", total},
                {"phone", {{"track_opened", track.has_value()}, {"stream_status", status ? json(*status) : json(nullptr)}, {"open_ms", open_ms}}}};
    std::cout << out.dump() << "\n";
    if (!track || status != 200)
        throw CommandError("the phone's own stream was not opened (" + (status ? std::to_string(*status) : std::string("no answer")) + ")");
}

// The database file's bytes with its write-ahead log; 0 for a file that is not there.
std::uintmax_t database_bytes(const std::string& path) {
    std::uintmax_t total = 0;
    for (const auto& f : {path, path + "-wal"}) {
        std::error_code ec;
        const auto n = std::filesystem::file_size(f, ec);
        if (!ec) total += n;
    }
    return total;
}

// Up to n tracks on --map opened by the hostile client (its opens are rate-limited too); at
// least one, or the run has nothing to flood.
std::vector<OpenedTrack> hostile_tracks(const Args& a, const Target& target, int n) {
    const std::string open_request = http_request("POST", "/v1/tracks", target.host_port, json{{"map_id", a.map}}.dump());
    std::vector<OpenedTrack> tracks;
    BenchConnection c(target.host, target.port, a.hostile_address);
    for (int k = 0; k < n; ++k)
        if (auto t = open_track(c, open_request)) tracks.push_back(*t);
    if (tracks.empty()) throw CommandError("the hostile client could not open a track");
    return tracks;
}

void run_fixes(const Args& a) {
    if (a.radiomap <= 0) throw CommandError("--radiomap is required with --scenario fixes: the phones localize against it");
    const Target target = loopback_target(a.server.client_options().base_url, "bench abuse");
    api::Client setup(a.server.client_options());
    const std::int64_t floor_id = setup.radiomap(a.radiomap).floor_id;
    const std::vector<OpenedTrack> tracks = hostile_tracks(a, target, 2);
    const std::uintmax_t db_before = a.db.empty() ? 0 : database_bytes(a.db);
    const long long idle_rss_kb = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
    auto running = [&] { return Clock::now() < deadline; };
    // Each batch a thousand fixes a millisecond apart, batch after batch a second apart, an
    // hour ago: all new, all within the retention period.
    const double start = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count() - 3600;
    StatusCounts posts;
    std::atomic<long long> stored{0};
    std::vector<std::thread> hostile;
    for (const auto& t : tracks)
        hostile.emplace_back([&, t] {
            BenchConnection c(target.host, target.port, a.hostile_address);
            for (int batch = 0; running();) {
                json fixes = json::array();
                for (int i = 0; i < 1000; ++i)
                    fixes.push_back({{"t", start + batch + i * 1e-3}, {"floor_id", floor_id}, {"x", 1.0 + i % 10}, {"y", 1.0}, {"accuracy_m", 3.0}});
                std::string body;
                const auto status = c.round_trip(http_request("POST", "/v1/tracks/" + t.id + "/fixes", target.host_port,
                                                              json{{"fixes", fixes}}.dump(), "X-Track-Token: " + t.token + "\r\n"),
                                                 &body);
                posts.add(status);
                if (status != 200) continue;
                stored += json::parse(body, nullptr, false).value("stored", 0LL);
                ++batch;  // the next second: refused batches would otherwise drift past the server's clock
            }
        });
    LocalizingPhones phones(a, target, floor_id);
    phones.run(running);
    for (auto& t : hostile) t.join();
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    json out = {{"scenario", "fixes"},
                {"seconds", elapsed},
                {"phones", phones.to_json()},
                {"hostile", {{"address", a.hostile_address}, {"tracks", tracks.size()}, {"posts", posts.to_json()}, {"fixes_stored", stored.load()}}}};
    if (!a.db.empty()) out["database"] = {{"file", a.db}, {"growth_mb", (static_cast<double>(database_bytes(a.db)) - static_cast<double>(db_before)) / 1e6}};
    if (a.server_pid) {
        const long long peak = proc_status_kb(a.server_pid, "VmHWM:");
        out["server"] = {{"rss_idle_mb", idle_rss_kb / 1024.0}, {"peak_mb", peak / 1024.0}, {"peak_above_idle_mb", (peak - idle_rss_kb) / 1024.0}};
    }
    std::cout << out.dump() << "\n";
    if (phones.refused() > 0 || posts.any_server_error())
        throw CommandError(std::to_string(phones.refused()) + " phone requests refused" + (posts.any_server_error() ? "; the hostile client got a 5xx" : ""));
}

// The status of an answer's first bytes ("HTTP/1.1 429 …"), or nullopt.
std::optional<int> status_line(std::string_view head) {
    if (head.size() < 12 || !head.starts_with("HTTP/1.1 ")) return std::nullopt;
    int status = 0;
    for (const char c : head.substr(9, 3)) {
        if (c < '0' || c > '9') return std::nullopt;
        status = status * 10 + (c - '0');
    }
    return status;
}

// An 8 MiB localize body of empty scans, `{"scans":[[],[],…]}`: what the parser once read
// into millions of empty scans (some 110 MiB a body).
std::string empty_scans_body(std::size_t bytes) {
    std::string body = R"({"scans":[[])";
    while (body.size() + 5 < bytes) body += ",[]";
    return body + "]}";
}

// The phones' figures, the hostile client's answers and the server's peak memory, as one
// object; throws when a phone was refused or the hostile client got a 5xx other than 503.
void report(json out, const LocalizingPhones& phones, const StatusCounts& hostile, const Args& a, long long idle_rss_kb) {
    out["phones"] = phones.to_json();
    out["hostile"] = {{"address", a.hostile_address}, {"answers", hostile.to_json()}};
    if (a.server_pid) {
        const long long peak = proc_status_kb(a.server_pid, "VmHWM:");
        out["server"] = {{"rss_idle_mb", idle_rss_kb / 1024.0}, {"peak_mb", peak / 1024.0}, {"peak_above_idle_mb", (peak - idle_rss_kb) / 1024.0}};
    }
    std::cout << out.dump() << "\n";
    const json answers = hostile.to_json();
    bool server_error = false;
    for (const auto& [status, n] : answers.items()) server_error = server_error || (status[0] == '5' && status != "503");
    if (phones.refused() > 0 || server_error)
        throw CommandError(std::to_string(phones.refused()) + " phone requests refused" + (server_error ? "; the hostile client got a 5xx" : ""));
}

// `--scenario bodies`: --body-connections connections of the hostile client post 8 MiB bodies
// of empty scans back to back; `--scenario slow-bodies`: --body-connections connections each
// send all but the last byte of one, then a byte every 4 s.
void run_bodies(const Args& a, bool slow) {
    if (a.radiomap <= 0) throw CommandError("--radiomap is required with --scenario " + a.scenario + ": the phones localize against it");
    const Target target = loopback_target(a.server.client_options().base_url, "bench abuse");
    api::Client setup(a.server.client_options());
    const std::int64_t floor_id = setup.radiomap(a.radiomap).floor_id;
    const std::string request =
        http_request("POST", "/v1/radiomaps/" + std::to_string(a.radiomap) + "/localize", target.host_port, empty_scans_body(8u << 20));
    const long long idle_rss_kb = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
    auto running = [&] { return Clock::now() < deadline; };
    StatusCounts answers;
    std::vector<std::thread> hostile;
    for (int k = 0; k < a.body_connections; ++k)
        hostile.emplace_back([&] {
            if (!slow) {
                BenchConnection c(target.host, target.port, a.hostile_address);
                while (running()) answers.add(c.round_trip(request));
                return;
            }
            // All but the last byte, then a byte every 4 s: answered (refused, or cut at the
            // body's time limit) or still held at the end.
            HeldStream held;
            held.fd = open_socket(target.host, target.port, a.hostile_address);
            if (held.fd < 0) return answers.add(std::nullopt);
            std::size_t sent = 0;
            std::optional<int> status;
            auto answered = [&] {
                pollfd p{held.fd, POLLIN, 0};
                if (::poll(&p, 1, 0) <= 0) return false;
                char head[64] = {};
                const ssize_t n = ::recv(held.fd, head, sizeof head - 1, 0);
                if (const auto got = status_line(std::string_view(head, static_cast<std::size_t>(std::max<ssize_t>(n, 0))))) status = got;
                return true;
            };
            while (running() && sent + 1 < request.size() && !answered()) {
                const std::size_t n = std::min<std::size_t>(64 * 1024, request.size() - 1 - sent);
                const ssize_t w = ::send(held.fd, request.data() + sent, n, MSG_NOSIGNAL);
                if (w <= 0) break;
                sent += static_cast<std::size_t>(w);
            }
            auto next = Clock::now();
            while (running() && !answered()) {
                if (Clock::now() >= next && sent + 1 < request.size()) {
                    if (::send(held.fd, request.data() + sent, 1, MSG_NOSIGNAL) <= 0) break;
                    ++sent;
                    next += std::chrono::seconds(4);
                }
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
            if (status) answers.add(status);
            else answers.add(std::nullopt);
        });
    LocalizingPhones phones(a, target, floor_id);
    phones.run(running);
    for (auto& t : hostile) t.join();
    report({{"scenario", a.scenario}, {"seconds", std::chrono::duration<double>(Clock::now() - t0).count()}, {"connections", a.body_connections}},
           phones, answers, a, idle_rss_kb);
}

// A plan of `walls` short walls on a 30 m × 20 m floor: some 110 bytes of answer a wall.
json walls_plan(int walls) {
    json features = json::array();
    for (int i = 0; i < walls; ++i) {
        const double x = 0.5 + (i % 230) * 0.125, y = 0.5 + (i / 230) * 0.0625;
        features.push_back({{"type", "Feature"},
                            {"properties", {{"feature", "wall"}}},
                            {"geometry", {{"type", "LineString"}, {"coordinates", {{x, y}, {x, y + 0.03125}}}}}});
    }
    return {{"type", "FeatureCollection"}, {"features", features}};
}

// `--scenario slow-readers`: the setup (with the key) adds a map whose floor has a plan of
// 50,000 walls (a 5.6 MB answer); --body-connections connections of the hostile client ask for
// it and read 1 KB every 5 s. Each is cut when its answer's time is up (or refused at once);
// the map is deleted at the end.
void run_slow_readers(const Args& a) {
    if (a.radiomap <= 0) throw CommandError("--radiomap is required with --scenario slow-readers: the phones localize against it");
    const Target target = loopback_target(a.server.client_options().base_url, "bench abuse");
    api::Client setup(a.server.client_options());
    const std::int64_t floor_id = setup.radiomap(a.radiomap).floor_id;
    const auto big = setup.create_map("bench abuse slow-readers " + std::to_string(::getpid()));
    const auto building = setup.create_building(big.id, "Big");
    api::FloorInfo f;
    f.building_id = building.id;
    f.name = "Walls";
    f.width = 30;
    f.height = 20;
    const std::int64_t plan_floor = setup.create_floor(f).id;
    const std::string plan_path = "/v1/floors/" + std::to_string(plan_floor) + "/plan";
    setup.put(plan_path, walls_plan(50'000));
    const std::string request = http_request("GET", plan_path, target.host_port);

    const long long idle_rss_kb = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
    auto running = [&] { return Clock::now() < deadline; };
    StatusCounts answers;
    std::atomic<int> cut{0}, held_to_end{0};
    // The phones open their tracks first: the readers' answers then cost the server its CPU too.
    LocalizingPhones phones(a, target, floor_id);
    std::thread phone_thread([&] { phones.run(running); });
    std::this_thread::sleep_for(std::chrono::seconds(1));
    std::vector<std::thread> hostile;
    for (int k = 0; k < a.body_connections; ++k)
        hostile.emplace_back([&] {
            HeldStream held;
            held.fd = open_socket(target.host, target.port, a.hostile_address);
            if (held.fd < 0) return answers.add(std::nullopt);
            const int small = 4096;
            ::setsockopt(held.fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
            if (::send(held.fd, request.data(), request.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(request.size()))
                return answers.add(std::nullopt);
            char buf[1024];
            bool first = true;
            while (running()) {
                pollfd p{held.fd, POLLIN, 0};
                if (::poll(&p, 1, 100) <= 0) continue;
                const ssize_t n = ::recv(held.fd, buf, sizeof buf, 0);
                if (n <= 0) {
                    ++cut;
                    return;
                }
                if (first) {
                    first = false;
                    answers.add(status_line(std::string_view(buf, static_cast<std::size_t>(n))));
                }
                for (int w = 0; w < 50 && running(); ++w) std::this_thread::sleep_for(std::chrono::milliseconds(100));  // 5 s
            }
            ++held_to_end;
        });
    phone_thread.join();
    for (auto& t : hostile) t.join();
    setup.del("/v1/maps/" + std::to_string(big.id));
    report({{"scenario", a.scenario},
            {"seconds", std::chrono::duration<double>(Clock::now() - t0).count()},
            {"connections", a.body_connections},
            {"cut", cut.load()},
            {"held_to_end", held_to_end.load()}},
           phones, answers, a, idle_rss_kb);
}

// `--scenario steps-scans`: see the file's comment. Each batch's scans are 0.1 s apart,
// batch after batch 100 s apart, starting an hour ago: all new, all within the retention.
void run_steps_scans(const Args& a) {
    if (a.radiomap <= 0) throw CommandError("--radiomap is required with --scenario steps-scans: its RPs are the scans, and the phones localize against it");
    const Target target = loopback_target(a.server.client_options().base_url, "bench abuse");
    api::Client setup(a.server.client_options());
    const std::int64_t floor_id = setup.radiomap(a.radiomap).floor_id;
    // The phones' bodies, read before the clock starts, are the flood's scans too.
    LocalizingPhones phones(a, target, floor_id);
    std::vector<json> readings;  // one scan's readings per localize body
    for (const auto& b : phones.bodies()) readings.push_back(json::parse(b).at("scans").at(0));
    if (readings.empty()) throw CommandError("radio map " + std::to_string(a.radiomap) + " has no RP to make scans of");
    const std::vector<OpenedTrack> tracks = hostile_tracks(a, target, a.scan_tracks);
    const long long idle_rss_kb = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;
    const double cpu_before = a.server_pid ? proc_cpu_seconds(a.server_pid) : -1.0;
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
    auto running = [&] { return Clock::now() < deadline; };
    const double start = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count() - 3600;
    StatusCounts posts;
    std::atomic<long long> localized{0};
    std::deque<std::thread> hostile;
    for (std::size_t k = 0; k < tracks.size(); ++k)
        hostile.emplace_back([&, k] {
            const OpenedTrack& t = tracks[k];
            BenchConnection c(target.host, target.port, a.hostile_address);
            // A batch is made again only once one was taken (a refused one stored nothing), so
            // the client's own CPU goes to sending; a refusal's Retry-After is not waited for.
            std::string request;
            for (int batch = 0; running();) {
                if (request.empty()) {
                    json scans = json::array();
                    for (int i = 0; i < 1000; ++i)
                        scans.push_back({{"t", start + 100.0 * batch + 0.1 * i}, {"readings", readings[(k * 1000 + static_cast<std::size_t>(i)) % readings.size()]}});
                    request = http_request("POST", "/v1/tracks/" + t.id + "/steps", target.host_port, json{{"scans", scans}}.dump(),
                                           "X-Track-Token: " + t.token + "\r\n");
                }
                std::string body;
                const auto status = c.round_trip(request, &body);
                posts.add(status);
                if (status != 200) continue;
                localized += static_cast<long long>(json::parse(body, nullptr, false).value("scan_fixes", json::array()).size());
                ++batch;
                request.clear();
            }
        });
    phones.run(running);
    for (auto& t : hostile) t.join();
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    json out = {{"scenario", "steps-scans"},
                {"seconds", elapsed},
                {"rps", readings.size()},
                {"tracks", tracks.size()},
                {"scans_localized", localized.load()},
                {"scans_localized_per_s", static_cast<double>(localized.load()) / elapsed}};
    if (a.server_pid) out["server_cpu_s_per_s"] = (proc_cpu_seconds(a.server_pid) - cpu_before) / elapsed;
    report(out, phones, posts, a, idle_rss_kb);
}

void run(const Args& a) {
    if (!a.hostile_address.starts_with("127.") || a.hostile_address == "127.0.0.1")
        throw CommandError("--hostile-address must be a loopback address other than 127.0.0.1 (e.g. 127.0.0.2)");
    if (a.scenario == "route-build") return run_route_build(a);
    if (a.scenario == "streams") return run_streams(a);
    if (a.scenario == "fixes") return run_fixes(a);
    if (a.scenario == "bodies" || a.scenario == "slow-bodies") return run_bodies(a, a.scenario == "slow-bodies");
    if (a.scenario == "slow-readers") return run_slow_readers(a);
    if (a.scenario == "steps-scans") return run_steps_scans(a);
    if (a.radiomap <= 0) throw CommandError("--radiomap is required with --scenario all: the phones localize against it");
    const Target target = loopback_target(a.server.client_options().base_url, "bench abuse");
    api::Client setup(a.server.client_options());
    const std::int64_t floor_id = setup.radiomap(a.radiomap).floor_id;
    const auto bodies = localize_bodies(a.server, a.radiomap, "", "wknn");
    const std::string hp = target.host_port;
    const std::string localize_path = "/v1/radiomaps/" + std::to_string(a.radiomap) + "/localize";
    const std::string map_path = "/v1/maps/" + std::to_string(a.map);
    const std::string open_request = http_request("POST", "/v1/tracks", hp, json{{"map_id", a.map}}.dump());

    // The bombs are made before the clock starts (compressing 512 MiB takes a second or two).
    const std::string prefix = R"({"algorithm":"wknn","scans":[[{"bssid":"00:00:00:00:00:01","rss":-50}]],"pad":")";
    const std::string localize_bomb =
        http_request("POST", localize_path, hp, compress_stream(prefix, ' ', 512u << 20, "\"}"), "Content-Encoding: gzip\r\n");
    const std::string brotli = http_request("POST", localize_path, hp, bodies.front(), "Content-Encoding: br\r\n");

    const long long idle_rss_kb = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
    auto running = [&] { return Clock::now() < deadline; };

    // The hostile client.
    StatusCounts bombs, tracks, streams, expensive;
    // A deque: its threads never move (a vector's reallocation draws a false -Warray-bounds from
    // gcc 12 at -O3).
    std::deque<std::thread> hostile;
    hostile.emplace_back([&] {
        BenchConnection c(target.host, target.port, a.hostile_address);
        for (std::size_t i = 0; running(); ++i) bombs.add(c.round_trip(i % 2 ? brotli : localize_bomb));
    });
    std::mutex held_mu;
    std::vector<OpenedTrack> held;
    hostile.emplace_back([&] {
        BenchConnection c(target.host, target.port, a.hostile_address);
        auto last_refresh = Clock::now();
        while (running()) {
            std::string body;
            const auto status = c.round_trip(open_request, &body);
            tracks.add(status);
            if (status == 201) {
                const json j = json::parse(body, nullptr, false);
                std::lock_guard lock(held_mu);
                held.push_back({std::to_string(j["id"].get<long long>()), j["token"].get<std::string>()});
            }
            if (Clock::now() - last_refresh > std::chrono::seconds(5)) {  // one fix each keeps them alive
                last_refresh = Clock::now();
                std::vector<OpenedTrack> copy;
                {
                    std::lock_guard lock(held_mu);
                    copy = held;
                }
                for (const auto& t : copy)
                    if (running()) tracks.add(c.round_trip(fix_request(t, floor_id, 1.0, 1.0, hp)));
            }
        }
    });
    hostile.emplace_back([&] {
        std::vector<std::unique_ptr<HeldStream>> open;
        for (std::size_t i = 0; running(); ++i) {
            OpenedTrack t;
            {
                std::lock_guard lock(held_mu);
                if (!held.empty()) t = held[i % held.size()];
            }
            if (t.id.empty() || open.size() >= static_cast<std::size_t>(a.max_streams)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
                continue;
            }
            auto s = std::make_unique<HeldStream>();
            const auto status = open_stream(target, a.hostile_address, "/v1/tracks/" + t.id + "/events?token=" + t.token, *s);
            streams.add(status);
            if (status == 200) open.push_back(std::move(s));
        }
    });
    for (int k = 0; k < 2; ++k)
        hostile.emplace_back([&, k] {
            const std::string route = http_request(
                "POST", map_path + "/route", hp,
                json{{"from", {{"floor_id", floor_id}, {"x", 1.0}, {"y", 1.0}}}, {"to", {{"floor_id", floor_id}, {"x", 20.0}, {"y", 10.0}}}}.dump());
            const std::string search = http_request("GET", map_path + "/search?q=room&limit=50", hp);
            const std::string map_localize = http_request("POST", map_path + "/localize", hp, bodies.front());
            BenchConnection c(target.host, target.port, a.hostile_address);
            for (std::size_t i = static_cast<std::size_t>(k); running(); ++i)
                expensive.add(c.round_trip(i % 3 == 0 ? route : i % 3 == 1 ? search : map_localize));
        });

    // The phones.
    LocalizingPhones phones(a, target, floor_id);
    phones.run(running);
    for (auto& t : hostile) t.join();
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();

    json out = {{"seconds", elapsed},
                {"phones", phones.to_json()},
                {"hostile",
                 {{"address", a.hostile_address},
                  {"bombs", bombs.to_json()},
                  {"tracks", tracks.to_json()},
                  {"streams", streams.to_json()},
                  {"expensive", expensive.to_json()}}}};
    if (a.server_pid) {
        const long long peak = proc_status_kb(a.server_pid, "VmHWM:");
        out["server"] = {{"rss_idle_mb", idle_rss_kb / 1024.0}, {"peak_mb", peak / 1024.0}, {"peak_above_idle_mb", (peak - idle_rss_kb) / 1024.0}};
    }
    std::cout << out.dump() << "\n";
    const bool hostile_5xx = bombs.any_server_error() || tracks.any_server_error() || streams.any_server_error() ||
                             expensive.any_server_error();
    const int refused = phones.refused();
    if (refused > 0 || hostile_5xx)
        throw CommandError(std::to_string(refused) + " phone requests refused" +
                           (hostile_5xx ? "; the hostile client got a 5xx" : ""));
}

}  // namespace

LOCUS_COMMAND("bench-abuse", [](CLI::App& app) {
    auto& bench = locus::tools::group(app, "bench", "Measure a running server");
    auto* cmd = bench.add_subcommand("abuse", "One hostile client without the API key against well-behaved phones, on loopback");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--map", args->map, "the map the phones open tracks on")->required();
    cmd->add_option("--radiomap", args->radiomap, "a radio map of that map, which the phones localize against (scenario all)");
    cmd->add_option("--phones", args->phones, "well-behaved phones, each from its own loopback address")->capture_default_str()->check(CLI::Range(1, 1000));
    cmd->add_option("--seconds", args->seconds, "how long the run lasts")->capture_default_str()->check(CLI::Range(1.0, 120.0));
    cmd->add_option("--phone-interval", args->phone_interval, "seconds between a phone's localize + fix")->capture_default_str()->check(CLI::Range(0.05, 60.0));
    cmd->add_option("--hostile-address", args->hostile_address, "the hostile client's loopback source address")->capture_default_str();
    cmd->add_option("--hostile-streams", args->max_streams, "event streams the hostile client tries to hold")->capture_default_str()->check(CLI::Range(1, 2000));
    cmd->add_option("--scenario", args->scenario,
                    "all: bombs, track, stream and route floods at once; route-build: routes on a large map's graph; streams: "
                    "clients holding every stream they may, then a phone's own; fixes: two tracks posting 1,000-fix batches; "
                    "bodies: 8 MiB localize bodies on many connections; slow-bodies: 8 MiB bodies sent all but their last bytes; "
                    "slow-readers: a 5.6 MB plan read 1 KB every 5 s on many connections; steps-scans: tracks posting /steps "
                    "batches of 1,000 scans to localize")
        ->capture_default_str()
        ->check(CLI::IsMember({"all", "route-build", "streams", "fixes", "bodies", "slow-bodies", "slow-readers", "steps-scans"}));
    cmd->add_option("--scan-tracks", args->scan_tracks, "steps-scans: the hostile client's tracks")->capture_default_str()->check(CLI::Range(1, 16));
    cmd->add_option("--body-connections", args->body_connections, "bodies, slow-bodies, slow-readers: the hostile client's connections")
        ->capture_default_str()->check(CLI::Range(1, 500));
    cmd->add_option("--db", args->db, "fixes: the server's SQLite database file, to report how much it (and its WAL) grew");
    cmd->add_option("--stream-holders", args->stream_holders, "streams: clients holding streams before the phone opens its own")
        ->capture_default_str()->check(CLI::Range(1, 1000));
    cmd->add_option("--big-floor-m", args->big_floor_m, "route-build: the side of the big map's two square floors, metres")
        ->capture_default_str()->check(CLI::Range(10.0, 500.0));
    cmd->add_option("--server-pid", args->server_pid, "the server's process id, to report its peak resident memory (/proc)")->check(CLI::PositiveNumber);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_bench_abuse
