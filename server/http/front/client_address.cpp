#include "http/front/client_address.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <stdexcept>

namespace locus::http {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

// ::ffff:a.b.c.d is the IPv4 client a.b.c.d (a dual-stack listener reports it so).
void unmap(AddressRange& a) {
    static constexpr std::uint8_t prefix[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
    if (!a.v6 || std::memcmp(a.bytes.data(), prefix, sizeof prefix) != 0) return;
    std::array<std::uint8_t, 16> v4{};
    std::copy(a.bytes.begin() + 12, a.bytes.end(), v4.begin());
    a.bytes = v4;
    a.v6 = false;
    a.prefix = a.prefix >= 96 ? a.prefix - 96 : 0;
}

bool bit_set(const std::array<std::uint8_t, 16>& b, int i) { return (b[static_cast<std::size_t>(i / 8)] >> (7 - i % 8)) & 1; }

}  // namespace

bool AddressRange::contains(const AddressRange& address) const {
    if (address.v6 != v6) return false;
    for (int i = 0; i < prefix; ++i)
        if (bit_set(bytes, i) != bit_set(address.bytes, i)) return false;
    return true;
}

std::optional<AddressRange> parse_address(std::string_view text) {
    // inet_pton needs a terminated string; an address is at most 45 characters.
    if (text.empty() || text.size() > 45) return std::nullopt;
    char buf[46];
    std::memcpy(buf, text.data(), text.size());
    buf[text.size()] = '\0';
    AddressRange a;
    if (inet_pton(AF_INET, buf, a.bytes.data()) == 1) {
        a.prefix = 32;
    } else if (inet_pton(AF_INET6, buf, a.bytes.data()) == 1) {
        a.v6 = true;
        a.prefix = 128;
        unmap(a);
    } else {
        return std::nullopt;
    }
    return a;
}

std::optional<AddressRange> parse_range(std::string_view text) {
    text = trim(text);
    const auto slash = text.find('/');
    auto a = parse_address(text.substr(0, slash));
    if (!a || slash == std::string_view::npos) return a;
    const std::string_view digits = text.substr(slash + 1);
    int prefix = -1;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), prefix);
    // An IPv4-mapped range was unmapped with its full length; its prefix counts from bit 96.
    const bool mapped = !a->v6 && text.substr(0, slash).find(':') != std::string_view::npos;
    const int max = a->v6 || mapped ? 128 : 32;
    if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size() || prefix < 0 || prefix > max) return std::nullopt;
    if (mapped) {
        if (prefix < 96) return std::nullopt;
        prefix -= 96;
    }
    a->prefix = prefix;
    // "10.0.0.1/8" most likely means something other than 10.0.0.0/8: refused, not guessed.
    for (int i = prefix; i < (a->v6 ? 128 : 32); ++i)
        if (bit_set(a->bytes, i)) return std::nullopt;
    return a;
}

std::vector<AddressRange> parse_trusted_proxies(const std::vector<std::string>& values) {
    std::vector<AddressRange> out;
    for (const auto& value : values) {
        std::string_view rest = value;
        while (true) {
            const auto comma = rest.find(',');
            const std::string_view entry = trim(rest.substr(0, comma));
            const auto r = parse_range(entry);
            if (!r)
                throw std::invalid_argument("--trusted-proxy: '" + std::string(entry) +
                                            "' is not an IP address or CIDR range (e.g. 10.0.0.5, 10.0.0.0/8, fd00::/8)");
            out.push_back(*r);
            if (comma == std::string_view::npos) break;
            rest.remove_prefix(comma + 1);
        }
    }
    return out;
}

std::string client_key(const AddressRange& address) {
    char buf[INET6_ADDRSTRLEN] = {};
    if (!address.v6) {
        inet_ntop(AF_INET, address.bytes.data(), buf, sizeof buf);
        return buf;
    }
    std::array<std::uint8_t, 16> net{};
    std::copy(address.bytes.begin(), address.bytes.begin() + 8, net.begin());
    inet_ntop(AF_INET6, net.data(), buf, sizeof buf);
    return std::string(buf) + "/64";
}

std::string client_of(const std::string& remote, const std::vector<std::string>& forwarded,
                      const std::vector<AddressRange>& trusted) {
    // A peer that is not an address (a Unix socket) is one client.
    const auto client = client_address(remote, forwarded, trusted);
    return client ? client_key(*client) : remote;
}

bool is_loopback(const AddressRange& a) {
    if (!a.v6) return a.bytes[0] == 127;
    const auto zero = [&](int from, int to) {
        return std::all_of(a.bytes.begin() + from, a.bytes.begin() + to, [](std::uint8_t b) { return b == 0; });
    };
    if (zero(0, 15) && a.bytes[15] == 1) return true;                                   // ::1
    return zero(0, 10) && a.bytes[10] == 0xff && a.bytes[11] == 0xff && a.bytes[12] == 127;  // ::ffff:127.x.y.z
}

std::optional<AddressRange> client_address(const std::string& remote, const std::vector<std::string>& forwarded,
                                           const std::vector<AddressRange>& trusted) {
    const auto peer = parse_address(remote);
    if (!peer) return std::nullopt;
    const auto is_trusted = [&](const AddressRange& a) {
        return std::any_of(trusted.begin(), trusted.end(), [&](const AddressRange& r) { return r.contains(a); });
    };
    AddressRange client = *peer;
    if (trusted.empty() || !is_trusted(client)) return client;
    // Every value's entries, right to left; several headers count as one list in order.
    for (auto v = forwarded.rbegin(); v != forwarded.rend(); ++v) {
        std::string_view rest = *v;
        while (true) {
            const auto comma = rest.rfind(',');
            const std::string_view entry = trim(comma == std::string_view::npos ? rest : rest.substr(comma + 1));
            if (!entry.empty()) {
                const auto a = parse_address(entry);
                if (!a) return client;  // not written by a proxy: the last one vouched for is the client
                client = *a;
                if (!is_trusted(client)) return client;
            }
            if (comma == std::string_view::npos) break;
            rest = rest.substr(0, comma);
        }
    }
    return client;  // every hop a trusted proxy: the left-most one
}

}  // namespace locus::http
