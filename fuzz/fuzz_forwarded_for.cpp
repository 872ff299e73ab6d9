// Who a request is from (server/http/client_address.*): the first line of the input is a
// --trusted-proxy value, the second the peer address, each further line an X-Forwarded-For
// header value.
//
// Checks: parse_trusted_proxies throws nothing but std::invalid_argument; client_of always
// answers a key, and that key is the peer's own unless the peer is a trusted proxy; a key is
// an IPv4 address or an IPv6 /64 when the peer is an address; client_address is the address
// that key is of, and is loopback only when its text says so.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "http/front/client_address.hpp"

using namespace locus::http;

namespace {

[[noreturn]] void fail(const char* what, const std::string& input) {
    std::fprintf(stderr, "fuzz_forwarded_for: %s\ninput (%zu bytes): %s\n", what, input.size(), input.c_str());
    std::abort();
}

bool is_key(const std::string& key) {
    if (key.ends_with("/64")) {
        const auto a = parse_address(key.substr(0, key.size() - 3));
        return a && a->v6;
    }
    const auto a = parse_address(key);
    return a && !a->v6;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string input(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> lines;
    std::size_t start = 0;
    for (std::size_t nl; (nl = input.find('\n', start)) != std::string::npos; start = nl + 1) lines.push_back(input.substr(start, nl - start));
    lines.push_back(input.substr(start));
    std::vector<AddressRange> trusted;
    try {
        trusted = parse_trusted_proxies({lines[0]});
    } catch (const std::invalid_argument&) {
        trusted.clear();
    }
    const std::string peer = lines.size() > 1 ? lines[1] : "127.0.0.1";
    const std::vector<std::string> forwarded(lines.begin() + std::min<std::ptrdiff_t>(2, static_cast<std::ptrdiff_t>(lines.size())), lines.end());
    const std::string key = client_of(peer, forwarded, trusted);
    const auto peer_address = parse_address(peer);
    if (!peer_address) {
        if (key != peer) fail("a peer that is not an address did not stay its own key", input);
        return 0;
    }
    if (!is_key(key)) fail("the key is neither an IPv4 address nor an IPv6 /64", input);
    bool peer_trusted = false;
    for (const auto& r : trusted) peer_trusted = peer_trusted || r.contains(*peer_address);
    if (!peer_trusted && key != client_key(*peer_address)) fail("X-Forwarded-For was taken from an untrusted peer", input);
    const auto address = client_address(peer, forwarded, trusted);
    if (!address || client_key(*address) != key) fail("client_address is not the address of client_of's key", input);
    const bool v4_loopback = !address->v6 && address->bytes[0] == 127;
    if (!address->v6 && is_loopback(*address) != v4_loopback) fail("is_loopback disagrees with 127.0.0.0/8", input);
    return 0;
}
