#pragma once
// One client connection as cpp-httplib's Stream, kept for the connection's whole life.
//
// cpp-httplib's own server makes a new stream per request, so bytes it read past one request
// (the next, pipelined request) were dropped with it and the client hung until the keep-alive
// timeout. This stream keeps its buffer across requests, so pipelined requests are answered
// in order. It also enforces what the library cannot be configured to enforce:
// - a deadline for the whole request head (a client trickling a byte a second is cut off
//   after --header-timeout, not kept forever by a per-read timeout) and a cap on its size;
//   the head's bytes are kept, so what cpp-httplib's parser skips over can be checked;
// - a deadline for the whole body, from its size at a slow phone's rate;
// - a byte budget for the body, counted on the wire, so a chunked body cannot pass
//   --max-body-bytes (cpp-httplib checks the limit against Content-Length only);
// - a wake descriptor: when it becomes readable (server shutdown), waits for a next request,
//   a request head or a body end at once (nothing has been written for that request yet);
// - is_writable() is false once the peer closed or reset the connection, so an answer still
//   being produced for nobody (an event stream waiting for news) ends at once.
// All waits use poll(), so descriptors above FD_SETSIZE are fine.
#include <httplib.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace locus::http {

class ConnectionStream final : public httplib::Stream {
public:
    using Clock = std::chrono::steady_clock;
    enum class Failure { none, closed, timeout, head_too_large, body_too_large, stopped, error };

    ConnectionStream(int fd, int wake_fd, std::chrono::milliseconds read_timeout, std::chrono::milliseconds write_timeout);

    bool is_readable() const override { return begin_ < end_; }
    bool is_writable() const override;
    ssize_t read(char* ptr, size_t size) override;
    ssize_t write(const char* ptr, size_t size) override;
    void get_remote_ip_and_port(std::string& ip, int& port) const override;
    void get_local_ip_and_port(std::string& ip, int& port) const override;
    socket_t socket() const override { return fd_; }

    // Waits until a next request's first byte is here (buffered or arriving within `idle`).
    // False on timeout, close, error or shutdown.
    bool wait_for_request(std::chrono::milliseconds idle);
    // From here on, reads belong to a request head: they end at `deadline`, after `max_bytes`,
    // or when the wake descriptor fires. The head's bytes are kept (head()).
    void begin_head(Clock::time_point deadline, std::size_t max_bytes);
    // From here on, reads belong to the body: at most `budget` bytes, each read waiting at most
    // the read timeout and all of them ending at `deadline` (a body trickled a byte at a time
    // must not hold a worker for ever).
    void begin_body(std::uint64_t budget, Clock::time_point deadline);
    // No write of this answer waits past `until` (the next request head lifts it): an answer
    // with a time limit of its own (an export) is cut then, not a write timeout later.
    void limit_writes(Clock::time_point until) { write_deadline_ = until; }

    // The request head as it came on the wire (request line, headers, blank line), so far.
    const std::string& head();

    std::uint64_t consumed() const { return consumed_; }  // bytes handed to the reader so far
    std::uint64_t written() const { return written_; }    // bytes sent so far
    Failure failure() const { return failure_; }

private:
    enum class Phase { head, body };
    bool fill();  // false: failure_ says why (closed: orderly end of stream)
    bool wait(short events, Clock::time_point until, bool wakeable);

    int fd_, wake_fd_;
    std::chrono::milliseconds read_timeout_, write_timeout_;
    Phase phase_ = Phase::head;
    Clock::time_point deadline_ = Clock::time_point::max();  // of the head, or of the body
    Clock::time_point write_deadline_ = Clock::time_point::max();  // limit_writes
    std::optional<std::uint64_t> remaining_;  // bytes this phase may still read
    std::uint64_t consumed_ = 0, written_ = 0;
    std::string head_;          // the head's bytes that have left the buffer
    std::size_t head_from_ = 0;  // where the head's bytes not yet in head_ start in buffer_
    Failure failure_ = Failure::none;
    static constexpr std::size_t kBufferSize = 16 * 1024;
    char buffer_[kBufferSize];
    std::size_t begin_ = 0, end_ = 0;
};

}  // namespace locus::http
