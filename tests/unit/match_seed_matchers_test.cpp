// bsb, nn and bsbnn (docs/spec.md §4.3–§4.5; Traini 2017 eqs. 2.18–2.20) on a three-RP map worked by hand.
//   RP1 (0,0):  a -50, b -60, c -70      query: a -52, b -62   (|AP_on| = 2)
//   RP2 (10,0): a -55, b -65
//   RP3 (0,10): a -40, d -80
// BSB:  S1 = 2, S2 = 2, S3 = 1.
// NN:   S1 = √(2²+2²) + γ(3−2) = 2.828 + γ,  S2 = √(3²+3²) = 4.243,  S3 = √(12²) = 12.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string_view>

#include "locus/match/localize.hpp"
#include "match_fixture.hpp"

namespace match_seed_matchers_test {
namespace {

using namespace locus;
using namespace locus::match;
using namespace locus::match::testing;

Index three_rps() {
    return Index::build({rp(1, {0, 0}, {m("a", -50), m("b", -60), m("c", -70)}),
                         rp(2, {10, 0}, {m("a", -55), m("b", -65)}),
                         rp(3, {0, 10}, {m("a", -40), m("d", -80)})});
}

Query query(std::vector<std::pair<std::string, double>> aps) {
    std::vector<Reading> r;
    for (auto& [b, rss] : aps) r.push_back(Reading{"wifi", b, rss});
    return Query::from_means(r);
}

const Query kQuery = query({{"a", -52}, {"b", -62}});

TEST(Bsb, ReportsEveryTiedRpAndAnswersTheirCentroid) {
    const auto r = localize(three_rps(), kQuery, Algorithm::bsb);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1, 2}));
    EXPECT_DOUBLE_EQ(r->at.x, 5.0);
    EXPECT_DOUBLE_EQ(r->at.y, 0.0);
    EXPECT_DOUBLE_EQ(r->score, 2.0);
    EXPECT_EQ(r->matched_aps, 2);
    EXPECT_EQ(r->algorithm, "bsb");
    ASSERT_EQ(r->candidates.size(), 3u);
    EXPECT_EQ(r->candidates[2].rp_id, 3);
    EXPECT_DOUBLE_EQ(r->candidates[2].score, 1.0);
}

TEST(Bsb, ToleranceWidensTheSetByAFractionOfTheBest) {
    Options o;
    o.tolerance = 0.5;  // |S − 2| ≤ 1 keeps RP3 too
    const auto r = localize(three_rps(), kQuery, Algorithm::bsb, o);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1, 2, 3}));
    EXPECT_DOUBLE_EQ(r->at.x, 10.0 / 3.0);
    EXPECT_DOUBLE_EQ(r->at.y, 10.0 / 3.0);
}

TEST(Nn, PenaltyForExtraStoredApsDecides) {
    const auto r = localize(three_rps(), kQuery, Algorithm::nn);  // γ = 5 by default
    ASSERT_TRUE(r);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{2}));
    EXPECT_DOUBLE_EQ(r->at.x, 10.0);
    EXPECT_NEAR(r->score, std::sqrt(18.0), 1e-12);
    ASSERT_EQ(r->candidates.size(), 3u);
    EXPECT_EQ(r->candidates[1].rp_id, 1);
    EXPECT_NEAR(r->candidates[1].score, std::sqrt(8.0) + 5.0, 1e-12);
    EXPECT_NEAR(r->candidates[2].score, 12.0, 1e-12);

    Options no_penalty;
    no_penalty.gamma = 0.0;
    const auto r0 = localize(three_rps(), kQuery, Algorithm::nn, no_penalty);
    ASSERT_TRUE(r0);
    EXPECT_EQ(r0->rp_ids, (std::vector<long long>{1}));
    EXPECT_NEAR(r0->score, std::sqrt(8.0), 1e-12);
}

TEST(Nn, ToleranceIsRelativeToTheBestDistance) {
    Options o;
    o.tolerance = 0.8;  // 4.243 · 1.8 = 7.637 < 7.828: RP1 still out
    EXPECT_EQ(localize(three_rps(), kQuery, Algorithm::nn, o)->rp_ids, (std::vector<long long>{2}));
    o.tolerance = 0.9;  // 4.243 · 1.9 = 8.061 ≥ 7.828: RP1 in
    const auto r = localize(three_rps(), kQuery, Algorithm::nn, o);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{2, 1}));
    EXPECT_DOUBLE_EQ(r->at.x, 5.0);
}

TEST(BsbNn, BreaksTheBsbTieWithNn) {
    const auto r = localize(three_rps(), kQuery, Algorithm::bsbnn);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{2}));
    EXPECT_NEAR(r->score, std::sqrt(18.0), 1e-12);
    EXPECT_EQ(r->matched_aps, 2);
    Options no_penalty;
    no_penalty.gamma = 0.0;
    EXPECT_EQ(localize(three_rps(), kQuery, Algorithm::bsbnn, no_penalty)->rp_ids, (std::vector<long long>{1}));
}

TEST(BsbNn, NeverPrefersAnRpWithFewerCommonApsEvenIfCloserInSignal) {
    // RP3 shares only "a" but matches it exactly; BSB ranks it below the two-AP RPs.
    const Query q = query({{"a", -40}, {"b", -62}});
    Options o;
    o.gamma = 0.0;
    const auto r = localize(three_rps(), q, Algorithm::bsbnn, o);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1}));  // √(10²+2²) < √(15²+3²)
    // Plain NN with γ = 0 takes RP3: S3 = 0 < S1 = √(10²+2²).
    EXPECT_EQ(localize(three_rps(), q, Algorithm::nn, o)->rp_ids, (std::vector<long long>{3}));
}

TEST(BsbNn, ToleranceAppliesToNnAmongTheBsbWinners) {
    Options o;
    o.tolerance = 1.0;  // S1 = 7.828 ≤ 2 · 4.243; RP3 (BSB 1) stays out however wide
    const auto r = localize(three_rps(), kQuery, Algorithm::bsbnn, o);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{2, 1}));
}

TEST(Subarea, OnlyRpsNearThePriorAreCandidates) {
    Options o;
    o.near = Near{{0, 0}, 5.0};  // RP1 only (RP2 and RP3 are 10 m away)
    const auto r = localize(three_rps(), kQuery, Algorithm::nn, o);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1}));
    ASSERT_EQ(r->candidates.size(), 1u);
    o.near = Near{{0, 0}, 10.0};  // the radius is inclusive: all three
    EXPECT_EQ(localize(three_rps(), kQuery, Algorithm::nn, o)->candidates.size(), 3u);
    o.near = Near{{100, 100}, 5.0};
    EXPECT_FALSE(localize(three_rps(), kQuery, Algorithm::nn, o));
}

TEST(NoCommonAp, NoAnswerRatherThanAMadeUpPosition) {
    const Query q = query({{"zz", -50}});
    for (auto a : all_algorithms()) EXPECT_FALSE(localize(three_rps(), q, a)) << to_string(a);
    EXPECT_FALSE(localize(three_rps(), Query{}, Algorithm::bsb));
    EXPECT_FALSE(localize(Index::build({}), kQuery, Algorithm::nn));
}

TEST(NoCommonAp, ApsUnknownToTheMapStillCountInTheOnlineSetSize) {
    // |AP_on| = 4 now, so RP1's 3 stored APs draw no penalty: S1 = √8 < S2 = √18.
    const Query q = query({{"a", -52}, {"b", -62}, {"x", -70}, {"y", -75}});
    const auto r = localize(three_rps(), q, Algorithm::nn);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1}));
    EXPECT_EQ(r->matched_aps, 2);
}

TEST(Query, AveragesScansPerApAndNormalisesBssids) {
    const std::vector<Scan> scans{{{"wifi", "AA-BB-CC-DD-EE-FF", -50}, {"wifi", "x", -70}},
                                  {{"wifi", "aa:bb:cc:dd:ee:ff", -54}, {"wifi", "x", 100}},
                                  {{"ble", "x", -80}}};
    const Query q = Query::from_scans(scans);
    ASSERT_EQ(q.aps.size(), 3u);
    EXPECT_EQ(q.aps[0].bssid, "aa:bb:cc:dd:ee:ff");
    EXPECT_DOUBLE_EQ(q.aps[0].rss, -52.0);
    EXPECT_EQ(q.aps[1].bssid, "x");
    EXPECT_DOUBLE_EQ(q.aps[1].rss, -70.0);  // +100 is "not detected", not a sample
    EXPECT_EQ(q.aps[2].type, "ble");        // same id, other radio: another AP
}

TEST(Query, InterleavedRepeatsKeepFirstSeenOrder) {
    const Query q = Query::from_means({{"wifi", "b", -60}, {"wifi", "a", -50}, {"wifi", "b", -70}, {"wifi", "c", -90},
                                       {"wifi", "a", -53}, {"wifi", "B", -80}});
    ASSERT_EQ(q.aps.size(), 3u);
    EXPECT_EQ(q.aps[0].bssid, "b");
    EXPECT_DOUBLE_EQ(q.aps[0].rss, -70.0);  // (-60 - 70 - 80) / 3
    EXPECT_EQ(q.aps[1].bssid, "a");
    EXPECT_DOUBLE_EQ(q.aps[1].rss, -51.5);
    EXPECT_EQ(q.aps[2].bssid, "c");
    EXPECT_DOUBLE_EQ(q.aps[2].rss, -90.0);
}

// One id on two radios, interleaved: two APs, each averaged over its own readings, and each
// carrying the hash of its bssid that the index lookup uses.
TEST(Query, OneIdOnTwoRadiosStaysTwoAps) {
    const Query q = Query::from_means({{"wifi", "x", -50}, {"ble", "x", -60}, {"wifi", "x", -70}, {"ble", "X", -80}});
    ASSERT_EQ(q.aps.size(), 2u);
    EXPECT_EQ(q.aps[0].type, "wifi");
    EXPECT_DOUBLE_EQ(q.aps[0].rss, -60.0);
    EXPECT_EQ(q.aps[1].type, "ble");
    EXPECT_DOUBLE_EQ(q.aps[1].rss, -70.0);
    for (const auto& ap : q.aps) EXPECT_EQ(ap.bssid_hash, std::hash<std::string_view>{}(ap.bssid));
}

// Many APs, each heard twice, in reverse name order: the sort that finds the repeats must not
// change the first-seen order. 81 readings sort on the stack, 401 on the heap.
TEST(Query, ManyReadingsAveragedInFirstSeenOrder) {
    for (const int n : {40, 200}) {
        std::vector<Reading> means;
        for (int round = 0; round < 2; ++round)
            for (int i = n - 1; i >= 0; --i)
                means.push_back({"wifi", "ap" + std::to_string(i), round == 0 ? -50.0 : -61.0});
        means.push_back({"ble", "ap7", -70});
        const Query q = Query::from_means(means);
        ASSERT_EQ(q.aps.size(), static_cast<std::size_t>(n) + 1) << n;
        for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
            EXPECT_EQ(q.aps[k].bssid, "ap" + std::to_string(n - 1 - static_cast<int>(k))) << n;
            EXPECT_DOUBLE_EQ(q.aps[k].rss, -55.5) << n;
        }
        EXPECT_EQ(q.aps[n].type, "ble") << n;
        EXPECT_DOUBLE_EQ(q.aps[n].rss, -70.0) << n;
    }
}

TEST(Names, ParseAndPrintRoundTrip) {
    for (auto a : all_algorithms()) EXPECT_EQ(parse_algorithm(to_string(a)), a);
    EXPECT_EQ(all_algorithms().size(), 6u);
    EXPECT_FALSE(parse_algorithm("BSB"));
    EXPECT_EQ(parse_distance("sorensen"), Distance::sorensen);
    EXPECT_EQ(parse_representation("powed"), Representation::powed);
    EXPECT_EQ(parse_bayes_estimate("map"), BayesEstimate::map);
    EXPECT_FALSE(parse_distance("cosine"));
}

}  // namespace
}  // namespace match_seed_matchers_test
