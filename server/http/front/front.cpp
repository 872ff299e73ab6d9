#include "http/front/front.hpp"

#include <fcntl.h>
#include <poll.h>
#include <strings.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string_view>

#include "http/front/connection_pool.hpp"
#include "http/front/connection_stream.hpp"

namespace locus::http {

namespace {

using Clock = std::chrono::steady_clock;

thread_local RequestFraming* current_framing = nullptr;

void send_all(int fd, const std::string& bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;  // a full send buffer on a brand-new connection: the client is gone
        sent += static_cast<std::size_t>(n);
    }
}

// A chunked body's decoded size is checked once read (Front::body_over_limit); on the wire,
// chunk-size lines and CRLFs included, it may take this much before reading stops: enough
// for chunks of a few bytes, and a bound on what a client can make the server read.
std::uint64_t chunked_budget(std::uint64_t max_body) { return 2 * max_body + 64 * 1024; }

// How long `bytes` take at FrontOptions::min_body_rate, the slowest a body or an answer may go.
std::chrono::milliseconds at_rate(std::uint64_t bytes, std::uint64_t min_rate) {
    return std::chrono::milliseconds(bytes * 1000 / std::max<std::uint64_t>(min_rate, 1));
}

// The time a body of `budget` bytes may take; past it, and past 10 minutes for any body, a
// body trickled a byte at a time stops holding a worker.
std::chrono::milliseconds body_time(std::uint64_t budget, std::chrono::milliseconds read_timeout, std::uint64_t min_rate) {
    return std::min<std::chrono::milliseconds>(read_timeout + at_rate(budget, min_rate), std::chrono::minutes(10));
}

// What cpp-httplib's head parser would skip or misread without a word: a line not ending in
// CRLF, whitespace before a header's colon, a folded (obs-fold) line, a line without a name.
std::optional<std::string> head_problem(const std::string& head) {
    std::size_t pos = 0;
    bool request_line = true;
    while (pos < head.size()) {
        const std::size_t nl = head.find('\n', pos);
        if (nl == std::string::npos) break;
        if (nl == pos || head[nl - 1] != '\r') return "a line of the request head does not end in CRLF";
        const std::string_view line(head.data() + pos, nl - 1 - pos);
        pos = nl + 1;
        if (line.empty()) break;  // the blank line that ends the head
        if (request_line) {
            request_line = false;
            continue;
        }
        if (line.front() == ' ' || line.front() == '\t') return "a folded header line (obs-fold) is not accepted";
        const std::size_t colon = line.find(':');
        if (colon == std::string_view::npos || colon == 0) return "a header line has no name";
        if (line[colon - 1] == ' ' || line[colon - 1] == '\t') return "a header name is followed by whitespace before its colon";
    }
    return std::nullopt;
}

// An answer written straight to the socket, where cpp-httplib gives none (the connection cap,
// a request line it gave up on); the connection closes after it.
std::string canned_answer(int status, const char* reason, const std::string& extra_headers, const std::string& code,
                          const std::string& message) {
    const std::string body = R"({"error":{"code":")" + code + R"(","message":")" + message + R"("}})";
    return "HTTP/1.1 " + std::to_string(status) + " " + reason + "\r\nContent-Type: application/json\r\n" +
           extra_headers + "Connection: close\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

bool all_digits(const std::string& s) {
    return !s.empty() && s.size() <= 19 &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool has_body_method(const std::string& method) { return method == "POST" || method == "PUT" || method == "PATCH"; }

Refusal unsupported_coding(const RequestFraming& f) {
    const std::string sent = f.content_encoding.size() > 64 ? f.content_encoding.substr(0, 64) + "..." : f.content_encoding;
    if (!f.codings_allowed)
        return {415, "unsupported_encoding",
                "this route takes its body without a Content-Encoding (got '" + sent + "')"};
    return {415, "unsupported_encoding",
            "Content-Encoding '" + sent + "' is not accepted: send the body as is, or with one of gzip, deflate"};
}

// After refusing or breaking off a request, the client may still be sending. Closing with
// unread bytes makes the kernel answer with RST, which can destroy our answer before the
// client reads it; so stop writing, read and drop what comes for a moment, then close.
void close_lingering(int fd, std::chrono::milliseconds linger, std::uint64_t max_bytes) {
    ::shutdown(fd, SHUT_WR);
    const auto until = Clock::now() + linger;
    char scratch[16 * 1024];
    std::uint64_t dropped = 0;
    while (dropped < max_bytes) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(until - Clock::now()).count();
        if (left <= 0) break;
        pollfd p{fd, POLLIN, 0};
        const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));  // 1 s of silence ends it
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        const ssize_t n = ::recv(fd, scratch, sizeof scratch, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        dropped += static_cast<std::size_t>(n);
    }
    ::close(fd);
}

// Soft descriptor limit up to the hard one: each connection is a descriptor, and the usual
// soft limit (1024) is below a thousand phones. Returns the limit now in force.
rlim_t raise_descriptor_limit() {
    rlimit lim{};
    if (::getrlimit(RLIMIT_NOFILE, &lim) != 0) return 1024;
    if (lim.rlim_cur < lim.rlim_max) {
        rlimit raised = lim;
        raised.rlim_cur = lim.rlim_max;
        if (::setrlimit(RLIMIT_NOFILE, &raised) == 0) lim = raised;
    }
    return lim.rlim_cur;
}


// The Accept-Encoding list without `br`. cpp-httplib as Debian builds it prefers Brotli
// whenever a client lists it, at Brotli's slowest quality: 2 s for a 1,000-RP export that
// gzip sends in 15 ms. Every browser lists `br`; gzip is what it gets instead.
std::string without_brotli(const std::string& accept) {
    std::string kept;
    std::size_t start = 0;
    while (start <= accept.size()) {
        std::size_t end = accept.find(',', start);
        if (end == std::string::npos) end = accept.size();
        const std::string item = accept.substr(start, end - start);
        const std::size_t first = item.find_first_not_of(" \t");
        const std::size_t name_end = item.find_first_of(" \t;", first == std::string::npos ? 0 : first);
        const std::string name = first == std::string::npos ? "" : item.substr(first, name_end - first);
        if (!name.empty() && strcasecmp(name.c_str(), "br") != 0) kept += (kept.empty() ? "" : ", ") + item.substr(first);
        start = end + 1;
    }
    return kept;
}

}  // namespace

Front::Front(FrontOptions options) : options_(options) {
    if (::pipe2(wake_, O_CLOEXEC) != 0) wake_[0] = wake_[1] = -1;
    new_task_queue = [this] { return new ConnectionPool(options_.min_threads, options_.max_connections + 64); };
    // cpp-httplib's default also sets SO_REUSEPORT, with which a second server binds the same
    // port and the kernel splits connections between the two.
    set_socket_options([](socket_t sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    // Answers go out as headers then body in two writes; with Nagle on, every answer on a
    // kept-alive connection waits for the client's delayed ACK (~40 ms on Linux).
    set_tcp_nodelay(true);
    set_read_timeout(std::chrono::duration_cast<std::chrono::seconds>(options_.read_timeout).count(), 0);
    set_write_timeout(std::chrono::duration_cast<std::chrono::seconds>(options_.write_timeout).count(), 0);
    set_keep_alive_max_count(options_.keep_alive_max_requests);
    set_keep_alive_timeout(std::chrono::duration_cast<std::chrono::seconds>(options_.keep_alive_timeout).count());
    set_payload_max_length(options_.max_body_bytes);
}

Front::~Front() {
    for (int fd : wake_)
        if (fd >= 0) ::close(fd);
}

int Front::bind(const std::string& host, int port, std::string& error) {
    const rlim_t descriptors = raise_descriptor_limit();
    if (descriptors < options_.max_connections + 64)
        options_.max_connections = descriptors > 128 ? static_cast<std::size_t>(descriptors - 64) : 64;
    errno = 0;
    const int bound = port == 0 ? bind_to_any_port(host) : (bind_to_port(host, port) ? port : -1);
    if (bound < 0) {
        error = "cannot listen on " + host + ":" + std::to_string(port) +
                (errno != 0 ? std::string(": ") + std::strerror(errno) : std::string());
        return -1;
    }
    // A burst of connecting phones overflowed cpp-httplib's backlog of 5 (SYNs dropped and
    // retried a second later); listen() again only changes the backlog.
    ::listen(svr_sock_, SOMAXCONN);
    return bound;
}

void Front::shut_down() {
    stopping_ = true;
    if (wake_[1] >= 0) {
        const char byte = 1;
        [[maybe_unused]] const auto n = ::write(wake_[1], &byte, 1);
    }
    stop();
    // stop() does nothing before the accept loop has started: close the listening socket
    // here, so that loop ends at once instead of serving for ever.
    const socket_t sock = svr_sock_.exchange(INVALID_SOCKET);
    if (sock != INVALID_SOCKET) {
        ::shutdown(sock, SHUT_RDWR);
        ::close(sock);
    }
}

RequestFraming* Front::current() { return current_framing; }

void Front::close_after(httplib::Response& res) {
    if (current_framing) current_framing->close = true;
    if (res.get_header_value("Connection") != "close") res.set_header("Connection", "close");
}

void Front::limit_writes(Clock::time_point until) {
    if (current_framing && current_framing->stream) current_framing->stream->limit_writes(until);
}

std::optional<Refusal> Front::admit_answer(std::uint64_t bytes) {
    RequestFraming* f = current_framing;
    if (!f) return std::nullopt;
    if (f->stream && f->min_rate > 0) f->stream->limit_writes(Clock::now() + f->write_timeout + at_rate(bytes, f->min_rate));
    if (!f->answers) return std::nullopt;
    const auto verdict = f->answers->admit(f->client, bytes, f->answer_ticket);
    if (verdict == BodyBudget::Verdict::admitted) return std::nullopt;
    const auto& o = f->answers->options();
    if (verdict == BodyBudget::Verdict::server_full)
        return Refusal{503, "server_busy",
                       "the server is writing as many answers as it holds at once (--max-answer-bytes-in-flight " +
                           std::to_string(o.total_bytes) + " bytes); retry shortly"};
    return Refusal{429, "too_many_answers",
                   "this client's answers not yet read reach its share (--client-answer-bytes-in-flight " +
                       std::to_string(o.client_bytes) + " bytes); read them before asking for more"};
}

std::optional<Refusal> Front::finish_body(const httplib::Request& req) {
    RequestFraming* f = current_framing;
    if (!f) return std::nullopt;
    if (f->chunked && req.body.size() > f->max_body_bytes) return body_too_large(f->max_body_bytes);
    if (f->content_encoding.empty() || f->request != &req) return std::nullopt;
    const auto coding = parse_body_coding(f->content_encoding);
    if (!coding) return unsupported_coding(*f);  // refusal() answered it before the body; kept for safety
    DecodedBody decoded = decode_body(req.body, *coding, f->max_body_bytes);
    f->content_encoding.clear();  // decoded once, even if a handler asks again
    if (decoded.status == DecodedBody::Status::too_large) {
        f->request->body.clear();
        return Refusal{413, "payload_too_large",
                       "the request body, once decoded, is larger than the server accepts (" +
                           std::to_string(f->max_body_bytes) + " bytes)"};
    }
    if (decoded.status == DecodedBody::Status::corrupt)
        return Refusal{400, "bad_encoding", "the body does not decode as its Content-Encoding says: " + decoded.problem};
    // The connection owns the request object; handlers are given it const, so the decoded
    // body replaces the encoded one here, before any handler reads it.
    f->request->body = std::move(decoded.body);
    return std::nullopt;
}

Refusal body_too_large(std::uint64_t max_body_bytes) {
    return {413, "payload_too_large",
            "the request body is larger than the server accepts (" + std::to_string(max_body_bytes) + " bytes)"};
}

bool RequestFraming::body_left_unread() const {
    return content_length && stream && stream->consumed() - head_end < *content_length;
}

void Front::on_error_answer(httplib::Response& res) {
    RequestFraming* f = current_framing;
    if (!f) return;
    if (f->stream && res.status == 400 && res.body.empty()) {
        switch (f->stream->failure()) {
            case ConnectionStream::Failure::body_too_large: res.status = 413; break;
            case ConnectionStream::Failure::timeout: res.status = 408; break;
            case ConnectionStream::Failure::head_too_large: res.status = 431; break;
            default: break;
        }
    }
    // cpp-httplib's own failures (an empty body) mean it lost its place in the stream.
    const bool framing_lost = res.body.empty() && (res.status == 400 || res.status == 408 || res.status == 411 ||
                                                   res.status == 413 || res.status == 431);
    if (!f->parsed || f->close || f->body_left_unread() || framing_lost) close_after(res);
}

std::optional<Refusal> Front::refusal(const httplib::Request& req) const {
    const RequestFraming* f = current_framing;
    if (!f) return std::nullopt;
    if (f->head_problem) return Refusal{400, "bad_request", *f->head_problem};
    if (f->content_length_headers > 1 || !f->valid_content_length)
        return Refusal{400, "bad_request", "Content-Length must be given once, as a decimal number"};
    const bool has_coding = req.has_header("Transfer-Encoding");
    if (has_coding && f->content_length_headers > 0)
        return Refusal{400, "bad_request", "a request may not carry both Content-Length and Transfer-Encoding"};
    if (!has_body_method(req.method)) {
        if ((f->content_length && *f->content_length > 0) || has_coding)
            return Refusal{400, "bad_request", "a " + req.method + " request carries no body"};
        return std::nullopt;
    }
    // cpp-httplib would read a body without a length (or with another coding) until the client
    // closes the connection: the request would wait out the read timeout and get a bare 400.
    if (f->other_coding || (!f->content_length && !f->chunked))
        return Refusal{411, "length_required", "a " + req.method + " needs a Content-Length (or a chunked body)"};
    if (const auto limit = body_limit(req); f->content_length && *f->content_length > limit) return body_too_large(limit);
    if (!f->content_encoding.empty()) {
        const auto coding = parse_body_coding(f->content_encoding);
        if (!coding || (*coding != BodyCoding::identity && !f->codings_allowed)) return unsupported_coding(*f);
    }
    return std::nullopt;
}

void Front::allow_body(const std::string& method, const std::string& path_regex, std::uint64_t bytes, bool codings) {
    route_body_limits_.push_back({method, std::regex(path_regex), bytes, codings});
    // cpp-httplib's own check comes after ours (refusal, body_over_limit): it must let the
    // largest allowed body through.
    std::uint64_t largest = options_.max_body_bytes;
    for (const auto& l : route_body_limits_) largest = std::max(largest, l.bytes);
    set_payload_max_length(largest);
}

const Front::RouteBodyLimit* Front::route_limit(const httplib::Request& req) const {
    for (const auto& l : route_body_limits_)
        if (req.method == l.method && std::regex_match(req.path, l.path)) return &l;
    return nullptr;
}

void Front::allow_no_body(const std::string& method, const std::string& path_regex) {
    optional_bodies_.emplace_back(method, std::regex(path_regex));
}

std::uint64_t Front::body_limit(const httplib::Request& req) const {
    const RouteBodyLimit* l = route_limit(req);
    return l ? l->bytes : options_.max_body_bytes;
}

void Front::start_request(httplib::Request& req, RequestFraming& framing, ConnectionStream& stream) const {
    framing.parsed = true;
    framing.head_end = stream.consumed();
    framing.write_timeout = options_.write_timeout;
    framing.min_rate = options_.min_body_rate;
    framing.head_problem = head_problem(stream.head());  // before begin_body, which keeps the head
    const RouteBodyLimit* route = route_limit(req);
    framing.max_body_bytes = route ? route->bytes : options_.max_body_bytes;
    framing.codings_allowed = !route || route->codings;
    framing.request = &req;
    // Taken off before cpp-httplib reads the body, which it would otherwise inflate into
    // memory with no bound; finish_body decodes it under the limit.
    const std::size_t encodings = req.get_header_value_count("Content-Encoding");
    for (std::size_t i = 0; i < encodings; ++i)
        framing.content_encoding += (i ? ", " : "") + req.get_header_value("Content-Encoding", i);
    if (encodings > 0 && framing.content_encoding.empty()) framing.content_encoding = " ";  // present but blank
    req.headers.erase("Content-Encoding");
    if (has_body_method(req.method) && !req.has_header("Content-Length") && !req.has_header("Transfer-Encoding") &&
        std::any_of(optional_bodies_.begin(), optional_bodies_.end(),
                    [&](const auto& r) { return r.first == req.method && std::regex_match(req.path, r.second); }))
        req.headers.emplace("Content-Length", "0");  // cpp-httplib then reads no body
    framing.content_length_headers = req.get_header_value_count("Content-Length");
    for (std::size_t i = 0; i < framing.content_length_headers; ++i) {
        const std::string value = req.get_header_value("Content-Length", i);
        if (!all_digits(value)) framing.valid_content_length = false;
        else if (!framing.content_length) framing.content_length = std::stoull(value);
    }
    const std::size_t codings = req.get_header_value_count("Transfer-Encoding");
    framing.chunked = codings == 1 && strcasecmp(req.get_header_value("Transfer-Encoding").c_str(), "chunked") == 0;
    framing.other_coding = codings > 0 && !framing.chunked;
    if (framing.chunked) framing.close = true;

    // The body budget: a length is read exactly; a chunked body up to the limit on the wire.
    std::uint64_t budget = 0;
    if (framing.content_length && framing.valid_content_length) budget = *framing.content_length;
    else if (framing.chunked) budget = chunked_budget(framing.max_body_bytes);
    stream.begin_body(budget, Clock::now() + body_time(budget, options_.read_timeout, options_.min_body_rate));

    // `curl -d` sends JSON as a form; cpp-httplib parses forms and refuses them past 8 KiB.
    // Every body of this API is JSON, whatever the client calls it.
    auto type = req.headers.find("Content-Type");
    if (type != req.headers.end() && strncasecmp(type->second.c_str(), "application/x-www-form-urlencoded", 33) == 0)
        type->second = "application/json";
    const auto accepts = req.headers.equal_range("Accept-Encoding");
    for (auto it = accepts.first; it != accepts.second; ++it) it->second = without_brotli(it->second);
}

bool Front::process_and_close_socket(socket_t sock) {
    const std::size_t open = ++open_;
    if (open > options_.max_connections || stopping_) {
        // Written before reading anything: cheap on purpose.
        send_all(sock, canned_answer(503, "Service Unavailable", "Retry-After: 1\r\n", "server_busy",
                                     "the server is serving its limit of " + std::to_string(options_.max_connections) +
                                         " connections; retry shortly"));
        --open_;
        close_lingering(sock, std::chrono::milliseconds(200), 64 * 1024);
        return true;
    }
    serve_connection(sock);
    --open_;
    return true;
}

void Front::serve_connection(int fd) {
    ConnectionStream stream(fd, wake_[0], options_.read_timeout, options_.write_timeout);
    bool linger = false;
    for (std::size_t served = 0; !stopping_; ++served) {
        if (!stream.wait_for_request(served == 0 ? options_.header_timeout : options_.keep_alive_timeout)) break;
        RequestFraming framing;
        framing.start = Clock::now();
        framing.stream = &stream;
        current_framing = &framing;
        stream.begin_head(Clock::now() + options_.header_timeout, options_.max_header_bytes);
        const bool last = served + 1 >= options_.keep_alive_max_requests || stopping_;
        bool client_closes = false;
        const std::uint64_t written_before = stream.written();
        const bool answered =
            process_request(stream, last, client_closes, [&](httplib::Request& req) { start_request(req, framing, stream); });
        current_framing = nullptr;
        // An answer cut while being written (an export past its time limit) gets nothing
        // after it: the client sees the cut, not a second status line inside the body.
        if (!answered && !stream.head().empty() && stream.written() == written_before) {
            // cpp-httplib gives up on a request line without answering; say why.
            if (stream.failure() == ConnectionStream::Failure::timeout)
                send_all(fd, canned_answer(408, "Request Timeout", "", "request_timeout", "the request did not arrive in time"));
            else if (stream.failure() == ConnectionStream::Failure::head_too_large)
                send_all(fd, canned_answer(431, "Request Header Fields Too Large", "", "header_too_large",
                                           "the request head is larger than the server accepts"));
        }
        // Every chunked request has framing.close set (start_request).
        if (!answered || !framing.parsed || framing.close || framing.body_left_unread()) {
            linger = true;
            break;
        }
        if (client_closes || last) break;
    }
    if (linger) {
        // Long enough for a client that writes its whole body before reading (cpp-httplib's
        // own client does) to finish and read the refusal; bounded in time and bytes.
        close_lingering(fd, std::chrono::seconds(5), std::max<std::uint64_t>(4 * options_.max_body_bytes, 16u << 20));
    } else {
        ::shutdown(fd, SHUT_RDWR);
        ::close(fd);
    }
}

}  // namespace locus::http
