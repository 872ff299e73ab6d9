#pragma once
// A Locus server in the benchmark's own process on 127.0.0.1 (an ephemeral port): the store,
// every service and the HTTP front on one database, served on a thread of its own, so a
// benchmark measures requests over loopback without a child process. Stopped (tracks first,
// then the listener) and torn down in the reverse order of building.
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "directory/service.hpp"
#include "http/app.hpp"
#include "http/localize/localize_answer.hpp"
#include "localize/service.hpp"
#include "routing/service.hpp"
#include "store/sql_store.hpp"
#include "tracks/service.hpp"

namespace locus::bench {

struct InProcessServer {
    std::unique_ptr<store::SqlStore> store;
    std::unique_ptr<localize::Service> localizer;
    std::unique_ptr<routing::Service> router;
    std::unique_ptr<directory::Service> directory;
    std::unique_ptr<tracks::Service> tracks;
    std::unique_ptr<http::App> app;
    std::thread thread;
    int port = 0;

    // `db`: a SQLite file or a PostgreSQL URL. `api_key`: as --api-key (a benchmark sending it
    // is exempt from the per-client limits, http/front/fair_share.hpp).
    explicit InProcessServer(const std::string& db, const tracks::Options& track_options = {}, const std::string& api_key = "") {
        store = std::make_unique<store::SqlStore>(db);
        localizer = std::make_unique<localize::Service>(*store, http::prepare_answers);
        router = std::make_unique<routing::Service>(*store);
        directory = std::make_unique<directory::Service>(*store);
        tracks = std::make_unique<tracks::Service>(*store, track_options);
        app = std::make_unique<http::App>(*store, *localizer, *router, *directory, http::AppOptions{api_key, false, http::FrontOptions{}, {}, tracks.get()});
        std::string error;
        port = app->server().bind("127.0.0.1", 0, error);
        if (port < 0) throw std::runtime_error(error);
        thread = std::thread([this] { app->server().serve(); });
    }
    ~InProcessServer() {
        tracks->stop();
        app->server().shut_down();
        thread.join();
        app.reset();
        tracks.reset();
        directory.reset();
        router.reset();
        localizer.reset();
        store.reset();
    }
    InProcessServer(const InProcessServer&) = delete;
    InProcessServer& operator=(const InProcessServer&) = delete;
};

}  // namespace locus::bench
