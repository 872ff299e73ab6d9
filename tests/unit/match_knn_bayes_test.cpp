// knn, wknn and bayes, and building/floor detection, on maps small enough to work by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "locus/match/localize.hpp"
#include "match_fixture.hpp"

namespace match_knn_bayes_test {
namespace {

using namespace locus;
using namespace locus::match;
using namespace locus::match::testing;

Query query(std::vector<std::pair<std::string, double>> aps) {
    std::vector<Reading> r;
    for (auto& [b, rss] : aps) r.push_back(Reading{"wifi", b, rss});
    return Query::from_means(r);
}

// Positive representation with the missing value -100: rep = RSS + 100.
//   RP1 (0,0):  a 50, b 40, c 30    query: a 48, b 38
//   RP2 (10,0): a 45, b 35
//   RP3 (0,10): a 60, d 20
// Euclidean² over the union (absent = 0): 908, 18, 1988.  Manhattan: 34, 6, 70.
// Sørensen = Manhattan / (Σ RP + Σ query = 86): 34/206, 6/166, 70/166.
Index three_rps() {
    return Index::build({rp(1, {0, 0}, {m("a", -50), m("b", -60), m("c", -70)}),
                         rp(2, {10, 0}, {m("a", -55), m("b", -65)}),
                         rp(3, {0, 10}, {m("a", -40), m("d", -80)})});
}
const Query kQuery = query({{"a", -52}, {"b", -62}});

Options knn_options(int k, Distance d = Distance::euclidean) {
    Options o;
    o.k = k;
    o.distance = d;
    o.representation = Representation::positive;
    return o;
}

TEST(Knn, DistancesOverTheUnionOfAps) {
    const auto r = localize(three_rps(), kQuery, Algorithm::knn, knn_options(1));
    ASSERT_TRUE(r);
    ASSERT_EQ(r->candidates.size(), 3u);
    EXPECT_EQ(r->candidates[0].rp_id, 2);
    EXPECT_NEAR(r->candidates[0].score, std::sqrt(18.0), 1e-9);
    EXPECT_EQ(r->candidates[1].rp_id, 1);
    EXPECT_NEAR(r->candidates[1].score, std::sqrt(908.0), 1e-9);
    EXPECT_NEAR(r->candidates[2].score, std::sqrt(1988.0), 1e-9);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{2}));

    const auto man = localize(three_rps(), kQuery, Algorithm::knn, knn_options(1, Distance::manhattan));
    EXPECT_NEAR(man->candidates[0].score, 6.0, 1e-9);
    EXPECT_NEAR(man->candidates[1].score, 34.0, 1e-9);
    EXPECT_NEAR(man->candidates[2].score, 70.0, 1e-9);

    const auto sor = localize(three_rps(), kQuery, Algorithm::knn, knn_options(1, Distance::sorensen));
    EXPECT_NEAR(sor->candidates[0].score, 6.0 / 166.0, 1e-12);
    EXPECT_NEAR(sor->candidates[1].score, 34.0 / 206.0, 1e-12);
    EXPECT_NEAR(sor->candidates[2].score, 70.0 / 166.0, 1e-12);
}

TEST(Knn, AnApHeardOnlyOnlineCountsAgainstEveryRp) {
    // x at -70 (rep 30) is unknown to the map: every Euclidean² grows by 900.
    const auto r = localize(three_rps(), query({{"a", -52}, {"b", -62}, {"x", -70}}), Algorithm::knn, knn_options(1));
    EXPECT_NEAR(r->candidates[0].score, std::sqrt(918.0), 1e-9);
    EXPECT_NEAR(r->candidates[1].score, std::sqrt(1808.0), 1e-9);
}

TEST(Knn, PlainCentroidOfTheKNearest) {
    const auto r = localize(three_rps(), kQuery, Algorithm::knn, knn_options(2));
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{2, 1}));
    EXPECT_DOUBLE_EQ(r->at.x, 5.0);
    EXPECT_DOUBLE_EQ(r->at.y, 0.0);
    const auto all = localize(three_rps(), kQuery, Algorithm::knn, knn_options(10));  // k beyond the map: all
    EXPECT_NEAR(all->at.x, 10.0 / 3.0, 1e-12);
}

TEST(Wknn, InverseDistanceWeights) {
    const auto r = localize(three_rps(), kQuery, Algorithm::wknn, knn_options(2));
    const double w2 = 1.0 / std::sqrt(18.0), w1 = 1.0 / std::sqrt(908.0);
    EXPECT_NEAR(r->at.x, 10.0 * w2 / (w1 + w2), 1e-9);
    EXPECT_NEAR(r->at.y, 0.0, 1e-12);
    EXPECT_EQ(r->algorithm, "wknn");
}

TEST(Knn, EqualDistancesRankByIndexOrder) {
    const Index idx = Index::build({rp(7, {0, 0}, {m("a", -50)}), rp(5, {4, 0}, {m("a", -50)}), rp(6, {8, 0}, {m("a", -50)})});
    const auto r = localize(idx, query({{"a", -50}}), Algorithm::knn, knn_options(2));
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{7, 5}));
    EXPECT_DOUBLE_EQ(r->at.x, 2.0);
    // bsb/nn report the whole tie, not an arbitrary k.
    EXPECT_EQ(localize(idx, query({{"a", -50}}), Algorithm::nn)->rp_ids, (std::vector<long long>{7, 5, 6}));
}

TEST(Representation, FormsMapMissingToZero) {
    IndexParams params;
    params.missing_rss = -100.0;
    params.exponential_alpha = 24.0;
    params.powed_beta = std::numbers::e;
    const Index idx = Index::build({}, params);
    EXPECT_DOUBLE_EQ(idx.represent(-100, 0), 0.0);
    EXPECT_DOUBLE_EQ(idx.represent(-110, 0), 0.0);
    EXPECT_DOUBLE_EQ(idx.represent(-60, 0), 40.0);
    EXPECT_DOUBLE_EQ(idx.represent(-100, 1), 0.0);
    EXPECT_NEAR(idx.represent(-60, 1), (std::exp(40.0 / 24.0) - 1.0) / std::exp(100.0 / 24.0), 1e-12);
    EXPECT_DOUBLE_EQ(idx.represent(-100, 2), 0.0);
    EXPECT_NEAR(idx.represent(-50, 2), std::pow(0.5, std::numbers::e), 1e-12);
}

TEST(Knn, ExpectedRepresentationScalesByDetectionRate) {
    // "a" heard in 5 of 10 scans at -60: its expected positive rep is 0.5 · 40 = 20.
    const Index idx = Index::build({rp(1, {0, 0}, {m("a", -60, 1.0, 5)})});
    const auto r = localize(idx, query({{"a", -80}}), Algorithm::knn, knn_options(1));
    EXPECT_NEAR(r->score, 0.0, 1e-12);  // query rep 20 = 20
    IndexParams raw;
    raw.expected_representation = false;
    const auto r2 = localize(Index::build({rp(1, {0, 0}, {m("a", -60, 1.0, 5)})}, raw), query({{"a", -80}}), Algorithm::knn,
                             knn_options(1));
    EXPECT_NEAR(r2->score, 20.0, 1e-12);
}

// Bayes on two RPs (σ floor 1 dB so the stored variances are used as they are):
//   A (0,0):  a mean -50 var 4, heard 10/10 (rate clamped to 0.98)
//   B (10,0): a mean -60 var 4, heard 5/10;  b mean -70 var 9, heard 10/10 (0.98)
// Query a -52: ll_A = ln .98 − ½ln(2π·4) − 4/8,  ll_B = ln .5 − ½ln(2π·4) − 64/8 + ln(1 − .98).
IndexParams bayes_params() {
    IndexParams p;
    p.min_detection = 0.02;
    p.missing_rss = -100.0;
    return p;
}
Index two_rps() {
    return Index::build({rp(1, {0, 0}, {m("a", -50, 4.0, 10)}), rp(2, {10, 0}, {m("a", -60, 4.0, 5), m("b", -70, 9.0, 10)})},
                        bayes_params());
}
double ll_a(double var = 4.0) { return std::log(0.98) - 0.5 * std::log(2 * std::numbers::pi * var) - 4.0 / (2 * var); }
double ll_b(double var = 4.0) {
    return std::log(0.5) - 0.5 * std::log(2 * std::numbers::pi * var) - 64.0 / (2 * var) + std::log(0.02);
}
Options bayes(double sigma_floor, BayesEstimate e, int k = 2) {
    Options o;
    o.sigma_floor = sigma_floor;
    o.estimate = e;
    o.k = k;
    o.bayes_k = 0;  // k above
    o.temperature = 1.0;
    o.offset_sigma = 0.0;
    o.outlier_sigmas = 0.0;  // the plain Gaussian; the cap has its own test
    return o;
}

TEST(Bayes, GaussianLogLikelihoodWithDetectionRates) {
    const auto r = localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, bayes(1.0, BayesEstimate::map));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1}));
    EXPECT_NEAR(r->score, ll_a(), 1e-9);
    ASSERT_EQ(r->candidates.size(), 2u);
    EXPECT_NEAR(r->candidates[1].score, ll_b(), 1e-9);
    EXPECT_DOUBLE_EQ(r->at.x, 0.0);
}

TEST(Bayes, PosteriorMeanWeighsByLikelihood) {
    const auto r = localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, bayes(1.0, BayesEstimate::mean));
    const double wb = std::exp(ll_b() - ll_a());
    EXPECT_NEAR(r->at.x, 10.0 * wb / (1.0 + wb), 1e-12);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1, 2}));
    // Tempering flattens the posterior: T = 4 gives exp((ll_B − ll_A)/4).
    Options t = bayes(1.0, BayesEstimate::mean);
    t.temperature = 4.0;
    const double wt = std::exp((ll_b() - ll_a()) / 4.0);
    EXPECT_NEAR(localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, t)->at.x, 10.0 * wt / (1.0 + wt), 1e-12);
}

TEST(Bayes, VarianceFloor) {
    // σ floor 3 dB: both "a" variances become 9.
    const auto r = localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, bayes(3.0, BayesEstimate::map));
    EXPECT_NEAR(r->score, ll_a(9.0), 1e-9);
    EXPECT_NEAR(r->candidates[1].score, ll_b(9.0), 1e-9);
}

TEST(Bayes, ApHeardOnlyOnlineIsPenalisedAsIfStoredAtTheMissingValue) {
    // x at -70 is unknown: + ln(min_detection) + ln N(-70; -100, σf²) for every RP.
    const double pen = std::log(0.02) - 0.5 * std::log(2 * std::numbers::pi) - 900.0 / 2.0;
    const auto r = localize(two_rps(), query({{"a", -52}, {"x", -70}}), Algorithm::bayes, bayes(1.0, BayesEstimate::map));
    EXPECT_NEAR(r->score, ll_a() + pen, 1e-9);
}

TEST(Bayes, DeviceOffsetEstimate) {
    // For A: d = -2 dB, σ² = 4 → Σd/σ² = -0.5, Σ1/σ² = 0.25; prior σδ = 2 → gain ½·0.25/(0.25+0.25).
    Options o = bayes(1.0, BayesEstimate::map);
    o.offset_sigma = 2.0;
    const auto r = localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, o);
    EXPECT_NEAR(r->score, ll_a() + 0.25, 1e-9);
}

TEST(Bayes, OutlierCapBoundsEachApsResidual) {
    Options o = bayes(1.0, BayesEstimate::map);
    o.outlier_sigmas = 3.0;  // no AP costs more than 9/2 in its Gaussian exponent
    // a at -30: A is 20 dB off (z² = 400/4 = 100), B 30 dB (z² = 225); both count as 9.
    const double gauss_capped = -0.5 * std::log(2 * std::numbers::pi * 4.0) - 9.0 / 2.0;
    auto r = localize(two_rps(), query({{"a", -30}}), Algorithm::bayes, o);
    ASSERT_TRUE(r);
    EXPECT_NEAR(r->score, std::log(0.98) + gauss_capped, 1e-9);
    EXPECT_NEAR(r->candidates[1].score, std::log(0.5) + gauss_capped + std::log(0.02), 1e-9);
    // Uncapped, A would pay 400/8 = 50 instead of 4.5.
    Options plain = bayes(1.0, BayesEstimate::map);
    EXPECT_NEAR(localize(two_rps(), query({{"a", -30}}), Algorithm::bayes, plain)->score,
                std::log(0.98) - 0.5 * std::log(2 * std::numbers::pi * 4.0) - 50.0, 1e-9);
    // Under the cap nothing changes: a at -52 is 1σ from A.
    EXPECT_NEAR(localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, o)->score, ll_a(), 1e-9);
    // An AP the RP does not store is capped alike: x at -70 is 30σ from -100 (σ floor 1).
    const double pen = std::log(0.02) - 0.5 * std::log(2 * std::numbers::pi) - 9.0 / 2.0;
    EXPECT_NEAR(localize(two_rps(), query({{"a", -52}, {"x", -70}}), Algorithm::bayes, o)->score, ll_a() + pen, 1e-9);
    // A capped reading does not feed the offset estimate: σδ = 2 adds 0.25 at -52
    // (DeviceOffsetEstimate) and nothing at -30.
    o.offset_sigma = 2.0;
    EXPECT_NEAR(localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, o)->score, ll_a() + 0.25, 1e-9);
    EXPECT_NEAR(localize(two_rps(), query({{"a", -30}}), Algorithm::bayes, o)->score, std::log(0.98) + gauss_capped, 1e-9);
}

// A whole map: building 1 floor 10 holds RP1 (0,0) and RP2 (4,0); floor 20 holds RP3 (2,0).
Index whole_map() {
    return Index::build({rp(1, {0, 0}, {m("a", -50), m("b", -60)}, 10, 1), rp(2, {4, 0}, {m("a", -50), m("c", -60)}, 10, 1),
                         rp(3, {2, 0}, {m("a", -50), m("d", -60)}, 20, 1), rp(4, {2, 0}, {m("e", -50)}, 30, 2)});
}

TEST(FloorDetection, MajorityOfATiedSetAndOnlyItsRpsInTheCentroid) {
    const auto r = localize(whole_map(), query({{"a", -50}}), Algorithm::bsb);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->floor_id, 10);
    EXPECT_EQ(r->building_id, 1);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1, 2}));
    EXPECT_DOUBLE_EQ(r->at.x, 2.0);
    EXPECT_EQ(r->candidates.size(), 3u);  // RP3 is tied too, listed as a candidate
}

TEST(FloorDetection, KnnVotesAndTiesGoToTheBetterRankedFloor) {
    // d: RP3 matches a and d exactly; RP1 and RP2 each differ in two APs.
    const auto r = localize(whole_map(), query({{"a", -50}, {"d", -60}}), Algorithm::knn, knn_options(3));
    EXPECT_EQ(r->floor_id, 10);  // two of three neighbours
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1, 2}));
    const auto r2 = localize(whole_map(), query({{"a", -50}, {"d", -60}}), Algorithm::knn, knn_options(2));
    EXPECT_EQ(r2->floor_id, 20);  // one each: the nearest neighbour's floor
    EXPECT_EQ(r2->rp_ids, (std::vector<long long>{3}));
}

TEST(FloorDetection, BuildingFollowsTheMatch) {
    const auto r = localize(whole_map(), query({{"e", -52}}), Algorithm::bayes);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->building_id, 2);
    EXPECT_EQ(r->floor_id, 30);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{4}));
}

TEST(FloorDetection, BayesPicksTheFloorByPosteriorMass) {
    // RP3 alone is the MAP, but floor 10's two RPs together carry more posterior mass.
    const Index idx = Index::build({rp(1, {0, 0}, {m("a", -51, 4.0)}, 10), rp(2, {4, 0}, {m("a", -51, 4.0)}, 10),
                                    rp(3, {2, 0}, {m("a", -50, 4.0)}, 20)},
                                   bayes_params());
    Options o = bayes(1.0, BayesEstimate::map);
    o.floor_knn = 0;
    o.floor_aps = 0;
    const auto r = localize(idx, query({{"a", -50}}), Algorithm::bayes, o);
    // Per RP: ll = ln .98 − ½ln(8π) − d²/8, so floor 10 holds 2·e^(−1/8) > 1.
    EXPECT_EQ(r->floor_id, 10);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1, 2}));  // tied MAP within the floor
    EXPECT_EQ(r->candidates.front().rp_id, 3);
}

TEST(Bayes, ZeroVarianceAndZeroFloorStayFinite) {
    // One sample per AP gives variance 0; a zero floor must not divide by it.
    const Index idx = Index::build({rp(1, {0, 0}, {m("a", -50, 0.0, 1)}), rp(2, {6, 0}, {m("a", -60, 0.0, 1)})});
    Options o;
    o.sigma_floor = 0.0;
    o.outlier_sigmas = 0.0;  // with the cap both residuals (10σ, 90σ) would score alike
    const auto r = localize(idx, query({{"a", -51}}), Algorithm::bayes, o);
    ASSERT_TRUE(r);
    EXPECT_TRUE(std::isfinite(r->score));
    EXPECT_TRUE(std::isfinite(r->at.x));
    EXPECT_EQ(r->rp_ids.front(), 1);
}

TEST(Bayes, BayesKSizesThePosteriorMeanApartFromK) {
    Options o = bayes(1.0, BayesEstimate::mean, 2);
    o.bayes_k = 1;  // wins over k = 2
    const auto r = localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, o);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{1}));
    EXPECT_DOUBLE_EQ(r->at.x, 0.0);
    o.bayes_k = 0;  // falls back to k
    EXPECT_EQ(localize(two_rps(), query({{"a", -52}}), Algorithm::bayes, o)->rp_ids, (std::vector<long long>{1, 2}));
}

// Floor 10 holds RP1 (0,0), a at -50; floor 20 holds RP2 (10,0) and RP3 (20,0), a at -54.
// Query a -50 (variance 4, σ floor 1, T = 1): ll2 = ll3 = ll1 − 16/8, so the posterior shares
// are floor 10: 1/(1 + 2e⁻²) = 0.787, floor 20: 0.213. Manhattan over positive reps: RP1 at
// 0, RP2 and RP3 at 4, so the 3 nearest give floor 10 one third and floor 20 two thirds.
Index split_floors() {
    return Index::build({rp(1, {0, 0}, {m("a", -50, 4.0)}, 10), rp(2, {10, 0}, {m("a", -54, 4.0)}, 20),
                         rp(3, {20, 0}, {m("a", -54, 4.0)}, 20)},
                        bayes_params());
}
Options floor_vote(int floor_knn, double weight) {
    Options o = bayes(1.0, BayesEstimate::mean, 3);
    o.representation = Representation::positive;
    o.distance = Distance::manhattan;
    o.floor_knn = floor_knn;
    o.floor_knn_weight = weight;
    o.floor_aps = 0;
    return o;
}

TEST(FloorDetection, BayesFloorVoteMixesPosteriorAndKnnShares) {
    const Query q = query({{"a", -50}});
    const double p10 = 1.0 / (1.0 + 2.0 * std::exp(-2.0));
    // Floor 20 wins once (1 − w)(p10 − p20) < w/3, i.e. w > 0.633.
    const double w_star = (2 * p10 - 1) / (2 * p10 - 1 + 1.0 / 3.0);
    ASSERT_GT(w_star, 0.6);
    ASSERT_LT(w_star, 0.65);
    const auto posterior_only = localize(split_floors(), q, Algorithm::bayes, floor_vote(0, 0.7));
    EXPECT_EQ(posterior_only->floor_id, 10);
    EXPECT_EQ(posterior_only->rp_ids, (std::vector<long long>{1}));
    EXPECT_EQ(localize(split_floors(), q, Algorithm::bayes, floor_vote(3, 0.6))->floor_id, 10);
    const auto knn_heavy = localize(split_floors(), q, Algorithm::bayes, floor_vote(3, 0.7));
    EXPECT_EQ(knn_heavy->floor_id, 20);
    // The position comes from floor 20's RPs only, with equal posterior weights.
    EXPECT_EQ(knn_heavy->rp_ids, (std::vector<long long>{2, 3}));
    EXPECT_DOUBLE_EQ(knn_heavy->at.x, 15.0);
    EXPECT_EQ(knn_heavy->candidates.front().rp_id, 1);  // still the best candidate
    // The single nearest RP is on floor 10: its whole knn share goes there.
    EXPECT_EQ(localize(split_floors(), q, Algorithm::bayes, floor_vote(1, 0.9))->floor_id, 10);
}

TEST(FloorDetection, KnnVoteCanNameTheFloorWithoutMovingThePosition) {
    const Query q = query({{"a", -50}});
    Options o = floor_vote(3, 0.7);
    o.floor_knn_position = false;
    const auto label_only = localize(split_floors(), q, Algorithm::bayes, o);
    const auto posterior_only = localize(split_floors(), q, Algorithm::bayes, floor_vote(0, 0.7));
    ASSERT_TRUE(label_only && posterior_only);
    // The knn-heavy vote names floor 20 (as in the test above) ...
    EXPECT_EQ(label_only->floor_id, 20);
    // ... but the position, its RPs and the candidates stay floor 10's, as without the knn vote.
    EXPECT_EQ(label_only->rp_ids, posterior_only->rp_ids);
    EXPECT_EQ(label_only->rp_ids, (std::vector<long long>{1}));
    EXPECT_DOUBLE_EQ(label_only->at.x, posterior_only->at.x);
    EXPECT_EQ(label_only->candidates.front().rp_id, 1);
    // Where the knn vote agrees with the posterior nothing changes.
    o.floor_knn_weight = 0.6;
    EXPECT_EQ(localize(split_floors(), q, Algorithm::bayes, o)->floor_id, 10);
}

TEST(FloorDetection, FloorTemperatureFlattensOnlyTheFloorVote) {
    // Floor 20's mass 2e^(−2/Tf) passes floor 10's 1 when Tf > 2/ln 2 = 2.885.
    const Query q = query({{"a", -50}});
    Options o = floor_vote(0, 0.0);
    o.floor_temperature = 2.5;
    EXPECT_EQ(localize(split_floors(), q, Algorithm::bayes, o)->floor_id, 10);
    o.floor_temperature = 3.0;
    const auto r = localize(split_floors(), q, Algorithm::bayes, o);
    EXPECT_EQ(r->floor_id, 20);
    EXPECT_DOUBLE_EQ(r->at.x, 15.0);
    o.floor_temperature = 0.0;  // = temperature 1
    EXPECT_EQ(localize(split_floors(), q, Algorithm::bayes, o)->floor_id, 10);
}

// split_floors() plus RP4 (30,0) on floor 20 hearing a at -30: a is strongest there, so a's
// home floor is 20, but with ll4 = ll1 − 20²/8 RP4 carries no posterior weight. The shares
// stay floor 10: p10 = 1/(1 + 2e⁻² + e⁻⁵⁰) = 0.787, floor 20: 1 − p10. With the AP vote of
// weight w, floor 20 wins once (1 − w)(2·p10 − 1) < w, i.e. w > 0.365.
Index split_floors_with_loud_rp() {
    return Index::build({rp(1, {0, 0}, {m("a", -50, 4.0)}, 10), rp(2, {10, 0}, {m("a", -54, 4.0)}, 20),
                         rp(3, {20, 0}, {m("a", -54, 4.0)}, 20), rp(4, {30, 0}, {m("a", -30, 4.0)}, 20)},
                        bayes_params());
}
Options ap_vote(double weight) {
    Options o = floor_vote(0, 0.0);
    o.floor_aps = 1;
    o.floor_ap_weight = weight;
    return o;
}

TEST(Index, StrongestRpOfAnAp) {
    const Index idx = split_floors_with_loud_rp();
    EXPECT_EQ(idx.strongest_rp(static_cast<std::size_t>(idx.ap_of("wifi", "a"))), 3u);  // RP4, position 3
    EXPECT_EQ(split_floors().strongest_rp(0), 0u);  // RP1 at -50 beats -54; ties keep the first
}

TEST(FloorDetection, StrongestApsVoteForTheirHomeFloor) {
    const Query q = query({{"a", -50}});
    const double p10 = 1.0 / (1.0 + 2.0 * std::exp(-2.0) + std::exp(-50.0));
    const double w_star = (2 * p10 - 1) / (2 * p10);
    ASSERT_GT(w_star, 0.3);
    ASSERT_LT(w_star, 0.4);
    EXPECT_EQ(localize(split_floors_with_loud_rp(), q, Algorithm::bayes, ap_vote(0.0))->floor_id, 10);
    EXPECT_EQ(localize(split_floors_with_loud_rp(), q, Algorithm::bayes, ap_vote(0.3))->floor_id, 10);
    const auto r = localize(split_floors_with_loud_rp(), q, Algorithm::bayes, ap_vote(0.4));
    EXPECT_EQ(r->floor_id, 20);
    EXPECT_EQ(r->rp_ids, (std::vector<long long>{2, 3, 4}));
    EXPECT_NEAR(r->at.x, 15.0, 1e-9);  // RP4's weight e⁻⁴⁸ of the others'
    // A home RP outside `near` does not vote, so the floor vote never picks a floor without
    // candidates.
    Options o = ap_vote(0.4);
    o.near = Near{{0, 0}, 25.0};
    EXPECT_EQ(localize(split_floors_with_loud_rp(), q, Algorithm::bayes, o)->floor_id, 10);
}

// The same AP id on two radios is two APs: the index keys an AP by (type, bssid), though it
// hashes by the bssid alone.
TEST(Index, OneIdOnTwoRadiosIsTwoAps) {
    Measurement ble = m("x", -50);
    ble.type = "ble";
    const Index idx = Index::build({rp(1, {0, 0}, {m("x", -50)}), rp(2, {10, 0}, {ble})});
    ASSERT_EQ(idx.ap_count(), 2u);
    EXPECT_NE(idx.ap_of("wifi", "x"), idx.ap_of("ble", "x"));
    EXPECT_EQ(idx.ap_of("ble", "y"), -1);
    const auto heard_on_ble = localize(idx, Query::from_means({Reading{"ble", "x", -50}}), Algorithm::nn);
    ASSERT_TRUE(heard_on_ble);
    EXPECT_EQ(heard_on_ble->rp_ids, (std::vector<long long>{2}));
    EXPECT_EQ(localize(idx, Query::from_means({Reading{"wifi", "X", -50}}), Algorithm::nn)->rp_ids, (std::vector<long long>{1}));
}

// A radio map's index holds one floor, so every candidate is on it and bayes answers from its
// ranked list as it stands; with every floor option on, the answer is the one the whole map
// gives once the vote has picked that floor (StrongestApsVoteForTheirHomeFloor).
TEST(FloorDetection, OneFloorIndexAnswersAsTheWholeMapDoesForThatFloor) {
    const Index floor20 = Index::build({rp(2, {10, 0}, {m("a", -54, 4.0)}, 20), rp(3, {20, 0}, {m("a", -54, 4.0)}, 20),
                                        rp(4, {30, 0}, {m("a", -30, 4.0)}, 20)},
                                       bayes_params());
    const Query q = query({{"a", -50}});
    Options o = ap_vote(0.4);
    o.floor_knn = 3;
    o.floor_knn_weight = 0.3;
    const auto whole = localize(split_floors_with_loud_rp(), q, Algorithm::bayes, ap_vote(0.4));
    const auto one = localize(floor20, q, Algorithm::bayes, o);
    ASSERT_TRUE(whole && one);
    EXPECT_EQ(one->floor_id, 20);
    EXPECT_EQ(one->rp_ids, whole->rp_ids);
    EXPECT_NEAR(one->at.x, whole->at.x, 1e-9);
    ASSERT_EQ(one->candidates.size(), 3u);
    EXPECT_EQ(one->candidates[0].rp_id, 2);  // equal likelihoods rank by position
    EXPECT_EQ(one->candidates[1].rp_id, 3);
    EXPECT_EQ(one->candidates[2].rp_id, 4);
    // `near` leaves RP4 out of the candidates, and its AP vote with it.
    o.near = Near{{0, 0}, 25.0};
    const auto near = localize(floor20, q, Algorithm::bayes, o);
    ASSERT_TRUE(near);
    EXPECT_EQ(near->rp_ids, (std::vector<long long>{2, 3}));
    EXPECT_DOUBLE_EQ(near->at.x, 15.0);
    EXPECT_EQ(near->candidates.size(), 2u);
}

}  // namespace
}  // namespace match_knn_bayes_test
