// match::Workspace: an answer depends on the index, the query and the options only, never on
// what the workspace served before, how it got there or which thread holds it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "locus/match/localize.hpp"
#include "locus/match/workspace.hpp"
#include "match_fixture.hpp"

namespace match_workspace_test {
namespace {

using namespace locus;
using namespace locus::match;
using namespace locus::match::testing;

// The AP at grid point (ax, ay) of a floor: "b0f1-24".
std::string ap_name(int building, int floor, int ax, int ay) {
    std::string name = "b0f0-00";
    name[1] = static_cast<char>('0' + building);
    name[3] = static_cast<char>('0' + floor);
    name[5] = static_cast<char>('0' + ax);
    name[6] = static_cast<char>('0' + ay);
    return name;
}

// Two buildings of two floors, a 6×6 grid of RPs on each floor and an AP at every other
// grid point, heard by the RPs within 12 m: 144 RPs, enough to outgrow the small map below.
Index big_map() {
    std::vector<IndexedRp> rps;
    long long id = 0;
    for (int building = 0; building < 2; ++building)
        for (int floor = 0; floor < 2; ++floor)
            for (int x = 0; x < 6; ++x)
                for (int y = 0; y < 6; ++y) {
                    std::vector<Measurement> ms;
                    for (int ax = 0; ax < 6; ax += 2)
                        for (int ay = 0; ay < 6; ay += 2) {
                            const double d = 4.0 * std::hypot(x - ax, y - ay);
                            if (d > 12.0) continue;
                            ms.push_back(m(ap_name(building, floor, ax, ay), -40.0 - 3.0 * d, 2.0 + d / 4.0, 8));
                        }
                    rps.push_back(rp(++id, {4.0 * x + 100.0 * building, 4.0 * y}, std::move(ms), floor, building));
                }
    return Index::build(rps);
}

Index small_map() {
    return Index::build({rp(1, {0, 0}, {m("b0f0-00", -45), m("b0f0-20", -60)}),
                         rp(2, {10, 0}, {m("b0f0-20", -50), m("b1f1-44", -70)}, 2)});
}

void hear(std::vector<Reading>& r, double x, double y, int building, int floor, double loss = 0.0) {
    for (int ax = 0; ax < 6; ax += 2)
        for (int ay = 0; ay < 6; ay += 2) {
            const double d = std::hypot(x - 4.0 * ax, y - 4.0 * ay);
            if (d <= 14.0) r.push_back(Reading{"wifi", ap_name(building, floor, ax, ay), -42.0 - 3.0 * d - loss});
        }
}

Query query_at(double x, double y, int building, int floor) {
    std::vector<Reading> r;
    hear(r, x, y, building, floor);
    return Query::from_means(r);
}

// Heard through the ceiling as well: candidates on two floors, so bayes' floor vote picks one.
Query between_floors(double x, double y, int building) {
    std::vector<Reading> r;
    hear(r, x, y, building, 0);
    hear(r, x, y, building, 1, 12.0);
    return Query::from_means(r);
}

std::vector<Query> queries() {
    return {query_at(3, 5, 0, 0),       query_at(17, 9, 0, 1), between_floors(6, 6, 0), query_at(10, 18, 1, 0),
            between_floors(14, 2, 1), query_at(1, 1, 1, 1),  query_at(8, 8, 0, 0)};
}

// Every matcher, and bayes with both floor votes, which use the most of the workspace.
std::vector<std::pair<Algorithm, Options>> configurations() {
    std::vector<std::pair<Algorithm, Options>> out;
    for (Algorithm a : all_algorithms()) out.emplace_back(a, Options{});
    Options floor_knn;
    floor_knn.floor_knn = 3;
    out.emplace_back(Algorithm::bayes, floor_knn);
    Options near;
    near.near = Near{{8, 8}, 9.0};
    out.emplace_back(Algorithm::wknn, near);
    return out;
}

using Answers = std::vector<std::optional<Result>>;

Answers answer_all(const Index& index, Workspace& workspace) {
    Answers out;
    for (const Query& q : queries())
        for (const auto& [algorithm, options] : configurations())
            out.push_back(match::localize(index, q, algorithm, options, workspace));
    return out;
}

// Each answer from a workspace of its own, which has served nothing before.
Answers fresh(const Index& index) {
    Answers out;
    for (const Query& q : queries())
        for (const auto& [algorithm, options] : configurations()) {
            Workspace workspace;
            out.push_back(match::localize(index, q, algorithm, options, workspace));
        }
    return out;
}

void expect_same(const Answers& got, const Answers& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        SCOPED_TRACE("answer " + std::to_string(i));
        ASSERT_EQ(got[i].has_value(), want[i].has_value());
        if (!got[i]) continue;
        const Result& g = *got[i];
        const Result& w = *want[i];
        EXPECT_EQ(g.algorithm, w.algorithm);
        EXPECT_EQ(g.at.x, w.at.x);
        EXPECT_EQ(g.at.y, w.at.y);
        EXPECT_EQ(g.floor_id, w.floor_id);
        EXPECT_EQ(g.building_id, w.building_id);
        EXPECT_EQ(g.rp_ids, w.rp_ids);
        EXPECT_EQ(g.score, w.score);
        EXPECT_EQ(g.matched_aps, w.matched_aps);
        ASSERT_EQ(g.candidates.size(), w.candidates.size());
        for (std::size_t j = 0; j < g.candidates.size(); ++j) {
            EXPECT_EQ(g.candidates[j].rp_id, w.candidates[j].rp_id);
            EXPECT_EQ(g.candidates[j].score, w.candidates[j].score);
            EXPECT_EQ(g.candidates[j].matched_aps, w.candidates[j].matched_aps);
        }
    }
}

// The fixture must make the comparisons below mean something: answers on several floors and
// in both buildings, and bayes' floor vote with more than one floor to choose from.
TEST(Workspace, FixtureAnswersOnEveryFloor) {
    const Answers big = fresh(big_map());
    std::vector<std::pair<long long, long long>> floors;
    for (const auto& r : big)  // only the `near` configuration leaves building 1 unanswered
        if (r) floors.emplace_back(r->building_id, r->floor_id);
    EXPECT_GE(floors.size(), big.size() - 3);
    for (long long b = 0; b < 2; ++b)
        for (long long f = 0; f < 2; ++f)
            EXPECT_NE(std::find(floors.begin(), floors.end(), std::pair{b, f}), floors.end()) << b << "/" << f;
    // The small map shares APs with building 0 floor 0 only: some queries find no match.
    const Answers small = fresh(small_map());
    EXPECT_TRUE(std::any_of(small.begin(), small.end(), [](const auto& r) { return r.has_value(); }));
    EXPECT_TRUE(std::any_of(small.begin(), small.end(), [](const auto& r) { return !r.has_value(); }));
}

TEST(Workspace, AnswersDoNotDependOnTheMapsServedBefore) {
    const Index big = big_map(), small = small_map();
    const Answers want_big = fresh(big), want_small = fresh(small);
    Workspace w;
    // Grown on the small map, then the big one; then the big map's leftovers under the small.
    expect_same(answer_all(small, w), want_small);
    expect_same(answer_all(big, w), want_big);
    expect_same(answer_all(small, w), want_small);
    expect_same(answer_all(big, w), want_big);
}

TEST(Workspace, AMovedFromWorkspaceServesAgain) {
    const Index big = big_map();
    const Answers want = fresh(big);
    Workspace a;
    expect_same(answer_all(big, a), want);
    Workspace b = std::move(a);
    expect_same(answer_all(big, b), want);
    expect_same(answer_all(big, a), want);  // NOLINT(bugprone-use-after-move): reuse is the point
    a = std::move(b);
    expect_same(answer_all(big, a), want);
}

// One workspace per thread is all concurrent queries on one index need.
TEST(Workspace, OnePerThreadOnOneIndex) {
    const Index big = big_map();
    const Answers want = fresh(big);
    std::vector<Answers> got(4);
    std::vector<std::thread> threads;
    for (auto& out : got)
        threads.emplace_back([&big, &out] {
            Workspace w;
            for (int round = 0; round < 20; ++round) out = answer_all(big, w);
        });
    for (auto& t : threads) t.join();
    for (const auto& out : got) expect_same(out, want);
}

}  // namespace
}  // namespace match_workspace_test
