#pragma once
// The HTTP front: cpp-httplib's Server with its connection handling replaced, through the
// library's own extension points (the virtual process_and_close_socket, the protected
// process_request, a TaskQueue from new_task_queue, the socket options callback). Routing,
// request parsing and answer writing stay cpp-httplib's.
//
// What it adds, and why (each was seen failing with cpp-httplib's defaults):
// - A worker per open connection, started on demand (ConnectionPool), so idle keep-alive
//   clients cannot take every worker; past --max-connections a client gets an immediate
//   503 server_busy (Retry-After: 1) instead of waiting in a queue.
// - One stream per connection (ConnectionStream), so pipelined requests are answered in order.
// - A deadline for each request head (--header-timeout), a short idle keep-alive timeout and
//   a cap on requests per connection.
// - Framing checks before any body is read (refusal()): one decimal Content-Length, no
//   Content-Length together with Transfer-Encoding, only `chunked` as a coding, no body on
//   GET/HEAD/OPTIONS (no length on a route whose body is optional, allow_no_body: an empty
//   body), nothing over --max-body-bytes (or a route's own limit, allow_body). A chunked body is counted on the wire.
// - Bodies limited by their decoded size: a Content-Encoding is taken off before cpp-httplib
//   reads the body (it would inflate it without a bound), refused with 415 where the route
//   takes none, and decoded under the route's limit once read (body_coding.hpp): 413 past it.
// - Head lines cpp-httplib's parser would skip or misread (a bare LF, space before a colon,
//   a folded line) are refused: a skipped Content-Length would leave a body to be read as
//   the next request.
// - A connection whose request body was not read to its end (a refused write), and every
//   chunked request (cpp-httplib ends a chunked body early at a malformed chunk and reports
//   success), is closed after the answer, which says `Connection: close`: unread bytes are
//   never taken for a next request (request smuggling behind a proxy).
// - No SO_REUSEPORT: a second server on the same port fails to start instead of splitting
//   the traffic between two databases. The listen backlog is raised from the library's 5.
// - Shutdown wakes idle connections at once.
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "http/front/body_budget.hpp"
#include "http/front/body_coding.hpp"

namespace locus::http {

class ConnectionStream;

struct FrontOptions {
    std::size_t min_threads = 8;             // workers kept when idle
    std::size_t max_connections = 2048;      // open connections served at once; more get 503
    std::chrono::milliseconds keep_alive_timeout{10'000};
    std::size_t keep_alive_max_requests = 1000;
    std::chrono::milliseconds header_timeout{10'000};  // from a request's first byte to its blank line
    std::chrono::milliseconds read_timeout{10'000};    // longest wait for the next bytes of a body
    // The slowest a body may come on the whole: it must be read within read_timeout plus its
    // length at this rate (8 MiB: 42 s), so a body trickled a byte at a time is dropped well
    // before minutes, while a phone on a poor link (2 Mbit/s) still sends a full one.
    std::uint64_t min_body_rate = 256u * 1024u;  // bytes a second
    std::chrono::milliseconds write_timeout{10'000};
    std::size_t max_header_bytes = 64 * 1024;
    std::uint64_t max_body_bytes = 8u * 1024u * 1024u;
};

// What the connection layer knows of the request being served; handlers reach it through
// Front::current() because cpp-httplib's handler signature carries no connection.
struct RequestFraming {
    std::chrono::steady_clock::time_point start;  // the request's first byte was awaited from here
    bool parsed = false;                         // the head was read and parsed
    std::optional<std::string> head_problem;     // a head line cpp-httplib would skip or misread
    std::optional<std::uint64_t> content_length;
    std::size_t content_length_headers = 0;
    bool valid_content_length = true;            // every Content-Length was one decimal number
    bool chunked = false;
    bool other_coding = false;                   // a Transfer-Encoding other than one `chunked`
    std::uint64_t max_body_bytes = 0;            // on the wire, and once decoded
    std::string content_encoding;                // as sent (several joined by ", "); taken off the request
    bool codings_allowed = true;                 // the route takes gzip and deflate (allow_body)
    httplib::Request* request = nullptr;         // the request being read, whose body finish_body decodes
    std::uint64_t head_end = 0;                  // stream position where the body starts
    bool close = false;                          // end the connection after this answer
    bool share_taken = false;                    // the client's fair share was charged (app.cpp)
    bool body_admitted = false;                  // the body budget was asked (app.cpp)
    BodyBudget::Ticket body_ticket;              // the body's bytes in flight, given back with the framing
    BodyBudget::Ticket request_ticket;           // the client's request slot, while its handler runs
    // The answer's: the budget it is admitted against and the client it counts for (set by
    // the app before routing; none: not counted), its ticket, held until it is written.
    BodyBudget* answers = nullptr;
    std::optional<std::string> client;
    BodyBudget::Ticket answer_ticket;
    std::chrono::milliseconds write_timeout{0};  // the server's, for admit_answer's deadline
    std::uint64_t min_rate = 0;
    ConnectionStream* stream = nullptr;

    // A Content-Length body not read to its end: its rest would be taken for a next request.
    bool body_left_unread() const;
};

struct Refusal {
    int status;
    std::string code, message;
};

// The 413 refusal of a body over `max_body_bytes`, known before or after reading it.
Refusal body_too_large(std::uint64_t max_body_bytes);

class Front : public httplib::Server {
public:
    explicit Front(FrontOptions options = {});
    ~Front() override;
    Front(const Front&) = delete;
    Front& operator=(const Front&) = delete;

    // Binds and listens (port 0: any free port). Returns the port, or -1 with `error` set.
    int bind(const std::string& host, int port, std::string& error);
    // Serves until shut_down(); false if accepting failed.
    bool serve() { return listen_after_bind(); }
    // Stops accepting and wakes every connection waiting for a request; returns at once.
    void shut_down();

    const FrontOptions& options() const { return options_; }
    // A route that takes a larger body than --max-body-bytes (a plan image): a request whose
    // method and path (a full regex match) fit is allowed `bytes` instead, and nothing else
    // is. `codings`: whether the body may come gzip- or deflate-encoded (false: 415 for any
    // Content-Encoding; a route without an entry takes them). Called while routes are added,
    // before serving.
    void allow_body(const std::string& method, const std::string& path_regex, std::uint64_t bytes, bool codings = true);
    // A route whose body is optional (an action such as closing a track): a request with
    // neither Content-Length nor a chunked body has an empty body, as RFC 9112 §6.3 says,
    // instead of 411 (`curl -X POST` sends no length). Called while routes are added.
    void allow_no_body(const std::string& method, const std::string& path_regex);
    std::size_t open_connections() const { return open_.load(); }

    // Why the request now being read must be refused before its body is read, if it must.
    std::optional<Refusal> refusal(const httplib::Request& req) const;

    // The request being served on this thread, or nullptr.
    static RequestFraming* current();
    // Ends the connection after this answer, and says so in the answer.
    static void close_after(httplib::Response& res);
    // No write of the answer now being served waits past `until` (ConnectionStream::limit_writes).
    static void limit_writes(std::chrono::steady_clock::time_point until);
    // Before an answer of `bytes` is handed to the connection: it must be written within the
    // write timeout plus its size at --min-body-rate (a reader that does not keep up is cut),
    // and its bytes are admitted against the answer budget the app named in the framing,
    // held until written. The refusal (429 too_many_answers, 503 server_busy) if they do not fit.
    static std::optional<Refusal> admit_answer(std::uint64_t bytes);
    // Once the body is read, before a handler sees it: a chunked body over its limit (its
    // length was not known before), then an encoded body decoded in place of the one read,
    // 413 if its decoded size is over the limit and 400 if it does not decode.
    static std::optional<Refusal> finish_body(const httplib::Request& req);
    // Called for every answer >= 400: when the connection layer cut the body or head short,
    // turns cpp-httplib's bare 400 into 413, 408 or 431, and ends the connection when its
    // place in the stream is lost.
    static void on_error_answer(httplib::Response& res);

private:
    bool process_and_close_socket(socket_t sock) override;
    void serve_connection(int fd);
    void start_request(httplib::Request& req, RequestFraming& framing, ConnectionStream& stream) const;
    // The body limit of this request: its route's (allow_body), else --max-body-bytes.
    std::uint64_t body_limit(const httplib::Request& req) const;

    struct RouteBodyLimit {
        std::string method;
        std::regex path;
        std::uint64_t bytes;
        bool codings;
    };
    const RouteBodyLimit* route_limit(const httplib::Request& req) const;
    std::vector<RouteBodyLimit> route_body_limits_;
    std::vector<std::pair<std::string, std::regex>> optional_bodies_;

    FrontOptions options_;
    std::atomic<std::size_t> open_{0};
    std::atomic<bool> stopping_{false};
    int wake_[2] = {-1, -1};  // a pipe; its read end becomes readable at shutdown
};

}  // namespace locus::http
