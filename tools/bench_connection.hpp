#pragma once
// One keep-alive HTTP/1.1 connection for the load generator of `locus bench localize`.
//
// Why not cpp-httplib's client, which the rest of the tools use: it writes a request's headers
// and body with two send() calls, so every POST reaches the server as two segments and the
// server thread wakes twice; and it builds each request anew. A load generator should cost
// the machine as little as possible and the same for every request kind, so this one sends
// each pre-built request in a single write (as curl and wrk do) and reads the answer by its
// Content-Length. It speaks only what the benchmark needs: no chunked bodies, no TLS.
#include <optional>
#include <string>
#include <utility>

namespace locus::tools {

class BenchConnection {
public:
    // `source`: the local address to connect from ("127.0.0.2": a second client on loopback),
    // empty for the kernel's choice.
    BenchConnection(std::string host, int port, std::string source = {})
        : host_(std::move(host)), port_(port), source_(std::move(source)) {}
    ~BenchConnection();
    BenchConnection(const BenchConnection&) = delete;
    BenchConnection& operator=(const BenchConnection&) = delete;

    // Sends one complete request and returns the answer's status code, or nullopt on a
    // network error or a malformed answer (the connection is then closed and reopened on the
    // next call). The answer body is dropped, or kept in `body` when given.
    std::optional<int> round_trip(const std::string& request, std::string* body = nullptr);
    // Connects now rather than on the first request; false if the server cannot be reached.
    bool open();

private:
    void close();
    std::optional<int> read_answer(std::string* body);

    std::string host_;
    int port_;
    std::string source_;
    int fd_ = -1;
    std::string buffer_;  // bytes received past the previous answer
};

// A blocking TCP connection with TCP_NODELAY and 10 s send/receive timeouts, or -1; from the
// local address `source` when one is given (IPv4).
int open_socket(const std::string& host, int port, const std::string& source = {});

// "POST /path HTTP/1.1" with Host, Content-Type and Content-Length, any `extra_headers`
// ("Name: value\r\n" lines), then the body.
std::string http_request(const std::string& method, const std::string& path, const std::string& host_port,
                         const std::string& body = {}, const std::string& extra_headers = {});

}  // namespace locus::tools
