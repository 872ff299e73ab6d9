// locus-server: flags, wiring and signals. Everything else lives in store/, localize/ and http/.
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
}  // namespace

int main(int argc, char** argv) {
    CLI::App cli{"locus-server: the Locus radio-map and localization service"};
    std::string db_path = "locus.db", host = "127.0.0.1", api_key;
    int port = 8080;
    bool demo = false, quiet = false, allow_open_writes = false;
    locus::http::FrontOptions front;
    int threads = static_cast<int>(front.min_threads);
    double keep_alive_s = 10, header_s = 10, read_s = 10;
    cli.add_option("--db", db_path,
                   "the database: an SQLite file (a path or sqlite:PATH, created if missing) or a PostgreSQL URL "
                   "(postgresql://user@host/db; servers sharing one see each other's writes)")
        ->capture_default_str();
    cli.add_option("--host", host, "address to listen on")->capture_default_str();
    cli.add_option("--port", port, "port to listen on (0: any free port)")->capture_default_str()->check(CLI::Range(0, 65535));
    cli.add_option("--api-key", api_key, "require 'Authorization: Bearer KEY' for writes")->envname("LOCUS_API_KEY");
    cli.add_flag("--allow-open-writes", allow_open_writes,
                 "listen beyond loopback without --api-key (writes then open to the network)");
    cli.add_flag("--demo", demo, "create the demo map when the database holds no map");
    cli.add_option("--max-body-bytes", front.max_body_bytes, "largest request body accepted (a chunked body: on the wire)")
        ->capture_default_str()->check(CLI::PositiveNumber);
    cli.add_option("--threads", threads, "HTTP workers kept when idle; one more starts per open connection")
        ->capture_default_str()->check(CLI::Range(1, 256));
    cli.add_option("--max-connections", front.max_connections, "open connections served at once; past it, 503 server_busy")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    cli.add_option("--keep-alive-timeout", keep_alive_s, "seconds an idle kept-alive connection stays open")
        ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
    cli.add_option("--keep-alive-requests", front.keep_alive_max_requests, "requests served on one connection before it closes")
        ->capture_default_str()->check(CLI::Range(1, 1000000));
    cli.add_option("--header-timeout", header_s, "seconds a request head may take to arrive (slow clients are cut off)")
        ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
    cli.add_option("--read-timeout", read_s, "seconds to wait for the next bytes of a request body")
        ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
    cli.add_flag("--quiet", quiet, "no access log");
    std::size_t max_exports = 2;
    double export_timeout_s = 600;
    cli.add_option("--max-exports", max_exports,
                   "radio map exports written at once (each holds a database connection and read snapshot); past it, "
                   "503 server_busy")
        ->capture_default_str()->check(CLI::Range(1, 1000));
    cli.add_option("--export-timeout", export_timeout_s,
                   "seconds an export may take; past it the answer is cut (no last chunk) and its snapshot let go")
        ->capture_default_str()->check(CLI::Range(0.1, 604800.0));
    locus::tracks::Options tracks_options;
    cli.add_option("--track-ttl", tracks_options.ttl_s, "seconds without a fix after which a live track closes")
        ->capture_default_str()->check(CLI::Range(0.01, 1e7));
    cli.add_option("--track-retention", tracks_options.retention_s,
                   "seconds after a track closes (or its fixes were taken) that they are deleted")
        ->capture_default_str()->check(CLI::Range(0.01, 1e8));
    cli.add_option("--track-heartbeat", tracks_options.heartbeat_s, "seconds between heartbeat comments on an idle event stream")
        ->capture_default_str()->check(CLI::Range(0.01, 3600.0));
    cli.add_option("--max-track-streams", tracks_options.max_streams, "open track event streams; past it, 503 server_busy")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    cli.add_option("--max-live-tracks", tracks_options.max_live_tracks, "live tracks at once; past it, opening one answers 503")
        ->capture_default_str()->check(CLI::Range(1, 10000000));
    cli.add_option("--max-tracks", tracks_options.max_tracks,
                   "tracks held at all (live, closed within the retention period, deleted ones' tombstones); at it, "
                   "opening one evicts the oldest tombstone, else closed track, and answers 503 too_many_tracks only when "
                   "live tracks fill it")
        ->capture_default_str()->check(CLI::Range(1, 100000000));
    cli.add_option("--max-streams-per-track", tracks_options.max_streams_per_track,
                   "open event streams on one track; past it, 429 too_many_streams")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    // Per-client shares of the limits above (docs/deploy.md "Per-client limits"); a request with
    // the API key is exempt. Where a per-client cap is above its server-wide one, the
    // server-wide cap is met first.
    locus::http::FairShareOptions fair;
    std::vector<std::string> trusted_proxies;
    cli.add_option("--client-live-tracks", tracks_options.max_live_tracks_per_client,
                   "live tracks one client (address) holds at once; past it, opening one answers 429 too_many_live_tracks")
        ->capture_default_str()->check(CLI::Range(1, 10000000));
    cli.add_option("--client-streams", tracks_options.max_streams_per_client,
                   "event streams (track and positions) one client holds open; past it, 429 too_many_client_streams")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    cli.add_option("--client-track-opens", fair.track_open_rate,
                   "tracks one client may open a second, on average (POST /v1/tracks); past it, 429 rate_limited")
        ->capture_default_str()->check(CLI::Range(0.0001, 1e6));
    cli.add_option("--client-track-open-burst", fair.track_open_burst, "tracks one client may open at once before --client-track-opens applies")
        ->capture_default_str()->check(CLI::Range(1.0, 1e6));
    cli.add_option("--client-rate", fair.route_rate,
                   "route, search, map localize and radio map quality requests one client may send a second, on average; past it, "
                   "429 rate_limited")
        ->capture_default_str()->check(CLI::Range(0.0001, 1e6));
    cli.add_option("--client-burst", fair.route_burst, "such requests one client may send at once before --client-rate applies")
        ->capture_default_str()->check(CLI::Range(1.0, 1e6));
    cli.add_option("--trusted-proxy", trusted_proxies,
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
    std::string web_root = locus::http::default_web_root(), leaflet_root = locus::http::default_leaflet_root;
    cli.add_option("--web-root", web_root, "the web viewer's files, served at / (empty: no viewer)")->capture_default_str();
    cli.add_option("--leaflet-root", leaflet_root, "Leaflet's files (Debian's libjs-leaflet), served at /vendor/leaflet/")
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

    auto ms = [](double seconds) { return std::chrono::milliseconds(static_cast<long long>(seconds * 1000.0)); };
    front.min_threads = static_cast<std::size_t>(threads);
    front.keep_alive_timeout = ms(keep_alive_s);
    front.header_timeout = ms(header_s);
    front.read_timeout = ms(read_s);
    fair.trusted_proxies = locus::http::parse_trusted_proxies(trusted_proxies);
    // Replicas with one API key hash a client's address alike, so they count its live tracks
    // together in the database; the key itself is not in it (schema/015_track_client.sql).
    if (!api_key.empty()) tracks_options.client_key = locus::tracks::token_hash("locus client hash\n" + api_key);

    for (const auto& problem : {locus::startup::open_writes_problem(host, !api_key.empty(), allow_open_writes),
                                locus::startup::database_path_problem(db_path)})
        if (problem) {
            log_event({{"event", "error"}, {"message", *problem}});
            return 2;
        }
    try {
        const auto opened = locus::store::open(db_path);
        auto& store = *opened;
        if (demo && !store.has_maps()) {
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
        locus::localize::Service localizer(store, locus::http::prepare_answers);
        locus::routing::Service router(store);
        locus::directory::Service directory(store);
        locus::tracks::Service tracks(store, tracks_options);
        locus::http::App app(store, localizer, router, directory,
                             {api_key, !quiet, front, {web_root, leaflet_root}, &tracks, max_exports, ms(export_timeout_s), fair});
        auto& server = app.server();
        std::string listen_error;
        const int bound = server.bind(host, port, listen_error);
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
        log_event({{"event", "listening"}, {"host", host}, {"port", bound}, {"db", store.location()}, {"auth", !api_key.empty()},
                   {"max_connections", server.options().max_connections}, {"trusted_proxies", fair.trusted_proxies.size()}});
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
