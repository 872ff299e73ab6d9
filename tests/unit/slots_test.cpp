// http::Slots (http/front/slots.hpp): the cap shared by the quality assessments and the exports.
#include "http/front/slots.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <utility>

#include "http/api_error.hpp"

namespace slots_test {
namespace {

using locus::http::ApiError;
using locus::http::Slots;

TEST(Slots, PastTheCountATakeIsServerBusyWithRetryAfter) {
    Slots slots(2);
    httplib::Response res;
    const auto a = slots.take(res, "busy");
    const auto b = slots.take(res, "busy");
    EXPECT_FALSE(res.has_header("Retry-After"));
    try {
        (void)slots.take(res, "2 things are running already", 7);
        FAIL() << "a third slot was given";
    } catch (const ApiError& e) {
        EXPECT_EQ(e.status, 503);
        EXPECT_EQ(e.code, "server_busy");
        EXPECT_STREQ(e.what(), "2 things are running already");
    }
    EXPECT_EQ(res.get_header_value("Retry-After"), "7");
}

TEST(Slots, ASlotComesBackWhenItsLastHolderGoes) {
    Slots slots(1);
    httplib::Response res;
    std::optional<Slots::Held> moved;
    {
        auto held = slots.take(res, "busy");
        moved.emplace(std::move(held));  // the moved-from one gives nothing back
    }
    EXPECT_THROW((void)slots.take(res, "busy"), ApiError);
    moved.reset();
    const auto again = slots.take(res, "busy");
    EXPECT_THROW((void)slots.take(res, "busy"), ApiError);
}

}  // namespace
}  // namespace slots_test
