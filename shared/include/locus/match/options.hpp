#pragma once
// Per-query knobs of the matchers (the "options" object of the localize API).
#include <optional>

#include "locus/geometry.hpp"
#include "locus/match/algorithm.hpp"

namespace locus::match {

// Dynamic subarea (docs/spec.md §4.2, Lu et al. 2016): only RPs within `radius` metres of `at` are candidates.
struct Near {
    Point at;
    double radius = 0.0;
};

struct Options {
    // knn/wknn: neighbours averaged (and bayes, when bayes_k is 0).
    int k = 3;
    // bayes with estimate=mean: top RPs of the chosen floor in the posterior mean; 0 = k.
    // 20 did slightly better than 3 on the tuning users (2, 4, …, 18) of UJIIndoorLoc
    // (3 is best for knn/wknn), but the API's `k` has always sized the posterior mean, so 0
    // by default.
    int bayes_k = 0;
    // bsb/nn/bsbnn/bayes(map): keep every RP whose score is within tolerance·|best| of the
    // best and answer their centroid (docs/spec.md §4.6). 0 = the plain best.
    double tolerance = 0.0;
    // nn/bsbnn: penalty per AP the RP stores beyond the size of the online scan, in dB.
    double gamma = 5.0;
    std::optional<Near> near;
    // Defaults: the combination that did best on the tuning users (2, 4, …, 18) of
    // UJIIndoorLoc (and in the literature); positive + euclidean is the textbook kNN.
    Representation representation = Representation::powed;
    Distance distance = Distance::sorensen;
    // bayes: the stored standard deviation is raised to at least this (dB). A few scans per
    // RP underestimate the spread another phone sees. 5 dB did best on the tuning users of
    // UJIIndoorLoc together with outlier_sigmas (8 dB without the cap). Values below 0.1 dB
    // are treated as 0.1.
    double sigma_floor = 5.0;
    // bayes: each AP's squared standardised residual (rss − mean)² / σ² is capped at
    // outlier_sigmas², for stored APs and for APs the RP does not store alike, and a capped
    // AP is left out of the device-offset estimate. Some phones report glitched readings
    // (0 dBm where every RP stores -80), and without a cap one of them decides the answer.
    // 0 = no cap. 5 did best on the tuning users of UJIIndoorLoc (docs/matchers.md).
    double outlier_sigmas = 5.0;
    BayesEstimate estimate = BayesEstimate::mean;
    // bayes: posterior ∝ exp(log-likelihood / temperature). Summing per-AP log-likelihoods
    // as if APs were independent makes the posterior far too sharp; T > 1 tempers it.
    double temperature = 3.0;
    // bayes: prior standard deviation (dB) of a per-query RSS offset between the phone and
    // the survey device, estimated per RP; 0 turns the estimate off.
    double offset_sigma = 4.0;
    // bayes: temperature of the posterior mass that votes for the floor; 0 = `temperature`.
    double floor_temperature = 0.0;
    // bayes: the floor vote also counts the `floor_knn` nearest RPs by the knn distance
    // (`representation`, `distance`), each floor scoring
    //   (1 − floor_knn_weight) · its posterior share + floor_knn_weight · its share of them.
    // 0 = posterior mass alone. Off by default: why, docs/matchers.md "Tuning notes moved from the code".
    int floor_knn = 0;
    double floor_knn_weight = 0.7;
    // bayes, with floor_knn > 0: false = the knn vote names only the answer's building and
    // floor; the position, rp_ids and candidates stay those of the floor the posterior mass
    // and the AP vote pick (as with floor_knn 0). On UJIIndoorLoc's tuning users the knn vote
    // gets the floor right more often but its floor's RPs give a worse position (docs/matchers.md).
    bool floor_knn_position = true;
    // bayes: the floor vote also counts the query's `floor_aps` strongest known APs, each
    // voting for the floor of the RP where it is strongest (Index::strongest_rp), with a
    // total share of floor_ap_weight. Access points sit on a floor, so this needs no
    // coverage near the query. 0 = off. 5 and 0.5 did best on the tuning users of
    // UJIIndoorLoc (docs/matchers.md).
    int floor_aps = 5;
    double floor_ap_weight = 0.5;
    // How many ranked candidates a Result lists.
    int candidates = 10;
    // The position is the weighted centroid of the chosen RPs on the voted floor, so a fix
    // never averages points on different floors. false: of every chosen RP, whatever its
    // floor, as the literature's kNN does (the yardstick of `locus eval`). Not an API option.
    bool position_on_voted_floor = true;
};

}  // namespace locus::match
