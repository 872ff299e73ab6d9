// match::assign_folds: which CV fold each surveyed scan goes to (`locus eval --cv-blocks`).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "locus/match/cv_folds.hpp"

namespace match_cv_folds_test {
namespace {

using namespace locus;
using namespace locus::match;

// A survey of one floor: positions on a 2 m grid walked row by row, each scanned `scans`
// times in a row, then a second floor; returns one site per scan in file order.
std::vector<FoldSite> survey(int scans = 3) {
    std::vector<FoldSite> out;
    for (long long floor : {0, 1})
        for (int iy = 0; iy < 10; ++iy)
            for (int ix = 0; ix < 15; ++ix)
                for (int s = 0; s < scans; ++s) out.push_back({1, floor, Point{2.0 * ix, 2.0 * iy}});
    return out;
}

using Key = std::tuple<long long, long long, double, double>;
Key key(const FoldSite& s) { return {s.building, s.floor, s.at.x, s.at.y}; }

// Every scan of a position in one fold; returns each position's fold.
std::map<Key, int> position_folds(const std::vector<FoldSite>& sites, const std::vector<int>& folds) {
    std::map<Key, int> out;
    for (std::size_t i = 0; i < sites.size(); ++i) {
        const auto [it, inserted] = out.try_emplace(key(sites[i]), folds[i]);
        EXPECT_EQ(it->second, folds[i]) << "a position split across folds at scan " << i;
    }
    return out;
}

TEST(CvFolds, PositionBlocksAreRoundRobinInFirstAppearanceOrder) {
    // Positions A B A C D B E (A and B revisited later): A B C D E are positions 0..4.
    const std::vector<FoldSite> sites{{1, 0, {0, 0}}, {1, 0, {1, 0}}, {1, 0, {0, 0}}, {1, 0, {2, 0}},
                                      {1, 1, {0, 0}}, {1, 0, {1, 0}}, {2, 0, {0, 0}}};
    const auto f = assign_folds(sites, 3, FoldScheme{});
    EXPECT_EQ(f, (std::vector<int>{0, 1, 0, 2, 0, 1, 1}));  // same point on another floor or building: another position
}

TEST(CvFolds, SpatialCellsStayWholeAndEveryPositionHasOneFold) {
    const auto sites = survey();
    const auto folds = assign_folds(sites, 5, *parse_fold_scheme("spatial:6"));
    ASSERT_EQ(folds.size(), sites.size());
    const auto per_position = position_folds(sites, folds);
    EXPECT_EQ(per_position.size(), 300u);
    std::map<std::tuple<long long, long long, long long>, int> cell_fold;
    std::vector<int> load(5, 0);
    for (const auto& [k, f] : per_position) {
        ASSERT_GE(f, 0);
        ASSERT_LT(f, 5);
        ++load[static_cast<std::size_t>(f)];
        const auto& [b, floor, x, y] = k;
        const std::tuple<long long, long long, long long> cell{floor, static_cast<long long>(std::floor(x / 6)),
                                                               static_cast<long long>(std::floor(y / 6))};
        const auto [it, inserted] = cell_fold.try_emplace(cell, f);
        EXPECT_EQ(it->second, f) << "cell split across folds";
    }
    // x 0..28 and y 0..18 on a 2 m grid: 5 by 4 cells of 6 m (the last row of cells one
    // position high), on 2 floors.
    EXPECT_EQ(cell_fold.size(), 40u);
    for (int l : load) {
        EXPECT_GT(l, 40);  // 300 positions, no fold starved
        EXPECT_LT(l, 80);
    }
    // A position's neighbours 2 m away on the same floor: with cells of 6 m most of them share
    // its fold, where position folds send every neighbour in a row elsewhere.
    const auto round_robin = position_folds(sites, assign_folds(sites, 5, FoldScheme{}));
    int same_cell_scheme = 0, same_round_robin = 0;
    for (const auto& [k, f] : per_position) {
        const auto& [b, floor, x, y] = k;
        const auto right = per_position.find({b, floor, x + 2.0, y});
        if (right == per_position.end()) continue;
        same_cell_scheme += right->second == f;
        same_round_robin += round_robin.at({b, floor, x + 2.0, y}) == round_robin.at(k);
    }
    EXPECT_GT(same_cell_scheme, 150);
    EXPECT_EQ(same_round_robin, 0);
}

TEST(CvFolds, OrderBlocksAreRunsOfConsecutivePositions) {
    const auto sites = survey(2);
    const auto folds = assign_folds(sites, 4, *parse_fold_scheme("order:25"));
    // Scan i is position i / 2, block i / 50: twelve blocks dealt 0 1 2 3 0 1 …
    for (std::size_t i = 0; i < sites.size(); ++i) EXPECT_EQ(folds[i], static_cast<int>((i / 50) % 4)) << i;
    position_folds(sites, folds);
}

TEST(CvFolds, DeterministicAndIndependentOfTheScansPerPosition) {
    const auto a = survey(1), b = survey(4);
    for (const char* scheme : {"position", "spatial:5", "spatial:2.5", "order:7"}) {
        const auto s = *parse_fold_scheme(scheme);
        const auto fa = assign_folds(a, 5, s);
        EXPECT_EQ(fa, assign_folds(a, 5, s)) << scheme;
        const auto fb = assign_folds(b, 5, s);
        for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(fa[i], fb[4 * i]) << scheme;
    }
}

TEST(CvFolds, FewerBlocksThanFoldsLeavesFoldsEmpty) {
    const auto sites = survey(1);
    // One cell per floor: two blocks, folds 0 and 1.
    const auto folds = assign_folds(sites, 5, *parse_fold_scheme("spatial:1000"));
    EXPECT_EQ(std::set<int>(folds.begin(), folds.end()), (std::set<int>{0, 1}));
    EXPECT_TRUE(assign_folds({}, 5, FoldScheme{}).empty());
}

TEST(CvFolds, ParsesSchemesAndRefusesBadOnes) {
    EXPECT_EQ(parse_fold_scheme("position")->blocks, FoldBlocks::position);
    const auto s = parse_fold_scheme("spatial:12.5");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->blocks, FoldBlocks::spatial);
    EXPECT_DOUBLE_EQ(s->cell_m, 12.5);
    EXPECT_EQ(to_string(*s), "spatial:12.5");
    const auto o = parse_fold_scheme("order:30");
    ASSERT_TRUE(o);
    EXPECT_EQ(o->run, 30u);
    EXPECT_EQ(to_string(*o), "order:30");
    for (const char* bad : {"", "spatial", "spatial:", "spatial:0", "spatial:-5", "spatial:nan", "spatial:inf",
                            "spatial:5m", "order:0", "order:-3", "order:2.5", "order:", "Order:3", "position:1"})
        EXPECT_FALSE(parse_fold_scheme(bad)) << bad;
    EXPECT_THROW(assign_folds(survey(1), 0, FoldScheme{}), std::invalid_argument);
    EXPECT_THROW(assign_folds(survey(1), 3, FoldScheme{FoldBlocks::spatial, 0.0, 1}), std::invalid_argument);
    EXPECT_THROW(assign_folds(survey(1), 3, FoldScheme{FoldBlocks::order, 0.0, 0}), std::invalid_argument);
}

TEST(CvFolds, SpatialTextRoundTripsAndTinyCellsAreRefused) {
    // Every accepted cell side prints as text that parses back to the same double.
    for (const char* text : {"spatial:20", "spatial:2.5", "spatial:0.01", "spatial:0.1", "spatial:0.30000000000000004",
                             "spatial:123456.789", "spatial:1e+300"}) {
        const auto s = parse_fold_scheme(text);
        ASSERT_TRUE(s) << text;
        const auto back = parse_fold_scheme(to_string(*s));
        ASSERT_TRUE(back) << to_string(*s);
        EXPECT_EQ(back->cell_m, s->cell_m) << text << " printed as " << to_string(*s);
    }
    EXPECT_EQ(to_string(*parse_fold_scheme("spatial:20")), "spatial:20");
    EXPECT_EQ(to_string(*parse_fold_scheme("spatial:0.01")), "spatial:0.01");
    // Below a centimetre the cell index of an ordinary coordinate heads for long long's limits.
    for (const char* tiny : {"spatial:1e-7", "spatial:0.0099", "spatial:1e-300", "spatial:4.9e-324"})
        EXPECT_FALSE(parse_fold_scheme(tiny)) << tiny;
    EXPECT_THROW(assign_folds(survey(1), 3, FoldScheme{FoldBlocks::spatial, 1e-300, 1}), std::invalid_argument);
    EXPECT_THROW(assign_folds(survey(1), 3, FoldScheme{FoldBlocks::spatial, kMinCellM / 2, 1}), std::invalid_argument);
}

TEST(CvFolds, CoordinatesBeyondACellIndexShareTheOutermostCell) {
    // x / 0.01 is far outside long long's range for these: each side's far-out positions are
    // one block (two blocks in all, one per side), and near ones keep their own cells.
    const std::vector<FoldSite> sites{{1, 0, {1e300, 0}}, {1, 0, {2e300, 0}}, {1, 0, {-1e300, 0}},
                                      {1, 0, {-3e300, 0}}, {1, 0, {0.005, 0}}, {1, 0, {0.015, 0}},
                                      {1, 0, {std::numeric_limits<double>::infinity(), 0}}};
    const auto folds = assign_folds(sites, 7, *parse_fold_scheme("spatial:0.01"));
    ASSERT_EQ(folds.size(), sites.size());
    EXPECT_EQ(folds[0], folds[1]);
    EXPECT_EQ(folds[0], folds[6]);
    EXPECT_EQ(folds[2], folds[3]);
    const std::set<int> distinct{folds[0], folds[2], folds[4], folds[5]};
    EXPECT_EQ(distinct.size(), 4u);  // blocks: +far, -far, cell 0, cell 1 on 7 folds
}

}  // namespace
}  // namespace match_cv_folds_test
