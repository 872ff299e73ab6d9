// locus-server: flags, wiring and signals. Everything else lives in the folders beside it (docs/ARCHITECTURE.md).
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <pthread.h>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "directory/service.hpp"
#include "http/app.hpp"
#include "http/json_text.hpp"
#include "http/localize/localize_answer.hpp"
#include "http/plans/bundle_plans.hpp"
#include "http/front/client_address.hpp"
#include "http/front/static_files.hpp"
#include "http/crud/store_json.hpp"
#include "localize/service.hpp"
#include "routing/service.hpp"
#include "startup/checks.hpp"
#include "store/migrations.hpp"
#include "tracks/service.hpp"
#include "tracks/token.hpp"

namespace {

void log_event(const nlohmann::json& event) {
    const std::string line = locus::http::json_text(event) + "\n";
    std::fwrite(line.data(), 1, line.size(), stderr);
    std::fflush(stderr);
}

std::chrono::milliseconds ms(double seconds) { return std::chrono::milliseconds(static_cast<long long>(seconds * 1000.0)); }

// Every flag's value, as parsed; the services' options are filled in by finish_flags.
struct Flags {
    std::string db_path = "locus.db", host = "127.0.0.1", api_key;
    int port = 8080;
    bool demo = false, quiet = false, allow_open_writes = false, public_positions = false;
    locus::http::FrontOptions front;
    int threads = static_cast<int>(front.min_threads);
    double keep_alive_s = 10, header_s = 10, read_s = 10;
    std::size_t max_exports = 2;
    double export_timeout_s = 600;
    double max_route_graph_mb = 192;
    locus::tracks::Options tracks;
    locus::http::FairShareOptions fair;
    locus::http::BodyBudgetOptions bodies;
    locus::http::BodyBudgetOptions answers = locus::http::AppOptions{}.answers;
    std::uint64_t client_requests = locus::http::AppOptions{}.client_requests;
    std::vector<std::string> trusted_proxies;
    std::string web_root = locus::http::default_web_root(), leaflet_root = locus::http::default_leaflet_root;
};

// The database, the listening socket, the connection limits and the exports.
void add_server_flags(CLI::App& cli, Flags& f) {
    cli.add_option("--db", f.db_path,
                   "the database: an SQLite file (a path or sqlite:PATH, created if missing) or a PostgreSQL URL "
                   "(postgresql://user@host/db; servers sharing one see each other's writes)")
        ->capture_default_str();
    cli.add_option("--host", f.host, "address to listen on")->capture_default_str();
    cli.add_option("--port", f.port, "port to listen on (0: any free port)")->capture_default_str()->check(CLI::Range(0, 65535));
    cli.add_option("--api-key", f.api_key, "require 'Authorization: Bearer KEY' for writes")->envname("LOCUS_API_KEY");
    cli.add_flag("--allow-open-writes", f.allow_open_writes,
                 "listen beyond loopback without --api-key (writes then open to the network)");
    cli.add_flag("--demo", f.demo, "create the demo map when the database holds no map");
    cli.add_flag("--public-positions", f.public_positions,
                 "answer every live track's position (GET /v1/maps/{id}/positions and its stream) to anyone; without it "
                 "they need --api-key's key, or with no key a client on this machine");
    cli.add_option("--max-body-bytes", f.front.max_body_bytes, "largest request body accepted (a chunked body: on the wire)")
        ->capture_default_str()->check(CLI::PositiveNumber);
    cli.add_option("--threads", f.threads, "HTTP workers kept when idle; one more starts per open connection")
        ->capture_default_str()->check(CLI::Range(1, 256));
    cli.add_option("--max-connections", f.front.max_connections, "open connections served at once; past it, 503 server_busy")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    cli.add_option("--keep-alive-timeout", f.keep_alive_s, "seconds an idle kept-alive connection stays open")
        ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
    cli.add_option("--keep-alive-requests", f.front.keep_alive_max_requests, "requests served on one connection before it closes")
        ->capture_default_str()->check(CLI::Range(1, 1000000));
    cli.add_option("--header-timeout", f.header_s, "seconds a request head may take to arrive (slow clients are cut off)")
        ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
    cli.add_option("--read-timeout", f.read_s, "seconds to wait for the next bytes of a request body")
        ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
    cli.add_option("--min-body-rate", f.front.min_body_rate,
                   "bytes a second a request body, or a JSON answer, must average: a body must be read within --read-timeout "
                   "plus its length at this rate, else it is dropped (408); an answer written within the write timeout plus "
                   "its length at this rate, else the connection is cut")
        ->capture_default_str()->check(CLI::Range(1.0, 1e12));
    // Request bodies being received and parsed at once (http/front/body_budget.hpp).
    cli.add_option("--max-body-bytes-in-flight", f.bodies.total_bytes,
                   "bytes of request bodies received and parsed at once, every client together (a chunked or encoded body "
                   "counts as its route's limit); past it, 503 server_busy")
        ->capture_default_str()->check(CLI::Range(1.0, 1e15));
    cli.add_option("--client-body-bytes-in-flight", f.bodies.client_bytes,
                   "bytes of request bodies one client (address) has received and parsed at once; past it, 429 "
                   "too_many_bodies (the API key: exempt)")
        ->capture_default_str()->check(CLI::Range(1.0, 1e15));
    cli.add_option("--client-requests-in-flight", f.client_requests,
                   "requests one client (address) has being handled at once (an event stream once it has begun: none); past "
                   "it, 429 too_many_requests (the API key: exempt)")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    // Answers being written at once (the same accounting, app.hpp's AppOptions::answers).
    cli.add_option("--max-answer-bytes-in-flight", f.answers.total_bytes,
                   "bytes of JSON answers being written at once, every client together; past it, 503 server_busy")
        ->capture_default_str()->check(CLI::Range(1.0, 1e15));
    cli.add_option("--client-answer-bytes-in-flight", f.answers.client_bytes,
                   "bytes of JSON answers one client (address) has not yet read; past it, 429 too_many_answers (the API key: "
                   "exempt)")
        ->capture_default_str()->check(CLI::Range(1.0, 1e15));
    cli.add_flag("--quiet", f.quiet, "no access log");
    cli.add_option("--max-exports", f.max_exports,
                   "radio map exports written at once (each holds a database connection and read snapshot); past it, "
                   "503 server_busy")
        ->capture_default_str()->check(CLI::Range(1, 1000));
    cli.add_option("--export-timeout", f.export_timeout_s,
                   "seconds an export may take; past it the answer is cut (no last chunk) and its snapshot let go")
        ->capture_default_str()->check(CLI::Range(0.1, 604800.0));
    cli.add_option("--max-route-graph-mb", f.max_route_graph_mb,
                   "largest route graph a map may have, estimated from its plans before it is built (a map past it: "
                   "routes answer 422 route_graph_too_large)")
        ->capture_default_str()->check(CLI::Range(1.0, 1e6));
}

// Live tracks, per-client shares and the proxies trusted to name the client.
void add_client_flags(CLI::App& cli, Flags& f) {
    cli.add_option("--track-ttl", f.tracks.ttl_s, "seconds without a fix after which a live track closes")
        ->capture_default_str()->check(CLI::Range(0.01, 1e7));
    cli.add_option("--track-retention", f.tracks.retention_s,
                   "seconds after a track closes (or its fixes were taken) that they are deleted")
        ->capture_default_str()->check(CLI::Range(0.01, 1e8));
    cli.add_option("--track-heartbeat", f.tracks.heartbeat_s, "seconds between heartbeat comments on an idle event stream")
        ->capture_default_str()->check(CLI::Range(0.01, 3600.0));
    cli.add_option("--max-track-streams", f.tracks.max_streams, "open track event streams; past it, 503 server_busy")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    cli.add_option("--max-live-tracks", f.tracks.max_live_tracks, "live tracks at once; past it, opening one answers 503")
        ->capture_default_str()->check(CLI::Range(1, 10000000));
    cli.add_option("--max-tracks", f.tracks.max_tracks,
                   "tracks held at all (live, closed within the retention period, deleted ones' tombstones); at it, "
                   "opening one evicts the oldest tombstone, else closed track, and answers 503 too_many_tracks only when "
                   "live tracks fill it")
        ->capture_default_str()->check(CLI::Range(1, 100000000));
    cli.add_option("--max-streams-per-track", f.tracks.max_streams_per_track,
                   "open event streams on one track; past it, 429 too_many_streams")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    // Per-client shares of the limits above (docs/deploy.md "Per-client limits"); a request with
    // the API key is exempt. Where a per-client cap is above its server-wide one, the
    // server-wide cap is met first.
    cli.add_option("--client-live-tracks", f.tracks.max_live_tracks_per_client,
                   "live tracks one client (address) holds at once; past it, opening one answers 429 too_many_live_tracks")
        ->capture_default_str()->check(CLI::Range(1, 10000000));
    cli.add_option("--client-streams", f.tracks.max_streams_per_client,
                   "event streams (track and positions) one client holds open; past it, 429 too_many_client_streams")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    cli.add_option("--client-track-opens", f.fair.track_open_rate,
                   "tracks one client may open a second, on average (POST /v1/tracks); past it, 429 rate_limited")
        ->capture_default_str()->check(CLI::Range(0.0001, 1e6));
    cli.add_option("--client-track-open-burst", f.fair.track_open_burst, "tracks one client may open at once before --client-track-opens applies")
        ->capture_default_str()->check(CLI::Range(1.0, 1e6));
    cli.add_option("--client-rate", f.fair.route_rate,
                   "route, search, map localize and radio map quality requests (and scans a track's /steps has localized) one "
                   "client may send a second, on average; past it, 429 rate_limited")
        ->capture_default_str()->check(CLI::Range(0.0001, 1e6));
    cli.add_option("--client-burst", f.fair.route_burst, "such requests one client may send at once before --client-rate applies")
        ->capture_default_str()->check(CLI::Range(1.0, 1e6));
    cli.add_option("--client-track-bytes", f.fair.track_write_rate,
                   "bytes of track fixes and steps (POST /v1/tracks/{id}/fixes, /steps) one client may post a second, on average; "
                   "past it, 429 rate_limited")
        ->capture_default_str()->check(CLI::Range(1.0, 1e12));
    cli.add_option("--client-track-bytes-burst", f.fair.track_write_burst,
                   "bytes of track fixes and steps one client may post at once before --client-track-bytes applies")
        ->capture_default_str()->check(CLI::Range(1.0, 1e12));
    cli.add_option("--trusted-proxy", f.trusted_proxies,
                   "a reverse proxy's address or CIDR range (repeatable, or comma-separated): from it, the client is the "
                   "right-most X-Forwarded-For entry that is not a trusted proxy; without one, X-Forwarded-For is ignored")
        ->check([](const std::string& value) {
            try {
                (void)locus::http::parse_trusted_proxies({value});
                return std::string();
            } catch (const std::invalid_argument& e) {
                return std::string(e.what());
            }
        });
}

// What the flags say in the units and forms the services take.
void finish_flags(Flags& f) {
    f.front.min_threads = static_cast<std::size_t>(f.threads);
    f.front.keep_alive_timeout = ms(f.keep_alive_s);
    f.front.header_timeout = ms(f.header_s);
    f.front.read_timeout = ms(f.read_s);
    f.fair.trusted_proxies = locus::http::parse_trusted_proxies(f.trusted_proxies);
    // Replicas with one API key hash a client's address alike, so they count its live tracks
    // together in the database; the key itself is not in it (schema/015_track_client.sql).
    if (!f.api_key.empty()) f.tracks.client_key = locus::tracks::token_hash("locus client hash\n" + f.api_key);
}

// Creates the demo map when asked and the database holds no map.
void create_demo_map(locus::store::Store& store) {
    const auto doc = nlohmann::json::parse(locus::server::demo_map_json());
    const auto plans = locus::http::parse_bundle_plans(doc);  // read all before writing any
    const auto map_id = store.import_map_bundle(locus::http::parse_map_bundle(doc)).id;
    // The plans need the floor ids the import made; a refused one (a bad demo file) takes
    // the map back out, so the next start tries again, and stops the server with its
    // message, as a bad bundle does.
    try {
        locus::http::put_bundle_plans(store, map_id, plans);
    } catch (...) {
        store.remove(locus::store::kind("maps"), map_id);
        throw;
    }
    log_event({{"event", "demo_map_created"}, {"map_id", map_id}, {"plans", plans.size()}});
}

// Opens the store, makes the services and the App on it, and serves until a signal of
// `signals` (blocked in every thread) arrives. The process's exit status.
int serve(const Flags& f, const sigset_t& signals) {
    try {
        const auto opened = locus::store::open(f.db_path);
        auto& store = *opened;
        if (f.demo && !store.has_maps()) create_demo_map(store);
        locus::localize::Service localizer(store, locus::http::prepare_answers);
        locus::routing::Service router(store, {f.max_route_graph_mb * 1024 * 1024, {}});
        locus::directory::Service directory(store);
        locus::tracks::Service tracks(store, f.tracks);
        locus::http::App app(store, localizer, router, directory,
                             {f.api_key, !f.quiet, f.front, {f.web_root, f.leaflet_root}, &tracks, f.max_exports,
                              ms(f.export_timeout_s), f.fair, f.bodies, f.answers, f.client_requests, f.public_positions});
        auto& server = app.server();
        std::string listen_error;
        const int bound = server.bind(f.host, f.port, listen_error);
        if (bound < 0) {
            log_event({{"event", "error"}, {"message", locus::startup::listen_problem(listen_error)}});
            return 1;
        }
        std::thread signal_waiter([&server, &tracks, signals] {
            int sig = 0;
            sigwait(&signals, &sig);
            log_event({{"event", "shutdown"}, {"signal", sig}});
            tracks.stop();  // ends the event streams, which would hold their connections open
            server.shut_down();
        });
        log_event({{"event", "listening"}, {"host", f.host}, {"port", bound}, {"db", store.location()}, {"auth", !f.api_key.empty()},
                   {"max_connections", server.options().max_connections}, {"trusted_proxies", f.fair.trusted_proxies.size()}});
        const bool ok = server.serve();
        if (!ok && server.is_running()) log_event({{"event", "error"}, {"message", "listen failed"}});
        // Wake the signal thread if listen ended for another reason.
        pthread_kill(signal_waiter.native_handle(), SIGTERM);
        signal_waiter.join();
        log_event({{"event", "stopped"}});
    } catch (const std::exception& e) {
        log_event({{"event", "error"}, {"message", e.what()}});
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App cli{"locus-server: the Locus radio-map and localization service"};
    cli.set_version_flag("--version", std::string("locus-server ") + LOCUS_VERSION);
    Flags flags;
    add_server_flags(cli, flags);
    add_client_flags(cli, flags);
    cli.add_option("--web-root", flags.web_root, "the web viewer's files, served at / (empty: no viewer)")->capture_default_str();
    cli.add_option("--leaflet-root", flags.leaflet_root, "Leaflet's files (Debian's libjs-leaflet), served at /vendor/leaflet/")
        ->capture_default_str();
    CLI11_PARSE(cli, argc, argv);

    // Signals are taken by one thread with sigwait, so shutdown runs as ordinary code.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::signal(SIGPIPE, SIG_IGN);
    // A file-size limit (RLIMIT_FSIZE) would kill the process; ignored, the write fails with
    // EFBIG like on a full disk and the request answers 503.
    std::signal(SIGXFSZ, SIG_IGN);

    finish_flags(flags);
    for (const auto& problem : {locus::startup::open_writes_problem(flags.host, !flags.api_key.empty(), flags.allow_open_writes),
                                locus::startup::database_path_problem(flags.db_path)})
        if (problem) {
            log_event({{"event", "error"}, {"message", *problem}});
            return 2;
        }
    return serve(flags, signals);
}
