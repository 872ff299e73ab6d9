#pragma once
// Who a request comes from, for the per-client limits (docs/deploy.md "Per-client limits").
//
// A client is the address its connection comes from. Behind a reverse proxy every request
// comes from the proxy, so `X-Forwarded-For` is read, but only when the connection comes from
// a proxy the operator named (--trusted-proxy): anyone else could write any address there.
// The client is then the right-most entry that is not itself a trusted proxy (each proxy
// appends the address it was reached from; entries left of it were written by the client and
// prove nothing).
//
// An IPv6 client is keyed by its /64: a single host is commonly handed a whole /64, so keying
// by the full address would give one client 2^64 shares. An IPv4-mapped IPv6 address counts
// as its IPv4 address.
//
// Pure text and address arithmetic (inet_pton), no I/O. Costs: parse O(length);
// client_of O(entries × trusted ranges).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace locus::http {

// An address range: a family's address and how many leading bits are fixed.
struct AddressRange {
    bool v6 = false;
    std::array<std::uint8_t, 16> bytes{};  // IPv4: the first 4
    int prefix = 0;
    bool contains(const AddressRange& address) const;  // `address` with its full prefix
};

// One address ("10.0.0.5", "::1") or CIDR range ("10.0.0.0/8", "fd00::/8"); nullopt for
// anything else (a host name, a port, a prefix longer than the family has, bits set past it).
std::optional<AddressRange> parse_range(std::string_view text);
// One address, as parse_range but without a prefix; "[::1]" and "1.2.3.4:port" are not taken.
std::optional<AddressRange> parse_address(std::string_view text);

// --trusted-proxy values: each an address or range, or a comma-separated list of them.
// std::invalid_argument naming the first bad entry.
std::vector<AddressRange> parse_trusted_proxies(const std::vector<std::string>& values);

// The client key of a request from `remote` (the connection's peer address) carrying the
// `forwarded` X-Forwarded-For header values, in the order they came (empty: none). With no
// trusted proxy, or a peer that is not one, the peer is the client. An entry that is not an
// address stops the walk: the proxy right of it is the client then.
std::string client_of(const std::string& remote, const std::vector<std::string>& forwarded,
                      const std::vector<AddressRange>& trusted);
// The client's address as client_of finds it; nullopt for a peer that is not an address.
std::optional<AddressRange> client_address(const std::string& remote, const std::vector<std::string>& forwarded,
                                           const std::vector<AddressRange>& trusted);
// This machine: 127.0.0.0/8, ::1, or an IPv4 loopback address mapped into IPv6.
bool is_loopback(const AddressRange& address);

// The key of one address: IPv4 as written by inet_ntop, IPv6 as its /64 ("2001:db8:1:2::/64").
std::string client_key(const AddressRange& address);

}  // namespace locus::http
