#include "http/front/connection_stream.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

namespace locus::http {

namespace {

void address_of(int fd, bool peer, std::string& ip, int& port) {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    const int r = peer ? ::getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len)
                       : ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    if (r != 0) return;
    char host[NI_MAXHOST], serv[NI_MAXSERV];
    if (::getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, serv, sizeof serv,
                      NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
        ip = host;
        port = std::atoi(serv);
    }
}

}  // namespace

ConnectionStream::ConnectionStream(int fd, int wake_fd, std::chrono::milliseconds read_timeout,
                                   std::chrono::milliseconds write_timeout)
    : fd_(fd), wake_fd_(wake_fd), read_timeout_(read_timeout), write_timeout_(write_timeout) {}

bool ConnectionStream::wait(short events, Clock::time_point until, bool wakeable) {
    for (;;) {
        const auto now = Clock::now();
        if (now >= until) {
            failure_ = Failure::timeout;
            return false;
        }
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(until - now).count();
        pollfd fds[2] = {{fd_, events, 0}, {wake_fd_, POLLIN, 0}};
        const nfds_t count = wakeable && wake_fd_ >= 0 ? 2 : 1;
        const int r = ::poll(fds, count, static_cast<int>(std::min<long long>(left, INT_MAX)));
        if (r < 0) {
            if (errno == EINTR) continue;
            failure_ = Failure::error;
            return false;
        }
        if (r == 0) continue;  // the loop checks the clock
        if (count == 2 && fds[1].revents != 0) {
            failure_ = Failure::stopped;
            return false;
        }
        if (fds[0].revents != 0) return true;  // POLLHUP and POLLERR too: recv/send say what
    }
}

bool ConnectionStream::fill() {
    if (phase_ == Phase::head) head_.append(buffer_ + head_from_, end_ - head_from_);  // all of it was read
    begin_ = end_ = head_from_ = 0;
    const auto until = phase_ == Phase::head ? deadline_ : std::min(deadline_, Clock::now() + read_timeout_);
    // Read first, wait only when nothing is there: on a busy kept-alive connection the next
    // request has usually arrived, and a poll() before every recv() would double the calls.
    for (;;) {
        const ssize_t n = ::recv(fd_, buffer_, kBufferSize, MSG_DONTWAIT);
        if (n > 0) {
            end_ = static_cast<std::size_t>(n);
            return true;
        }
        if (n == 0) {
            failure_ = Failure::closed;
            return false;
        }
        if (errno == EINTR) continue;
        if (errno != EAGAIN && errno != EWOULDBLOCK) {
            failure_ = Failure::error;
            return false;
        }
        if (!wait(POLLIN, until, true)) return false;
    }
}

ssize_t ConnectionStream::read(char* ptr, size_t size) {
    if (size == 0) return 0;
    std::uint64_t want = size;
    if (remaining_) {
        if (*remaining_ == 0) {
            failure_ = phase_ == Phase::head ? Failure::head_too_large : Failure::body_too_large;
            return -1;
        }
        want = std::min(want, *remaining_);
    }
    if (begin_ == end_ && !fill()) return failure_ == Failure::closed ? 0 : -1;
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(want, end_ - begin_));
    std::memcpy(ptr, buffer_ + begin_, n);
    begin_ += n;
    consumed_ += n;
    if (remaining_) *remaining_ -= n;
    return static_cast<ssize_t>(n);
}

bool ConnectionStream::is_writable() const {
    const auto now = Clock::now();
    if (now >= write_deadline_) return false;
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(write_deadline_ - now);
    // A peer that closed (its FIN: POLLRDHUP) or reset the connection reads nothing more: an
    // answer still being produced for it (an event stream waiting for news) ends now. An HTTP
    // client does not half-close a connection it still reads from.
    pollfd fd{fd_, POLLOUT | POLLRDHUP, 0};
    if (::poll(&fd, 1, static_cast<int>(std::min(write_timeout_, left).count())) <= 0) return false;
    return (fd.revents & (POLLRDHUP | POLLHUP | POLLERR)) == 0;
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
    // Send first, wait only when the socket's buffer is full (as fill() reads first).
    // Not woken at shutdown: the answer to a request already served should still reach its client.
    const auto until = std::min(Clock::now() + write_timeout_, write_deadline_);
    for (;;) {
        const ssize_t n = ::send(fd_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n >= 0) {
            written_ += static_cast<std::uint64_t>(n);
            return n;
        }
        if (errno == EINTR) continue;
        if (errno != EAGAIN && errno != EWOULDBLOCK) {
            failure_ = Failure::error;
            return -1;
        }
        if (!wait(POLLOUT, until, false)) return -1;
    }
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const { address_of(fd_, true, ip, port); }
void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const { address_of(fd_, false, ip, port); }

bool ConnectionStream::wait_for_request(std::chrono::milliseconds idle) {
    failure_ = Failure::none;
    if (begin_ < end_) return true;
    return wait(POLLIN, Clock::now() + idle, true);
}

void ConnectionStream::begin_head(Clock::time_point deadline, std::size_t max_bytes) {
    phase_ = Phase::head;
    deadline_ = deadline;
    remaining_ = max_bytes;
    write_deadline_ = Clock::time_point::max();
    failure_ = Failure::none;
    head_.clear();
    head_from_ = begin_;
}

const std::string& ConnectionStream::head() {
    if (phase_ == Phase::head) {
        head_.append(buffer_ + head_from_, begin_ - head_from_);
        head_from_ = begin_;
    }
    return head_;
}

void ConnectionStream::begin_body(std::uint64_t budget, Clock::time_point deadline) {
    head();  // the head's last bytes are in the buffer still
    phase_ = Phase::body;
    remaining_ = budget;
    deadline_ = deadline;
}

}  // namespace locus::http
