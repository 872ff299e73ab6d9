#pragma once
// The HTTP layer: routes, authentication, request limits, error bodies and the access log.
// Handlers parse and validate, call the repository (or the localizer), and serialise.
#include <httplib.h>

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "http/front.hpp"
#include "store/kinds.hpp"
#include "store/repository.hpp"

namespace locus::http {

struct AppOptions {
    std::string api_key;  // empty: writes need no key
    bool access_log = true;
    FrontOptions front;   // connections, timeouts, body limit
};

// Told after every committed write, so in-memory indexes can follow (kind, the row as it was
// written or, for a delete, as it was before, and whether it was deleted).
using WriteListener = std::function<void(const store::Kind& kind, const nlohmann::json& row, bool deleted)>;

class App {
public:
    App(store::Repository& repo, AppOptions options);
    Front& server() { return server_; }
    // The CRUD, scan and radio-map routes. httplib tries a method's routes in the order they
    // were added, one regex match each, so routes added before these (localize, the request
    // a phone repeats) are found without failing a match per store route first.
    void install_store_routes();
    void on_write(WriteListener listener) { listener_ = std::move(listener); }

    // Runs a handler body, turning every failure into the JSON error shape (and a chunked body
    // found over the limit once read into 413).
    static void respond(const httplib::Request& req, httplib::Response& res,
                        const std::function<std::pair<int, nlohmann::json>()>& body);
    // The same guard for a handler that writes its own answer into `res`.
    static void guarded(const httplib::Request& req, httplib::Response& res, const std::function<void()>& body);

private:
    void install_middleware();
    // Answers a request that must be refused before its body is read; false if it may go on.
    bool refuse_before_body(const httplib::Request& req, httplib::Response& res) const;
    void install_crud();
    void install_radiomap_routes();
    void notify(const store::Kind& kind, const nlohmann::json& row, bool deleted);

    store::Repository& repo_;
    AppOptions options_;
    Front server_;
    WriteListener listener_;
};

void write_error(httplib::Response& res, int status, const std::string& code, const std::string& message);
// 503 storage_unavailable (with Retry-After) for a storage fault (SqliteError::is_storage_fault).
void write_storage_unavailable(httplib::Response& res, const store::SqliteError& e);

}  // namespace locus::http
