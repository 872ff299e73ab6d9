// Who a request is from (http/front/client_address.hpp): the peer, unless the peer is a trusted
// proxy; then the right-most X-Forwarded-For entry that is not one. IPv6 clients by their /64.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "http/front/client_address.hpp"

namespace client_address_test {
namespace {

using locus::http::client_of;
using locus::http::parse_range;
using locus::http::parse_trusted_proxies;

const std::vector<locus::http::AddressRange> kNone;

TEST(ClientAddress, WithoutTrustedProxiesTheHeaderIsIgnored) {
    EXPECT_EQ(client_of("203.0.113.7", {"198.51.100.1"}, kNone), "203.0.113.7");
    EXPECT_EQ(client_of("127.0.0.1", {}, kNone), "127.0.0.1");
}

TEST(ClientAddress, AnUntrustedPeerIsTheClient) {
    const auto trusted = parse_trusted_proxies({"10.0.0.5"});
    EXPECT_EQ(client_of("203.0.113.7", {"198.51.100.1"}, trusted), "203.0.113.7");
}

TEST(ClientAddress, TheRightMostUntrustedEntryBehindATrustedProxy) {
    const auto trusted = parse_trusted_proxies({"10.0.0.5", "10.1.0.0/16"});
    EXPECT_EQ(client_of("10.0.0.5", {"198.51.100.1"}, trusted), "198.51.100.1");
    // The client wrote the left entry itself: only what the proxies appended counts.
    EXPECT_EQ(client_of("10.0.0.5", {"1.2.3.4, 198.51.100.1"}, trusted), "198.51.100.1");
    // Two proxies: the inner one (10.1.2.3) appended the outer's client.
    EXPECT_EQ(client_of("10.0.0.5", {"1.2.3.4, 198.51.100.1, 10.1.2.3"}, trusted), "198.51.100.1");
    // Several headers are one list, in order.
    EXPECT_EQ(client_of("10.0.0.5", {"1.2.3.4", "198.51.100.9"}, trusted), "198.51.100.9");
    // No header: the proxy itself.
    EXPECT_EQ(client_of("10.0.0.5", {}, trusted), "10.0.0.5");
    // Every entry a trusted proxy: the left-most of them.
    EXPECT_EQ(client_of("10.0.0.5", {"10.1.0.1, 10.1.0.2"}, trusted), "10.1.0.1");
    // Garbage where a proxy's entry should be: the proxy that vouched last is the client.
    EXPECT_EQ(client_of("10.0.0.5", {"198.51.100.1, evil"}, trusted), "10.0.0.5");
    EXPECT_EQ(client_of("10.0.0.5", {" 198.51.100.1 ,, "}, trusted), "198.51.100.1");
}

TEST(ClientAddress, IPv6IsKeyedByItsSlash64) {
    EXPECT_EQ(client_of("2001:db8:1:2::5", {}, kNone), "2001:db8:1:2::/64");
    EXPECT_EQ(client_of("2001:db8:1:2:ffff:1:2:3", {}, kNone), "2001:db8:1:2::/64");
    EXPECT_EQ(client_of("::ffff:192.0.2.4", {}, kNone), "192.0.2.4");
    const auto trusted = parse_trusted_proxies({"::1"});
    EXPECT_EQ(client_of("::1", {"2001:db8::7"}, trusted), "2001:db8::/64");
}

TEST(ClientAddress, RangesContainTheirAddresses) {
    const auto r = parse_range("10.1.0.0/16");
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->contains(*parse_range("10.1.255.3")));
    EXPECT_FALSE(r->contains(*parse_range("10.2.0.1")));
    EXPECT_FALSE(r->contains(*parse_range("::1")));
    const auto v6 = parse_range("fd00::/8");
    ASSERT_TRUE(v6);
    EXPECT_TRUE(v6->contains(*parse_range("fd12:3456::1")));
    EXPECT_FALSE(v6->contains(*parse_range("fe80::1")));
    EXPECT_TRUE(parse_range("0.0.0.0/0")->contains(*parse_range("8.8.8.8")));
    const auto mapped = parse_range("::ffff:10.0.0.0/104");
    ASSERT_TRUE(mapped);
    EXPECT_TRUE(mapped->contains(*parse_range("10.9.9.9")));
}

TEST(ClientAddress, BadProxyValuesAreRefusedByName) {
    for (const char* bad : {"nginx", "10.0.0.1/8", "10.0.0.0/33", "10.0.0.0/", "10.0.0.0/x", "1.2.3.4:80", "[::1]", "", "::/129",
                            "10.0.0.0/-1"}) {
        try {
            parse_trusted_proxies({bad});
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(parse_trusted_proxies({"10.0.0.5,172.16.0.0/12", "::1"}).size(), 3u);
    EXPECT_THROW(parse_trusted_proxies({"10.0.0.5,"}), std::invalid_argument);
}

// Who is on this machine: loopback addresses of both families, after the proxies are walked.
TEST(ClientAddress, LoopbackIsThisMachinesAddressesOnly) {
    const auto loopback = [](const char* text) { return locus::http::is_loopback(*locus::http::parse_address(text)); };
    for (const char* local : {"127.0.0.1", "127.0.0.2", "127.255.255.254", "::1", "::ffff:127.0.0.1"}) EXPECT_TRUE(loopback(local)) << local;
    for (const char* other : {"10.0.0.1", "128.0.0.1", "126.255.255.255", "0.0.0.0", "::", "::2", "::ffff:10.0.0.1", "fe80::1", "2001:db8::1"})
        EXPECT_FALSE(loopback(other)) << other;
    const auto trusted = parse_trusted_proxies({"127.0.0.1"});
    const auto through = [&](const std::vector<std::string>& forwarded) {
        return locus::http::is_loopback(*locus::http::client_address("127.0.0.1", forwarded, trusted));
    };
    EXPECT_TRUE(through({}));
    EXPECT_TRUE(through({"127.0.0.9"}));
    EXPECT_FALSE(through({"203.0.113.7"}));
    EXPECT_FALSE(through({"127.0.0.9, 203.0.113.7"}));
    EXPECT_FALSE(locus::http::client_address("not an address", {}, trusted).has_value());
}

}  // namespace
}  // namespace client_address_test
