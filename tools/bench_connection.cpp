#include "bench_connection.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <string_view>

namespace locus::tools {

namespace {
constexpr std::size_t kMaxBody = 64u << 20;  // far above any answer of ours; guards the buffer
constexpr std::size_t kMaxHead = 64u << 10;

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
    return true;
}

bool iequals_prefix(std::string_view line, std::string_view name) {
    return line.size() >= name.size() && iequals(line.substr(0, name.size()), name);
}

std::string_view trim_blanks(std::string_view v) {
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
    while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
    return v;
}

}  // namespace

std::string http_request(const std::string& method, const std::string& path, const std::string& host_port,
                         const std::string& body, const std::string& extra_headers) {
    std::string r = method + " " + path + " HTTP/1.1\r\nHost: " + host_port + "\r\n" + extra_headers;
    if (!body.empty() || method == "POST")
        r += "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) + "\r\n";
    return r + "\r\n" + body;
}

BenchConnection::~BenchConnection() { close(); }

int open_socket(const std::string& host, int port, const std::string& source) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return -1;
    int fd = -1;
    for (addrinfo* a = found; a && fd < 0; a = a->ai_next) {
        fd = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
        if (fd < 0) continue;
        // Before connect: on Linux the send timeout also bounds connect(), so a full
        // listen backlog cannot hold a thread past the benchmark's time limit.
        const timeval timeout{10, 0};
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
        ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
        if (!source.empty()) {
            sockaddr_in local{};
            local.sin_family = AF_INET;
            if (a->ai_family != AF_INET || ::inet_pton(AF_INET, source.c_str(), &local.sin_addr) != 1 ||
                ::bind(fd, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
                ::close(fd);
                fd = -1;
                continue;
            }
        }
        if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
            ::close(fd);
            fd = -1;
        }
    }
    freeaddrinfo(found);
    if (fd >= 0) {
        const int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    }
    return fd;
}

bool BenchConnection::open() {
    close();
    fd_ = open_socket(host_, port_, source_);
    buffer_.clear();
    return fd_ >= 0;
}

void BenchConnection::close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

std::optional<int> BenchConnection::round_trip(const std::string& request, std::string* body) {
    if (fd_ < 0 && !open()) return std::nullopt;
    for (std::size_t sent = 0; sent < request.size();) {
        const ssize_t n = ::send(fd_, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            close();
            return std::nullopt;
        }
        sent += static_cast<std::size_t>(n);
    }
    auto status = read_answer(body);
    if (!status) close();
    return status;
}

std::optional<int> BenchConnection::read_answer(std::string* body) {
    char chunk[16384];
    const auto receive = [&]() -> bool {
        for (;;) {
            const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) return false;
            buffer_.append(chunk, static_cast<std::size_t>(n));
            return true;
        }
    };
    std::size_t head_end;
    while ((head_end = buffer_.find("\r\n\r\n")) == std::string::npos)
        if (buffer_.size() > kMaxHead || !receive()) return std::nullopt;
    const std::string_view head(buffer_.data(), head_end);
    // "HTTP/1.1 200 OK"
    const auto space = head.find(' ');
    int status = 0;
    if (!head.starts_with("HTTP/1.") || space == std::string_view::npos ||
        std::from_chars(head.data() + space + 1, head.data() + head.size(), status).ec != std::errc())
        return std::nullopt;
    std::optional<std::size_t> length;
    bool close_after = false;
    for (std::size_t at = head.find("\r\n"); at != std::string_view::npos;) {
        const std::size_t next = head.find("\r\n", at + 2);
        const std::string_view line = head.substr(at + 2, next == std::string_view::npos ? std::string_view::npos : next - at - 2);
        if (iequals_prefix(line, "content-length:")) {
            const auto value = trim_blanks(line.substr(15));
            std::size_t n = 0;
            const auto r = std::from_chars(value.data(), value.data() + value.size(), n);
            if (r.ec != std::errc() || r.ptr != value.data() + value.size() || n > kMaxBody || (length && *length != n))
                return std::nullopt;
            length = n;
        } else if (iequals_prefix(line, "transfer-encoding:")) {
            return std::nullopt;  // chunked answers: not something our server sends
        } else if (iequals_prefix(line, "connection:") && iequals(trim_blanks(line.substr(11)), "close")) {
            close_after = true;
        }
        at = next;
    }
    // Without a length the end of the answer is unknowable here (only 204 and 304 have no body).
    if (!length && status != 204 && status != 304) return std::nullopt;
    const std::size_t total = head_end + 4 + length.value_or(0);
    while (buffer_.size() < total)
        if (!receive()) return std::nullopt;
    if (body) body->assign(buffer_, head_end + 4, length.value_or(0));
    buffer_.erase(0, total);
    if (close_after) close();
    return status;
}

}  // namespace locus::tools
