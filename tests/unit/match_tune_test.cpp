// match::tune: the K-fold CV over a radio map's own RPs that chooses its settings.
#include <gtest/gtest.h>

#include <cmath>

#include "locus/match/tune.hpp"
#include "match_fixture.hpp"

namespace match_tune_test {
namespace {

using namespace locus;
using namespace locus::match;
using locus::match::testing::m;
using locus::match::testing::rp;

std::string ap(int i) { return "aa:00:00:00:00:0" + std::to_string(i); }

// RPs every 2 m along a corridor; each AP's mean falls off with distance from its spot, so
// the nearest RP in signal space is the nearest in space.
std::vector<IndexedRp> corridor(int n, long long floor = 1) {
    std::vector<IndexedRp> rps;
    for (int i = 0; i < n; ++i) {
        const double x = 2.0 * i;
        std::vector<Measurement> ms;
        for (int a = 0; a < 4; ++a) ms.push_back(m(ap(a), -30.0 - 1.5 * std::abs(x - 10.0 * a)));
        rps.push_back(rp(100 + i, {x, 0.0}, ms, floor));
    }
    return rps;
}

TuneCandidate knn(int k) {
    TuneCandidate c{"knn k=" + std::to_string(k), {}};
    c.setting.algorithm = Algorithm::knn;
    c.setting.options.k = k;
    return c;
}

long long level(long long floor) { return floor; }

TEST(MatchTune, PicksTheSettingWithTheLowestCvErrorWhateverItsPlaceInTheGrid) {
    const auto rps = corridor(15);
    // Held out, an RP's nearest neighbours are 2 m away on either side: one of them is right
    // to 2 m, the mean of eight spreads over ±8 m.
    const std::vector<TuneCandidate> near_first{knn(1), knn(8)}, far_first{knn(8), knn(1)};
    const auto a = tune(rps, near_first, level, {.folds = 15});
    const auto b = tune(rps, far_first, level, {.folds = 15});
    EXPECT_EQ(a.best, 0u);
    EXPECT_EQ(b.best, 1u);
    EXPECT_EQ(a.folds, 15u);  // leave-one-out
    EXPECT_EQ(a.queries, 15u);
    EXPECT_FALSE(a.subsampled);
    EXPECT_NEAR(a.rows[0].mean_error_m, 2.0, 1e-9);  // every held-out RP lands on a neighbour
    EXPECT_GT(a.rows[1].mean_error_m, a.rows[0].mean_error_m + 0.5);  // the ends pull the mean of eight inward
    EXPECT_DOUBLE_EQ(a.rows[0].mean_error_m, b.rows[1].mean_error_m);  // same folds, same figures
    EXPECT_DOUBLE_EQ(a.rows[0].floor_hit_rate, 1.0);
}

TEST(MatchTune, CountsFloorErrorsAsEvaalDoes) {
    // Two floors with the same signals: knn k=1 answers the other floor's twin, 0 m away but
    // a floor wrong; 4 m per floor of difference (levels 0 and 2: 8 m).
    auto rps = corridor(4, 10);
    for (auto r : corridor(4, 12)) {
        r.rp.id += 50;
        rps.push_back(r);
    }
    const std::vector<TuneCandidate> grid{knn(1)};
    const auto report = tune(rps, grid, [](long long floor) { return floor - 10; }, {.folds = 8});
    EXPECT_DOUBLE_EQ(report.rows[0].floor_hit_rate, 0.0);
    EXPECT_NEAR(report.rows[0].mean_horizontal_m, 0.0, 1e-9);
    EXPECT_NEAR(report.rows[0].mean_error_m, 8.0, 1e-9);
}

TEST(MatchTune, IsBoundedAndDeterministic) {
    const auto rps = corridor(40);
    const auto grid = tune_grid();
    ASSERT_GE(grid.size(), 5u);
    EXPECT_EQ(grid[0].setting.algorithm, kDefaultAlgorithm);  // a tie keeps the built-in default
    const auto a = tune(rps, grid, level, {.folds = 5, .max_queries = 12});
    const auto b = tune(rps, grid, level, {.folds = 5, .max_queries = 12});
    EXPECT_EQ(a.queries, 12u);
    EXPECT_TRUE(a.subsampled);
    EXPECT_EQ(a.best, b.best);
    for (std::size_t i = 0; i < grid.size(); ++i) {
        EXPECT_DOUBLE_EQ(a.rows[i].mean_error_m, b.rows[i].mean_error_m);
        EXPECT_LE(a.rows[a.best].mean_error_m, a.rows[i].mean_error_m);
    }
}

TEST(MatchTune, RefusesFewerThanTwoRps) {
    const auto grid = tune_grid();
    EXPECT_THROW(tune({}, grid, level), TuneRefused);
    EXPECT_THROW(tune(corridor(1), grid, level), TuneRefused);
    EXPECT_THROW(tune(corridor(3), {}, level), TuneRefused);
    // Two RPs: each is localized against the other.
    const auto two = tune(corridor(2), grid, level);
    EXPECT_EQ(two.folds, 2u);
    EXPECT_NEAR(two.rows[two.best].mean_horizontal_m, 2.0, 1e-9);
}

TEST(MatchTune, HybridTiesWithItsBayesOnOneFloorSoTheEarlierCandidateStays) {
    // On one floor the knn vote has no other floor to name: the hybrid answers exactly as
    // bayes with the same bayes_k, and the tie keeps the earlier (plain) candidate.
    const auto grid = tune_grid();
    std::size_t hybrid = grid.size(), wide = grid.size();
    for (std::size_t i = 0; i < grid.size(); ++i) {
        const auto& s = grid[i].setting;
        if (s.algorithm != Algorithm::bayes || s.options.bayes_k != 20) continue;
        (s.options.floor_knn > 0 && !s.options.floor_knn_position ? hybrid : wide) = i;
    }
    ASSERT_LT(wide, hybrid);
    ASSERT_LT(hybrid, grid.size());
    const auto report = tune(corridor(40), grid, level, {.folds = 5, .max_queries = 40});
    EXPECT_DOUBLE_EQ(report.rows[hybrid].mean_error_m, report.rows[wide].mean_error_m);
    EXPECT_NE(report.best, hybrid);
}

TEST(MatchTune, SpatialBlocksTakeAHeldOutRpsNeighboursOutWithIt) {
    // Cells of 6 m hold 3 RPs each (x 0-4, 6-10, …, 24-28), one cell per fold: an RP in a
    // cell's middle finds its nearest remaining RP 4 m away, one at a cell's edge 2 m away,
    // the corridor's two end RPs 6 m away: (6 + 4 + 2) · 2 + (2 + 4 + 2) · 3 over 15 RPs.
    const auto rps = corridor(15);
    const std::vector<TuneCandidate> grid{knn(1)};
    const auto blocked = tune(rps, grid, level, {.folds = 5, .blocks = parse_fold_scheme("spatial:6")});
    EXPECT_EQ(blocked.queries, 15u);
    EXPECT_NEAR(blocked.rows[0].mean_error_m, 48.0 / 15.0, 1e-9);
    // Left out alone, every RP keeps a neighbour 2 m away.
    EXPECT_NEAR(tune(rps, grid, level, {.folds = 15}).rows[0].mean_error_m, 2.0, 1e-9);
}

TEST(MatchTune, BlocksThatLeaveOneFoldFallBackToTheShuffle) {
    const auto rps = corridor(20);
    const auto grid = tune_grid();
    const auto shuffled = tune(rps, grid, level, {.folds = 5});
    const auto one_cell = tune(rps, grid, level, {.folds = 5, .blocks = parse_fold_scheme("spatial:1000")});
    EXPECT_EQ(one_cell.queries, shuffled.queries);
    for (std::size_t i = 0; i < grid.size(); ++i)
        EXPECT_DOUBLE_EQ(one_cell.rows[i].mean_error_m, shuffled.rows[i].mean_error_m) << grid[i].name;
}

}  // namespace
}  // namespace match_tune_test
