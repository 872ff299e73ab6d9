// The budget of request bodies in flight (http/front/body_budget.hpp): a server-wide total and
// a per-client share, each body's bytes held until its ticket goes; a body larger than a
// budget holding nothing else still passes alone; the operator (no client) has no share.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "http/front/body_budget.hpp"

namespace body_budget_test {
namespace {

using locus::http::BodyBudget;
using Verdict = BodyBudget::Verdict;

TEST(BodyBudget, AClientHoldsItsShareUntilItsTicketsGo) {
    BodyBudget b({.total_bytes = 1000, .client_bytes = 400, .small_bytes = 10, .client_small_bytes = 30});
    BodyBudget::Ticket first, second, third;
    EXPECT_EQ(b.admit(std::string("a"), 300, first), Verdict::admitted);
    EXPECT_EQ(b.admit(std::string("a"), 100, second), Verdict::admitted);
    EXPECT_EQ(b.in_flight(), 400u);
    EXPECT_EQ(b.admit(std::string("a"), 11, third), Verdict::client_full);
    EXPECT_EQ(third.bytes(), 0u);  // a refusal holds nothing
    EXPECT_EQ(b.admit(std::string("b"), 400, third), Verdict::admitted);  // another client's share
    first.reset();
    EXPECT_EQ(b.in_flight(), 500u);
    BodyBudget::Ticket again;
    EXPECT_EQ(b.admit(std::string("a"), 300, again), Verdict::admitted);
}

TEST(BodyBudget, TheTotalBoundsEveryClientTogether) {
    BodyBudget b({.total_bytes = 1000, .client_bytes = 600, .small_bytes = 10, .client_small_bytes = 30});
    BodyBudget::Ticket t[4];
    EXPECT_EQ(b.admit(std::string("a"), 500, t[0]), Verdict::admitted);
    EXPECT_EQ(b.admit(std::string("b"), 500, t[1]), Verdict::admitted);
    EXPECT_EQ(b.admit(std::string("c"), 11, t[2]), Verdict::server_full);
    EXPECT_EQ(b.admit(std::nullopt, 11, t[2]), Verdict::server_full);  // the operator too: memory is memory
    {
        const BodyBudget::Ticket gone = std::move(t[1]);  // a moved ticket holds, and gives back once
    }
    EXPECT_EQ(b.in_flight(), 500u);
    EXPECT_EQ(b.admit(std::string("c"), 500, t[2]), Verdict::admitted);
}

TEST(BodyBudget, TheOperatorHasNoShareAndEmptyBodiesCostNothing) {
    BodyBudget b({.total_bytes = 1000, .client_bytes = 100, .small_bytes = 10, .client_small_bytes = 30});
    BodyBudget::Ticket t[3];
    EXPECT_EQ(b.admit(std::nullopt, 300, t[0]), Verdict::admitted);
    EXPECT_EQ(b.admit(std::nullopt, 300, t[1]), Verdict::admitted);
    EXPECT_EQ(b.admit(std::string("a"), 0, t[2]), Verdict::admitted);
    EXPECT_EQ(b.in_flight(), 600u);
}

TEST(BodyBudget, ABodyLargerThanABudgetPassesAlone) {
    BodyBudget b({.total_bytes = 1000, .client_bytes = 100, .small_bytes = 10, .client_small_bytes = 30});
    BodyBudget::Ticket big, next;
    EXPECT_EQ(b.admit(std::string("a"), 5000, big), Verdict::admitted);  // over both, but nothing else is held
    EXPECT_EQ(b.admit(std::string("b"), 20, next), Verdict::server_full);
    big.reset();
    EXPECT_EQ(b.in_flight(), 0u);
    EXPECT_EQ(b.admit(std::string("b"), 20, next), Verdict::admitted);
}

TEST(BodyBudget, SmallBodiesHaveAShareOfTheirOwnOutsideTheTotal) {
    BodyBudget b({.total_bytes = 100, .client_bytes = 100, .small_bytes = 10, .client_small_bytes = 30});
    BodyBudget::Ticket large, small[4];
    EXPECT_EQ(b.admit(std::string("a"), 100, large), Verdict::admitted);  // the client's share and the total, full
    EXPECT_EQ(b.admit(std::string("a"), 10, small[0]), Verdict::admitted);  // its phone still localizes
    EXPECT_EQ(b.admit(std::string("b"), 10, small[1]), Verdict::admitted);  // and so does anyone's
    EXPECT_EQ(b.admit(std::string("a"), 10, small[2]), Verdict::admitted);
    EXPECT_EQ(b.admit(std::string("a"), 10, small[3]), Verdict::admitted);
    BodyBudget::Ticket more;
    EXPECT_EQ(b.admit(std::string("a"), 1, more), Verdict::client_full);  // 30 of small bodies held
    EXPECT_EQ(b.in_flight(), 100u);  // small ones are not in the total
    small[0].reset();
    EXPECT_EQ(b.admit(std::string("a"), 10, more), Verdict::admitted);
    EXPECT_EQ(b.admit(std::nullopt, 10, small[0]), Verdict::admitted);  // the operator's small bodies pass
}

}  // namespace
}  // namespace body_budget_test
