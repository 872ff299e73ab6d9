#include "http/app.hpp"

#include <chrono>
#include <optional>
#include <cstdio>
#include <ctime>

#include "http/api_error.hpp"
#include "http/json_text.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

bool is_read(const httplib::Request& req) {
    if (req.method == "GET" || req.method == "HEAD" || req.method == "OPTIONS") return true;
    // Localizing reads the radio map, routing the plans; phones ask without a key.
    if (req.method == "POST" && (req.path.ends_with("/localize") || req.path.ends_with("/route"))) return true;
    // A track is opened by a phone and then answers only to its own tokens (track_routes.cpp).
    return req.path == "/v1/tracks" || req.path.starts_with("/v1/tracks/");
}

bool same_secret(const std::string& a, const std::string& b) {
    unsigned char diff = a.size() == b.size() ? 0 : 1;
    for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i % (b.empty() ? 1 : b.size())]);
    return diff == 0;
}

std::string utc_now() {
    const auto now = std::chrono::system_clock::now();
    const std::time_t t = std::chrono::system_clock::to_time_t(now);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

const char* code_for_status(int status) {
    switch (status) {
        case 400: return "bad_request";
        case 401: return "unauthorized";
        case 404: return "not_found";
        case 405: return "method_not_allowed";
        case 408: return "request_timeout";
        case 411: return "length_required";
        case 413: return "payload_too_large";
        case 414: return "uri_too_long";
        case 415: return "unsupported_media_type";
        case 431: return "header_too_large";
        default: return status >= 500 ? "internal" : "error";
    }
}

}  // namespace

void write_error(httplib::Response& res, int status, const std::string& code, const std::string& message) {
    res.status = status;
    res.set_content(json_text(json{{"error", {{"code", code}, {"message", message}}}}), "application/json");
}

void write_storage_unavailable(httplib::Response& res, const store::DbError& e) {
    // The request was one transaction and it did not commit: nothing of it was written. The
    // file's path is for the log and /ready, not for every client.
    // PostgreSQL's message names its host and address: the client is told only which kind of
    // fault it is.
    res.set_header("Retry-After", "1");
    const std::string what = store::is_postgres_url(e.file) ? "the PostgreSQL database cannot be reached or refused the request" : e.what();
    write_error(res, 503, "storage_unavailable", "storage unavailable: " + what + "; the request changed nothing, retry later");
}

void App::respond(const httplib::Request& req, httplib::Response& res,
                  const std::function<std::pair<int, json>()>& body) {
    guarded(req, res, [&] {
        auto [status, out] = body();
        if (status == 204) {
            res.status = status;
            return;
        }
        std::string text = json_text(out);
        if (refuse_answer(res, text.size())) return;
        res.status = status;
        res.set_content(std::move(text), "application/json");
    });
}

void App::respond_text(const httplib::Request& req, httplib::Response& res,
                       const std::function<std::shared_ptr<const std::string>()>& body) {
    guarded(req, res, [&] {
        const auto text = body();
        if (refuse_answer(res, text->size())) return;  // before the copy
        res.status = 200;
        res.set_content(*text, "application/json");
    });
}

bool App::refuse_answer(httplib::Response& res, std::size_t bytes) {
    const auto refusal = Front::admit_answer(bytes);
    if (!refusal) return false;
    res.set_header("Retry-After", "1");
    write_error(res, refusal->status, refusal->code, refusal->message);
    return true;
}

void App::guarded(const httplib::Request& req, httplib::Response& res, const std::function<void()>& body) {
    if (auto refusal = Front::finish_body(req)) {
        write_error(res, refusal->status, refusal->code, refusal->message);
        return;
    }
    try {
        body();
    } catch (const ApiError& e) {
        if (e.retry_after_s > 0) res.set_header("Retry-After", std::to_string(retry_seconds(e.retry_after_s)));
        write_error(res, e.status, e.code, e.what());
    } catch (const store::NotFound& e) {
        write_error(res, 404, "not_found", e.what());
    } catch (const store::KeptByPlan& e) {
        write_error(res, 409, "kept_by_plan",
                    std::string(e.what()) + ": change the plan with PUT /v1/floors/" + std::to_string(e.floor_id) + "/plan");
    } catch (const store::PlanFeatureRefused& e) {
        // The plan routes name the feature as the client's document counts it; any other
        // writer of plans (a map bundle's) gets the store's own name for it.
        write_error(res, 422, "invalid_plan", e.feature + ": " + e.what());
    } catch (const store::Conflict& e) {
        write_error(res, 409, "conflict", e.what());
    } catch (const store::OutOfRange& e) {
        write_error(res, 422, "out_of_range", e.what());
    } catch (const routing::TooLarge& e) {
        write_error(res, 422, "route_graph_too_large", e.what());
    } catch (const store::DbError& e) {
        // Constraint failures that validation did not catch are still the client's input.
        if (e.is_constraint()) write_error(res, 409, "conflict", e.what());
        else if (e.is_storage_fault()) write_storage_unavailable(res, e);
        else write_error(res, 500, "internal", "storage error");
        if (e.is_storage_fault())
            std::fprintf(stderr, "{\"event\":\"storage_error\",\"db\":%s,\"message\":%s}\n", json_text(e.file).c_str(),
                         json_text(e.what()).c_str());
        else
            std::fprintf(stderr, "{\"event\":\"sqlite_error\",\"message\":%s}\n", json_text(e.what()).c_str());
    } catch (const std::exception& e) {
        // Input problems were refused above as ApiError; anything else (a JSON type error
        // included) is a server bug, and the client is told so rather than blamed.
        write_error(res, 500, "internal", "internal error");
        std::fprintf(stderr, "{\"event\":\"internal_error\",\"message\":%s}\n", json_text(e.what()).c_str());
    }
}

App::App(store::Store& store, localize::Service& localizer, routing::Service& router, directory::Service& directory,
         AppOptions options)
    : store_(store),
      localizer_(localizer),
      router_(router),
      directory_(directory),
      options_(std::move(options)),
      server_(options_.front) {
    install_middleware();
    install_health();
    install_localize();
    install_crud();
    install_geo_routes();
    install_radiomap_routes();
    install_plan_routes();
    install_route_routes();
    install_search_routes();
    install_image_routes();
    install_transmitter_routes();
    if (options_.tracks) install_track_routes();
    install_static_routes(server_, options_.web);
}

bool App::refuse_before_body(const httplib::Request& req, httplib::Response& res) const {
    if (auto refusal = server_.refusal(req)) {
        write_error(res, refusal->status, refusal->code, refusal->message);
        Front::close_after(res);  // what follows the head cannot be told apart from a next request
        return true;
    }
    if (const RequestFraming* f = Front::current(); f && f->close) Front::close_after(res);  // a chunked body
    if (options_.api_key.empty() || is_read(req)) return false;
    const std::string auth = req.get_header_value("Authorization");
    const std::string prefix = "Bearer ";
    if (!auth.starts_with(prefix) || !same_secret(auth.substr(prefix.size()), options_.api_key)) {
        res.set_header("WWW-Authenticate", "Bearer");
        write_error(res, 401, "unauthorized", "writes need 'Authorization: Bearer <api key>'");
        return true;
    }
    return false;
}

bool App::refuse_body(const httplib::Request& req, httplib::Response& res) {
    RequestFraming* f = Front::current();
    if (!f || f->body_admitted) return false;
    f->body_admitted = true;
    // A length known before reading is what is held; a chunked or encoded body may grow to the
    // route's limit (decoded) before that is known.
    std::uint64_t bytes = f->content_length.value_or(0);
    if (f->chunked || (!f->content_encoding.empty() && bytes > 0)) bytes = f->max_body_bytes;
    f->client = fair_share_.client(req);
    f->answers = &answer_budget_;
    // Each request being handled costs a worker's CPU and what its answer is built in: a client
    // has a few at once, as a browser does (six connections to a host).
    std::optional<Refusal> refusal;
    if (request_slots_.admit(f->client, 1, f->request_ticket) != BodyBudget::Verdict::admitted) {
        refusal = Refusal{429, "too_many_requests",
                          "this client has " + std::to_string(request_slots_.options().client_bytes) +
                              " requests being handled at once (--client-requests-in-flight); send the next once an answer has come"};
    } else if (const auto verdict = body_budget_.admit(f->client, bytes, f->body_ticket); verdict == BodyBudget::Verdict::server_full) {
        refusal = Refusal{503, "server_busy",
                          "the server is receiving and parsing as many request bodies as it holds at once (--max-body-bytes-in-flight " +
                              std::to_string(body_budget_.options().total_bytes) + " bytes); retry shortly"};
    } else if (verdict == BodyBudget::Verdict::client_full) {
        refusal = Refusal{429, "too_many_bodies",
                          "this client's request bodies being received and parsed reach its share (--client-body-bytes-in-flight " +
                              std::to_string(body_budget_.options().client_bytes) + " bytes); send the next once an answer has come"};
    }
    if (!refusal) return false;
    res.set_header("Retry-After", "1");
    write_error(res, refusal->status, refusal->code, refusal->message);
    Front::close_after(res);  // the body is not read
    return true;
}

void App::install_middleware() {
    // Before any body is read: bad framing, then the API key. Also asked for a request that
    // says `Expect: 100-continue`, so such a client is refused before it sends its body.
    // Then, once the request may go on, its client's share (fair_share.hpp).
    // The share is taken once per request: by the 100-continue handler when the client waits
    // for it (so a client over its rate is refused before it sends its body), else here.
    const auto refuse_share = [this](const httplib::Request& req, httplib::Response& res) {
        RequestFraming* f = Front::current();
        if (f && f->share_taken) return false;
        if (f) f->share_taken = true;
        return fair_share_.refuse(req, res);
    };
    server_.set_pre_routing_handler([this, refuse_share](const httplib::Request& req, httplib::Response& res) {
        return refuse_before_body(req, res) || refuse_share(req, res) || refuse_body(req, res)
                   ? httplib::Server::HandlerResponse::Handled
                   : httplib::Server::HandlerResponse::Unhandled;
    });
    server_.set_expect_100_continue_handler([this, refuse_share](const httplib::Request& req, httplib::Response& res) {
        return refuse_before_body(req, res) || refuse_share(req, res) || refuse_body(req, res) ? res.status : 100;
    });
    // The body has been parsed and handled: its bytes go back before the answer is written, so
    // a client that sends its next body as soon as it reads the answer finds them free.
    server_.set_post_routing_handler([](const httplib::Request&, httplib::Response&) {
        if (RequestFraming* f = Front::current()) {
            f->body_ticket.reset();
            f->request_ticket.reset();  // a stream's handler has returned: it holds no slot while it streams
        }
    });

    // Called for every answer >= 400. httplib answers some failures itself (unknown route, a
    // body it could not read) with an empty body.
    server_.set_error_handler(httplib::Server::HandlerWithResponse([this](const httplib::Request& req, httplib::Response& res) {
        Front::on_error_answer(res);  // may say why httplib gave up: 408, 413, 431
        if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
        std::string message = "request failed with status " + std::to_string(res.status);
        if (res.status == 404) message = "no route for " + req.method + " " + req.path;
        if (res.status == 413) {
            const RequestFraming* f = Front::current();  // the route's own limit (Front::allow_body), if any
            message = body_too_large(f && f->max_body_bytes ? f->max_body_bytes : server_.options().max_body_bytes).message;
        }
        if (res.status == 408) message = "the request did not arrive in time";
        if (res.status == 431) message = "the request head is larger than the server accepts";
        write_error(res, res.status, code_for_status(res.status), message);
        return httplib::Server::HandlerResponse::Handled;
    }));

    server_.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        write_error(res, 500, "internal", "internal error");
    });

    if (options_.access_log) {
        server_.set_logger([](const httplib::Request& req, const httplib::Response& res) {
            const RequestFraming* f = Front::current();
            const auto us = f ? std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() -
                                                                                      f->start)
                                    .count()
                              : 0;
            const std::string line = json_text(json{{"ts", utc_now()},
                                                    {"method", req.method},
                                                    {"path", req.path},
                                                    {"status", res.status},
                                                    {"us", us},
                                                    {"remote", req.remote_addr}}) +
                                     "\n";
            std::fwrite(line.data(), 1, line.size(), stderr);
        });
    }
}

void App::install_health() {
    server_.Get("/health", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(R"({"status":"ok"})", "application/json");
    });
    // Readiness: /health above is liveness and touches nothing; this commits a one-row write,
    // so a full disk, a read-only, corrupt or locked database turns it 503.
    server_.Get("/ready", [this](const httplib::Request&, httplib::Response& res) {
        try {
            store_.probe_write();
            res.set_content(R"({"status":"ready"})", "application/json");
        } catch (const std::exception& e) {
            res.set_header("Retry-After", "1");
            write_error(res, 503, "storage_unavailable", "database '" + store_.location() + "' cannot be written: " + e.what());
            std::fprintf(stderr, "{\"event\":\"not_ready\",\"db\":%s,\"message\":%s}\n", json_text(store_.location()).c_str(),
                         json_text(e.what()).c_str());
        }
    });
}

}  // namespace locus::http
