// How the CLI prints numbers in messages it passes on (the server formats ranges with
// std::to_string: "'rss' = 50.000000 is outside [-120.000000, 0.000000]").
#include <gtest/gtest.h>

#include "survey_connect.hpp"

namespace cli_messages_test {
namespace {

using locus::tools::plain_numbers;

TEST(PlainNumbers, SixDecimalNumbersLoseTheirTrailingZeros) {
    EXPECT_EQ(plain_numbers("'rss' = 50.000000 is outside [-120.000000, 0.000000]"), "'rss' = 50 is outside [-120, 0]");
    EXPECT_EQ(plain_numbers("'k' = 2.500000 is outside [1.000000, 100.000000]"), "'k' = 2.5 is outside [1, 100]");
    EXPECT_EQ(plain_numbers("-0.000000 and 0.125000 and -3.141593"), "0 and 0.125 and -3.141593");
}

TEST(PlainNumbers, OtherTextIsLeftAlone) {
    EXPECT_EQ(plain_numbers("radiomap 999 not found"), "radiomap 999 not found");
    EXPECT_EQ(plain_numbers("1.5 m, 0.1234567 and 1.0000000"), "1.5 m, 0.1234567 and 1.0000000");
    EXPECT_EQ(plain_numbers(""), "");
}

}  // namespace
}  // namespace cli_messages_test
