// `locus eval uji`: the localize pipeline in-process on UJIIndoorLoc, one JSON object of
// accuracy and speed per matcher (docs/spec.md §7.1).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/uji_csv.hpp"
#include "locus/match/localize.hpp"
#include "locus/metrics.hpp"

namespace {

using namespace locus;
namespace uji = locus::datasets::uji;
using metrics::percentile_interpolated;

struct Args {
    std::string train, test;
    std::optional<int> holdout_user, holdout_phone;
    std::vector<int> exclude_users;
    std::string algorithm = "all";
    std::optional<int> k, bayes_k, floor_knn, floor_aps;
    std::optional<double> floor_temperature, floor_knn_weight, floor_ap_weight;
    bool oracle = false;
    std::optional<double> covered_within;
    std::optional<double> outlier_sigmas;
    std::optional<double> offset_sigma, temperature, tolerance, gamma, sigma_floor, missing_rss, min_detection, alpha, beta;
    std::string representation, distance, estimate;
    bool json = false;
    std::optional<bool> expected;
    std::string per_query;
};

struct Truth {
    Point at;
    int building, floor;
};

double nearest_on_true_floor(const match::Index& index, const Truth& t);

nlohmann::json evaluate(const match::Index& index, const std::vector<match::Query>& queries,
                        const std::vector<Truth>& truth, match::Algorithm algorithm, const match::Options& options,
                        std::size_t& unanswered, std::FILE* per_query) {
    std::vector<std::optional<match::Result>> results(queries.size());
    match::Workspace workspace;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < queries.size(); ++i)
        results[i] = match::localize(index, queries[i], algorithm, options, workspace);
    const auto t1 = std::chrono::steady_clock::now();

    std::size_t building_hits = 0, floor_hits = 0;
    std::vector<double> errors;
    errors.reserve(queries.size());
    unanswered = 0;
    for (std::size_t i = 0; i < queries.size(); ++i) {
        // No common AP: no position. It counts as a building and floor miss and has no error.
        if (!results[i]) {
            ++unanswered;
            continue;
        }
        const auto& r = *results[i];
        const bool building_ok = r.building_id == truth[i].building;
        building_hits += building_ok;
        floor_hits += building_ok && r.floor_id == uji::floor_id(truth[i].building, truth[i].floor);
        errors.push_back(distance(r.at, truth[i].at));
        if (per_query &&
            std::fprintf(per_query, "%s,%zu,%d,%d,%.3f,%.3f,%lld,%lld,%.3f,%.3f,%.3f,%.3f\n",
                         std::string(match::to_string(algorithm)).c_str(), i, truth[i].building,
                         truth[i].floor, truth[i].at.x, truth[i].at.y, r.building_id, r.floor_id % 100, r.at.x, r.at.y,
                         errors.back(), nearest_on_true_floor(index, truth[i])) < 0)
            throw tools::CommandError("cannot write the --per-query file");
    }
    std::sort(errors.begin(), errors.end());
    const double n = static_cast<double>(queries.size());
    const double us = std::chrono::duration<double, std::micro>(t1 - t0).count();
    return nlohmann::json{
        {"algorithm", std::string(match::to_string(algorithm))},
        {"queries", queries.size()},
        {"building_hit_rate", static_cast<double>(building_hits) / n},
        {"floor_hit_rate", static_cast<double>(floor_hits) / n},
        {"mean_error_m", metrics::mean(errors)},
        {"median_error_m", percentile_interpolated(errors, 0.5)},
        {"p75_error_m", percentile_interpolated(errors, 0.75)},
        {"p95_error_m", percentile_interpolated(errors, 0.95)},
        {"us_per_query", us / n},
    };
}

// What no matcher answering an RP of the right floor can beat: the nearest RP of the map on
// the query's true building and floor. Held-out users who surveyed areas nobody else did
// are far from every remaining RP.
// Infinite when the true floor has no RP at all.
double nearest_on_true_floor(const match::Index& index, const Truth& t) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < index.size(); ++i) {
        const auto& rp = index.rp(i);
        if (rp.building_id == t.building && rp.floor_id == uji::floor_id(t.building, t.floor))
            best = std::min(best, distance(rp.at, t.at));
    }
    return best;
}

nlohmann::json oracle(const match::Index& index, const std::vector<Truth>& truth) {
    std::vector<double> errors;
    std::size_t no_floor = 0;
    for (const auto& t : truth) {
        const double best = nearest_on_true_floor(index, t);
        if (std::isfinite(best)) errors.push_back(best);
        else ++no_floor;
    }
    std::sort(errors.begin(), errors.end());
    const double n = static_cast<double>(truth.size());
    const double hits = static_cast<double>(errors.size()) / n;
    return nlohmann::json{
        {"algorithm", "oracle"},
        {"queries", truth.size()},
        {"building_hit_rate", hits},
        {"floor_hit_rate", hits},
        {"mean_error_m", metrics::mean(errors)},
        {"median_error_m", percentile_interpolated(errors, 0.5)},
        {"p75_error_m", percentile_interpolated(errors, 0.75)},
        {"p95_error_m", percentile_interpolated(errors, 0.95)},
        {"us_per_query", 0.0},
        {"floor_without_rps", no_floor},
    };
}

void run(const Args& a) {
    using tools::CommandError;
    const int split_modes = !a.test.empty() + a.holdout_user.has_value() + a.holdout_phone.has_value();
    if (split_modes != 1) throw CommandError("give exactly one of --test, --holdout-user, --holdout-phone");

    std::vector<match::Algorithm> algorithms;
    if (a.algorithm == "all") {
        auto all = match::all_algorithms();
        algorithms.assign(all.begin(), all.end());
    } else if (auto alg = match::parse_algorithm(a.algorithm)) {
        algorithms.push_back(*alg);
    } else {
        throw CommandError("unknown algorithm '" + a.algorithm + "' (bsb, nn, bsbnn, knn, wknn, bayes or all)");
    }

    match::Options options;
    if (a.k) options.k = *a.k;
    if (a.bayes_k) options.bayes_k = *a.bayes_k;
    if (a.tolerance) options.tolerance = *a.tolerance;
    if (a.gamma) options.gamma = *a.gamma;
    if (a.offset_sigma) options.offset_sigma = *a.offset_sigma;
    if (a.temperature) options.temperature = *a.temperature;
    if (a.sigma_floor) options.sigma_floor = *a.sigma_floor;
    if (a.outlier_sigmas) options.outlier_sigmas = *a.outlier_sigmas;
    if (a.floor_temperature) options.floor_temperature = *a.floor_temperature;
    if (a.floor_knn) options.floor_knn = *a.floor_knn;
    if (a.floor_knn_weight) options.floor_knn_weight = *a.floor_knn_weight;
    if (a.floor_aps) options.floor_aps = *a.floor_aps;
    if (a.floor_ap_weight) options.floor_ap_weight = *a.floor_ap_weight;
    if (!a.representation.empty()) {
        auto r = match::parse_representation(a.representation);
        if (!r) throw CommandError("unknown representation '" + a.representation + "' (positive, exponential, powed)");
        options.representation = *r;
    }
    if (!a.distance.empty()) {
        auto d = match::parse_distance(a.distance);
        if (!d) throw CommandError("unknown distance '" + a.distance + "' (euclidean, manhattan, sorensen)");
        options.distance = *d;
    }
    if (!a.estimate.empty()) {
        auto e = match::parse_bayes_estimate(a.estimate);
        if (!e) throw CommandError("unknown estimate '" + a.estimate + "' (map, mean)");
        options.estimate = *e;
    }
    match::IndexParams params;
    if (a.missing_rss) params.missing_rss = *a.missing_rss;
    if (a.min_detection) params.min_detection = *a.min_detection;
    if (a.alpha) params.exponential_alpha = *a.alpha;
    if (a.beta) params.powed_beta = *a.beta;
    if (a.expected) params.expected_representation = *a.expected;

    const uji::Data train = uji::read_file(a.train);
    uji::Data test_file;
    if (!a.test.empty()) {
        test_file = uji::read_file(a.test);
        if (test_file.waps != train.waps) throw CommandError("--test has different WAP columns from --train");
    }
    const uji::Data& test = a.test.empty() ? train : test_file;

    std::vector<std::size_t> train_rows, test_rows;
    for (std::size_t i = 0; i < train.rows.size(); ++i) {
        const auto& row = train.rows[i];
        // Lets a held-out phone be queried without the rows of a user who was also tuning data.
        if (std::find(a.exclude_users.begin(), a.exclude_users.end(), row.user_id) != a.exclude_users.end()) continue;
        const bool held = (a.holdout_user && row.user_id == *a.holdout_user) ||
                          (a.holdout_phone && row.phone_id == *a.holdout_phone);
        (held ? test_rows : train_rows).push_back(i);
    }
    if (!a.test.empty()) {
        test_rows.clear();
        for (std::size_t i = 0; i < test.rows.size(); ++i) test_rows.push_back(i);
    }
    if (train_rows.empty()) throw CommandError("no training rows left");

    const std::vector<match::IndexedRp> rps = uji::indexed_rps(train, train_rows);
    const match::Index index = match::Index::build(rps, params);

    // A scan with no valid reading is not a query (the API rejects it with 422).
    std::vector<match::Query> queries;
    std::vector<Truth> truth;
    std::size_t empty = 0;
    for (auto i : test_rows) {
        const auto& row = test.rows[i];
        if (row.heard.empty()) {
            ++empty;
            continue;
        }
        queries.push_back(match::Query::from_scans({uji::scan_of(test, row)}));
        truth.push_back(Truth{Point{row.longitude, row.latitude}, row.building, row.floor});
    }
    if (a.covered_within) {
        // Only the queries the map covers: separates matching errors from coverage gaps.
        std::size_t kept = 0;
        for (std::size_t i = 0; i < queries.size(); ++i) {
            if (nearest_on_true_floor(index, truth[i]) > *a.covered_within) continue;
            if (kept != i) {  // a self-move would empty the query
                queries[kept] = std::move(queries[i]);
                truth[kept] = truth[i];
            }
            ++kept;
        }
        std::cerr << "eval uji: " << kept << " of " << queries.size() << " queries within " << *a.covered_within
                  << " m of an RP on their floor\n";
        queries.resize(kept);
        truth.resize(kept);
    }
    if (queries.empty()) throw CommandError(a.covered_within ? "no query left within --covered-within" : "no test rows with a detected WAP");
    std::cerr << "eval uji: " << index.size() << " RPs, " << index.ap_count() << " APs, " << queries.size()
              << " queries (" << empty << " rows without any detected WAP skipped)\n";

    nlohmann::json out = nlohmann::json::array();
    if (a.oracle) out.push_back(oracle(index, truth));
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> per_query(nullptr, std::fclose);
    if (!a.per_query.empty()) {
        per_query.reset(std::fopen(a.per_query.c_str(), "w"));
        if (!per_query) throw CommandError("cannot write " + a.per_query);
        if (std::fputs("algorithm,query,building,floor,x,y,est_building,est_floor,est_x,est_y,error_m,oracle_m\n",
                       per_query.get()) < 0)
            throw CommandError("cannot write " + a.per_query);
    }
    for (auto alg : algorithms) {
        std::size_t unanswered = 0;
        auto o = evaluate(index, queries, truth, alg, options, unanswered, per_query.get());
        if (unanswered > 0)
            std::cerr << "eval uji: " << match::to_string(alg) << ": " << unanswered
                      << " queries shared no AP with any RP (counted as misses, no error)\n";
        out.push_back(std::move(o));
    }
    // A full disk often shows only when the buffer is flushed, so the close is checked too.
    if (per_query && std::fclose(per_query.release()) != 0) throw CommandError("cannot write " + a.per_query);
    if (a.json) {
        std::cout << (out.size() > 1 ? out : out.front()).dump() << "\n";
        return;
    }
    std::printf("%-6s %7s %9s %9s %8s %8s %8s %8s %9s\n", "algo", "queries", "building", "floor", "mean_m",
                "median_m", "p75_m", "p95_m", "us/query");
    for (const auto& o : out)
        std::printf("%-6s %7d %8.2f%% %8.2f%% %8.2f %8.2f %8.2f %8.2f %9.1f\n",
                    o["algorithm"].get<std::string>().c_str(), o["queries"].get<int>(),
                    100.0 * o["building_hit_rate"].get<double>(), 100.0 * o["floor_hit_rate"].get<double>(),
                    o["mean_error_m"].get<double>(), o["median_error_m"].get<double>(), o["p75_error_m"].get<double>(),
                    o["p95_error_m"].get<double>(), o["us_per_query"].get<double>());
}

}  // namespace

LOCUS_COMMAND("eval uji", [](CLI::App& app) {
    auto& eval = locus::tools::group(app, "eval", "Measure the matchers on real data sets");
    auto* cmd = eval.add_subcommand("uji", "Localize UJIIndoorLoc scans in-process and report accuracy and speed");
    auto a = std::make_shared<Args>();
    cmd->add_option("--train", a->train, "UJIIndoorLoc training CSV (the radio map)")->required()->check(CLI::ExistingFile);
    cmd->add_option("--test", a->test, "CSV of online scans (e.g. the validation file)")->check(CLI::ExistingFile);
    cmd->add_option("--holdout-user", a->holdout_user, "query with this USERID's training rows, map the rest");
    cmd->add_option("--holdout-phone", a->holdout_phone, "query with this PHONEID's training rows, map the rest");
    cmd->add_option("--exclude-user", a->exclude_users,
                    "drop this USERID's training rows from both map and queries (repeatable)");
    cmd->add_option("--algorithm", a->algorithm, "bsb, nn, bsbnn, knn, wknn, bayes or all")->capture_default_str();
    cmd->add_option("--k", a->k, "neighbours for knn/wknn (and bayes when --bayes-k is 0)");
    cmd->add_option("--bayes-k", a->bayes_k, "bayes: RPs in the posterior mean (0 = --k)");
    cmd->add_option("--tolerance", a->tolerance, "keep RPs within tolerance*|best| of the best score");
    cmd->add_option("--gamma", a->gamma, "NN penalty per extra stored AP (dB)");
    cmd->add_option("--representation", a->representation, "knn/wknn RSS form: positive, exponential, powed");
    cmd->add_option("--distance", a->distance, "knn/wknn distance: euclidean, manhattan, sorensen");
    cmd->add_option("--sigma-floor", a->sigma_floor, "bayes: minimum standard deviation (dB)");
    cmd->add_option("--outlier-sigmas", a->outlier_sigmas,
                    "bayes: cap of each AP's standardised residual, in sigmas (0 = no cap)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--temperature", a->temperature, "bayes: posterior tempering T");
    cmd->add_option("--offset-sigma", a->offset_sigma, "bayes: prior sd of the phone's RSS offset (dB), 0 = off");
    cmd->add_option("--estimate", a->estimate, "bayes: map or mean");
    cmd->add_option("--missing-rss", a->missing_rss, "value of an AP heard on one side only (dBm)");
    cmd->add_option("--min-detection", a->min_detection, "clamp of detection rates count/scans");
    cmd->add_option("--alpha", a->alpha, "exponential representation α");
    cmd->add_option("--beta", a->beta, "powed representation β");
    cmd->add_option("--expected", a->expected, "knn/wknn: RP fingerprint = detection rate x rep(mean) (1) or rep(mean) (0)");
    cmd->add_option("--floor-temperature", a->floor_temperature, "bayes: temperature of the floor vote (0 = --temperature)");
    cmd->add_option("--floor-knn", a->floor_knn, "bayes: nearest RPs by knn distance that also vote for the floor (0 = off)");
    cmd->add_option("--floor-knn-weight", a->floor_knn_weight, "bayes: share of the knn vote in the floor decision");
    cmd->add_option("--floor-aps", a->floor_aps, "bayes: strongest query APs voting for their home floor (0 = off)");
    cmd->add_option("--floor-ap-weight", a->floor_ap_weight, "bayes: share of the AP vote in the floor decision");
    cmd->add_flag("--oracle", a->oracle,
                  "also report 'oracle': the nearest remaining RP on the true floor, a bound set by coverage");
    cmd->add_option("--covered-within", a->covered_within,
                    "only queries within this many metres of a remaining RP on their true floor");
    cmd->add_option("--per-query", a->per_query,
                    "write one CSV line per answered query (truth, estimate, error, oracle distance) to this file");
    cmd->add_flag("--json", a->json, "print JSON (an array for --algorithm all)");
    cmd->callback([a] { run(*a); });
});
