#pragma once
// A raw TCP connection to a test server on 127.0.0.1, for the connection-level tests: it sends
// exactly the bytes given (pipelined requests, trickled heads, lying framing) and reads the
// answers back one by one, so what the server does with each byte can be checked.
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace locus::testing {

struct RawAnswer {
    int status = 0;
    std::string head;  // status line and headers
    std::string body;
    // The value of a header (case-insensitive name), or "" when absent.
    std::string header(const std::string& name) const;
};

class RawConnection {
public:
    // Connects at once; connected() says whether it worked. A `receive_buffer` (bytes, before
    // connecting) keeps the kernel from buffering much for a client that stops reading, so the
    // server's writes to it block sooner.
    explicit RawConnection(int port, int receive_buffer = 0);
    ~RawConnection();
    RawConnection(const RawConnection&) = delete;
    RawConnection& operator=(const RawConnection&) = delete;

    bool connected() const { return fd_ >= 0; }
    bool send(const std::string& bytes);
    // The next answer (read by its Content-Length), or nullopt when none arrives in time or
    // the server closed the connection first.
    std::optional<RawAnswer> read_answer(std::chrono::milliseconds timeout = std::chrono::seconds(5));
    // True when the server closes the connection (end of stream or reset) within `timeout`;
    // bytes that arrive meanwhile are kept for read_answer.
    bool closed_within(std::chrono::milliseconds timeout);
    // The bytes received that read_answer has not taken (a chunked body, as it came).
    const std::string& pending() const { return buffer_; }

private:
    bool fill(std::chrono::steady_clock::time_point until);  // false: timeout or closed
    int fd_ = -1;
    bool eof_ = false;
    std::string buffer_;
};

// "GET /path HTTP/1.1" with a Host header and, if given, extra header lines ("Name: value\r\n").
std::string raw_get(const std::string& path, const std::string& extra_headers = {});
// A POST with a Content-Length body.
std::string raw_post(const std::string& path, const std::string& body, const std::string& extra_headers = {});
// A POST with a chunked body, cut into chunks of `chunk_size` bytes.
std::string raw_chunked_post(const std::string& path, const std::string& body, std::size_t chunk_size,
                             const std::string& extra_headers = {});

// Seconds until `attempt` (say, a new connection asking for a stream: true once admitted)
// first succeeds, trying again at once for up to `limit`; nullopt when it never does.
std::optional<double> seconds_until(const std::function<bool()>& attempt, std::chrono::milliseconds limit);

}  // namespace locus::testing
