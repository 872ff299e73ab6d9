// match::held_out_errors: each RP's error when held out, as tune's folds hold it out.
#include <gtest/gtest.h>

#include <cmath>

#include "locus/match/quality.hpp"
#include "match_fixture.hpp"

namespace match_quality_test {
namespace {

using namespace locus;
using namespace locus::match;
using locus::match::testing::m;
using locus::match::testing::rp;

// RPs every 2 m along a corridor, signals falling off with distance from four AP spots.
std::vector<IndexedRp> corridor(int n, long long floor = 1) {
    std::vector<IndexedRp> rps;
    for (int i = 0; i < n; ++i) {
        const double x = 2.0 * i;
        std::vector<Measurement> ms;
        for (int a = 0; a < 4; ++a) ms.push_back(m("aa:00:00:00:00:0" + std::to_string(a), -30.0 - 1.5 * std::abs(x - 10.0 * a)));
        rps.push_back(rp(100 + i, {x, 0.0}, ms, floor));
    }
    return rps;
}

Setting knn1() {
    Setting s;
    s.algorithm = Algorithm::knn;
    s.options.k = 1;
    return s;
}

long long level(long long floor) { return floor; }

TEST(MatchQuality, EachRpGetsItsOwnErrorAndTheirMeanIsTunes) {
    auto rps = corridor(10);
    // An RP whose stored signals are another place's (x = 4 m's).
    rps[9].rp.measurements = rps[2].rp.measurements;
    const auto q = held_out_errors(rps, knn1(), level, {.folds = 10});
    ASSERT_EQ(q.rps.size(), 10u);
    EXPECT_EQ(q.queries, 10u);
    for (std::size_t i = 0; i < 8; ++i) {
        ASSERT_TRUE(q.rps[i].error_m) << i;
        EXPECT_EQ(q.rps[i].rp, i);
        EXPECT_TRUE(q.rps[i].floor_ok);
    }
    // The twins place each other: x = 18 m at x = 4 m and back, 14 m; every other RP lands on a
    // neighbour 2 m away.
    ASSERT_TRUE(q.rps[9].error_m);
    EXPECT_NEAR(*q.rps[9].error_m, 14.0, 1e-9);
    EXPECT_NEAR(*q.rps[2].error_m, 14.0, 1e-9);
    double sum = 0;
    for (const auto& r : q.rps) {
        sum += *r.error_m;
        if (r.rp != 2 && r.rp != 9) {
            EXPECT_LT(*r.error_m, 14.0) << r.rp;
        }
    }
    // The same folds as tune's: the mean is tune's row for this setting.
    const std::vector<TuneCandidate> grid{{"knn k=1", knn1()}};
    EXPECT_NEAR(sum / 10.0, tune(rps, grid, level, {.folds = 10}).rows[0].mean_error_m, 1e-9);
}

TEST(MatchQuality, IsBoundedAndRefusesTooFewRps) {
    const auto q = held_out_errors(corridor(40), Setting{}, level, {.folds = 5, .max_queries = 12});
    EXPECT_EQ(q.queries, 12u);
    EXPECT_TRUE(q.subsampled);
    std::size_t assessed = 0;
    for (const auto& r : q.rps) assessed += r.error_m.has_value();
    EXPECT_EQ(assessed, 12u);
    EXPECT_THROW(held_out_errors(corridor(1), Setting{}, level), TuneRefused);
}

}  // namespace
}  // namespace match_quality_test
