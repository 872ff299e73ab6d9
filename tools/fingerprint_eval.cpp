#include "fingerprint_eval.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>

#include "command_registry.hpp"
#include "locus/match/tune.hpp"
#include "locus/metrics.hpp"

namespace locus::tools::eval {

namespace {
using metrics::percentile_interpolated;

// EvAAL's penalties (the IPIN 2015 UJIIndoorLoc track): a floor missed costs 4 m per floor
// of difference, a building missed 50 m, on top of the horizontal error.
constexpr double kFloorPenaltyM = 4.0;
constexpr double kBuildingPenaltyM = 50.0;
}  // namespace

Method yardstick(const uji::Data& train, const std::vector<std::size_t>& train_rows) {
    Method m;
    m.name = "yardstick";
    m.algorithm = match::Algorithm::knn;
    m.options.k = 3;
    m.options.representation = match::Representation::powed;
    m.options.distance = match::Distance::sorensen;
    m.options.position_on_voted_floor = false;
    m.params.powed_beta = std::numbers::e;
    // "min" of the paper is one below the lowest RSS of the database, so the weakest reading
    // still counts as heard; the index maps RSS at or below missing_rss to "not heard".
    m.params.missing_rss = uji::min_rss(train, train_rows).value_or(-100.0) - 1.0;
    m.raw_scans = true;
    return m;
}

Method server_default() {
    Method m;
    m.name = "default";
    m.algorithm = match::kDefaultAlgorithm;
    return m;
}

Method tuned_default(const uji::Data& train, const std::vector<std::size_t>& train_rows, std::string& chosen,
                     const match::TuneLimits& limits) {
    const auto grid = match::tune_grid();
    // floor_id is building·100 + floor (uji::floor_id): the level is what is left of 100.
    const auto report = match::tune(uji::indexed_rps(train, train_rows), grid,
                                    [](long long floor) { return floor % 100; }, limits);
    const auto& best = report.rows[report.best];
    Method m = server_default();
    m.algorithm = best.setting.algorithm;
    m.options = best.setting.options;
    chosen = best.name;
    return m;
}

match::FoldScheme fold_scheme(const std::string& option, const std::string& text) {
    const auto scheme = match::parse_fold_scheme(text);
    if (!scheme)
        throw CommandError(option + ": expected position, spatial:G (metres >= 0.01) or order:N (N >= 1), got '" + text +
                           "'");
    return *scheme;
}

void MatcherFlags::add_to(CLI::App& cmd) {
    cmd.add_option("--k", k, "neighbours for knn/wknn (and bayes when --bayes-k is 0)");
    cmd.add_option("--bayes-k", bayes_k, "bayes: RPs in the posterior mean (0 = --k)");
    cmd.add_option("--tolerance", tolerance, "keep RPs within tolerance*|best| of the best score");
    cmd.add_option("--gamma", gamma, "NN penalty per extra stored AP (dB)");
    cmd.add_option("--representation", representation, "knn/wknn RSS form: positive, exponential, powed");
    cmd.add_option("--distance", distance, "knn/wknn distance: euclidean, manhattan, sorensen");
    cmd.add_option("--sigma-floor", sigma_floor, "bayes: minimum standard deviation (dB)");
    cmd.add_option("--outlier-sigmas", outlier_sigmas,
                   "bayes: cap of each AP's standardised residual, in sigmas (0 = no cap)")
        ->check(CLI::NonNegativeNumber);
    cmd.add_option("--temperature", temperature, "bayes: posterior tempering T");
    cmd.add_option("--offset-sigma", offset_sigma, "bayes: prior sd of the phone's RSS offset (dB), 0 = off");
    cmd.add_option("--estimate", estimate, "bayes: map or mean");
    cmd.add_option("--missing-rss", missing_rss, "value of an AP heard on one side only (dBm)");
    cmd.add_option("--min-detection", min_detection, "clamp of detection rates count/scans");
    cmd.add_option("--alpha", alpha, "exponential representation α");
    cmd.add_option("--beta", beta, "powed representation β");
    cmd.add_option("--expected", expected,
                   "knn/wknn: RP fingerprint = detection rate x rep(mean) (1) or rep(mean) (0)");
    cmd.add_option("--floor-temperature", floor_temperature,
                   "bayes: temperature of the floor vote (0 = --temperature)");
    cmd.add_option("--floor-knn", floor_knn, "bayes: nearest RPs by knn distance that also vote for the floor (0 = off)");
    cmd.add_option("--floor-knn-weight", floor_knn_weight, "bayes: share of the knn vote in the floor decision");
    cmd.add_flag("--floor-knn-floor-only", floor_knn_floor_only,
                 "bayes: the knn vote names the floor only; the position stays on the posterior's floor");
    cmd.add_option("--floor-aps", floor_aps, "bayes: strongest query APs voting for their home floor (0 = off)");
    cmd.add_option("--floor-ap-weight", floor_ap_weight, "bayes: share of the AP vote in the floor decision");
    cmd.add_flag("--raw-scans", raw_scans,
                 "map every training row as its own RP (raw fingerprints) instead of one RP per position");
}

match::Options MatcherFlags::options() const {
    match::Options o;
    if (k) o.k = *k;
    if (bayes_k) o.bayes_k = *bayes_k;
    if (tolerance) o.tolerance = *tolerance;
    if (gamma) o.gamma = *gamma;
    if (offset_sigma) o.offset_sigma = *offset_sigma;
    if (temperature) o.temperature = *temperature;
    if (sigma_floor) o.sigma_floor = *sigma_floor;
    if (outlier_sigmas) o.outlier_sigmas = *outlier_sigmas;
    if (floor_temperature) o.floor_temperature = *floor_temperature;
    if (floor_knn) o.floor_knn = *floor_knn;
    if (floor_knn_weight) o.floor_knn_weight = *floor_knn_weight;
    if (floor_knn_floor_only) o.floor_knn_position = false;
    if (floor_aps) o.floor_aps = *floor_aps;
    if (floor_ap_weight) o.floor_ap_weight = *floor_ap_weight;
    if (!representation.empty()) {
        auto r = match::parse_representation(representation);
        if (!r) throw CommandError("unknown representation '" + representation + "' (positive, exponential, powed)");
        o.representation = *r;
    }
    if (!distance.empty()) {
        auto d = match::parse_distance(distance);
        if (!d) throw CommandError("unknown distance '" + distance + "' (euclidean, manhattan, sorensen)");
        o.distance = *d;
    }
    if (!estimate.empty()) {
        auto e = match::parse_bayes_estimate(estimate);
        if (!e) throw CommandError("unknown estimate '" + estimate + "' (map, mean)");
        o.estimate = *e;
    }
    return o;
}

match::IndexParams MatcherFlags::params() const {
    match::IndexParams p;
    if (missing_rss) p.missing_rss = *missing_rss;
    if (min_detection) p.min_detection = *min_detection;
    if (alpha) p.exponential_alpha = *alpha;
    if (beta) p.powed_beta = *beta;
    if (expected) p.expected_representation = *expected;
    return p;
}

namespace {
[[noreturn]] void unknown_algorithm(const std::string& name) {
    throw CommandError("unknown algorithm '" + name +
                       "' (bsb, nn, bsbnn, knn, wknn, bayes, default, yardstick, all or grid)");
}
}  // namespace

void check_algorithm_name(const std::string& name) {
    if (name != "all" && name != "grid" && name != "default" && name != "yardstick" && !match::parse_algorithm(name))
        unknown_algorithm(name);
}

std::vector<Method> methods_named(const std::string& name, const MatcherFlags& flags, const uji::Data& train,
                                  const std::vector<std::size_t>& train_rows) {
    auto with_flags = [&](match::Algorithm a) {
        Method m;
        m.name = std::string(match::to_string(a));
        m.algorithm = a;
        m.options = flags.options();
        m.params = flags.params();
        m.raw_scans = flags.raw_scans;
        return m;
    };
    std::vector<Method> out;
    if (name == "all") {
        for (auto a : match::all_algorithms()) out.push_back(with_flags(a));
        out.push_back(yardstick(train, train_rows));
    } else if (name == "grid") {
        // tune's candidates exactly as tune runs them (their own options, the default index),
        // so a CV here ranks what the tune chooses between.
        for (const auto& c : match::tune_grid()) {
            Method m;
            m.name = c.name;
            m.algorithm = c.setting.algorithm;
            m.options = c.setting.options;
            out.push_back(std::move(m));
        }
        out.push_back(yardstick(train, train_rows));
    } else if (name == "default") {
        out.push_back(server_default());
    } else if (name == "yardstick") {
        out.push_back(yardstick(train, train_rows));
    } else if (auto a = match::parse_algorithm(name)) {
        out.push_back(with_flags(*a));
    } else {
        unknown_algorithm(name);
    }
    return out;
}

match::Index build_index(const Method& method, const uji::Data& train, const std::vector<std::size_t>& train_rows) {
    const auto rps = method.raw_scans ? uji::raw_rps(train, train_rows) : uji::indexed_rps(train, train_rows);
    return match::Index::build(rps, method.params);
}

Queries queries_of(const uji::Data& test, const std::vector<std::size_t>& test_rows) {
    Queries q;
    for (auto i : test_rows) {
        const auto& row = test.rows[i];
        if (row.heard.empty()) {
            ++q.skipped_empty;
            continue;
        }
        q.queries.push_back(match::Query::from_scans({uji::scan_of(test, row)}));
        q.truth.push_back(Truth{Point{row.longitude, row.latitude}, row.building, row.floor});
    }
    return q;
}

double nearest_on_true_floor(const match::Index& index, const Truth& t) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < index.size(); ++i) {
        const auto& rp = index.rp(i);
        if (rp.building_id == t.building && rp.floor_id == uji::floor_id(t.building, t.floor))
            best = std::min(best, distance(rp.at, t.at));
    }
    return best;
}

nlohmann::json evaluate(const match::Index& index, const Queries& q, const Method& method, std::size_t& unanswered,
                        std::FILE* per_query) {
    const auto& queries = q.queries;
    const auto& truth = q.truth;
    std::vector<std::optional<match::Result>> results(queries.size());
    match::Workspace workspace;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < queries.size(); ++i)
        results[i] = match::localize(index, queries[i], method.algorithm, method.options, workspace);
    const auto t1 = std::chrono::steady_clock::now();

    std::size_t building_hits = 0, floor_hits = 0;
    std::vector<double> errors, evaal;
    errors.reserve(queries.size());
    evaal.reserve(queries.size());
    unanswered = 0;
    for (std::size_t i = 0; i < queries.size(); ++i) {
        if (!results[i]) {
            ++unanswered;
            continue;
        }
        const auto& r = *results[i];
        const bool building_ok = r.building_id == truth[i].building;
        const long long floor = r.floor_id % 100;
        building_hits += building_ok;
        floor_hits += building_ok && r.floor_id == uji::floor_id(truth[i].building, truth[i].floor);
        errors.push_back(distance(r.at, truth[i].at));
        evaal.push_back(errors.back() + kFloorPenaltyM * static_cast<double>(std::llabs(floor - truth[i].floor)) +
                        (building_ok ? 0.0 : kBuildingPenaltyM));
        if (per_query &&
            std::fprintf(per_query, "%s,%zu,%d,%d,%.3f,%.3f,%lld,%lld,%.3f,%.3f,%.3f,%.3f\n", method.name.c_str(), i,
                         truth[i].building, truth[i].floor, truth[i].at.x, truth[i].at.y, r.building_id, floor, r.at.x,
                         r.at.y, errors.back(), nearest_on_true_floor(index, truth[i])) < 0)
            throw CommandError("cannot write the --per-query file");
    }
    std::sort(errors.begin(), errors.end());
    const double n = static_cast<double>(queries.size());
    const double us = std::chrono::duration<double, std::micro>(t1 - t0).count();
    return nlohmann::json{
        {"algorithm", method.name},
        {"queries", queries.size()},
        {"rps", index.size()},
        {"building_hit_rate", static_cast<double>(building_hits) / n},
        {"floor_hit_rate", static_cast<double>(floor_hits) / n},
        {"mean_error_m", metrics::mean(errors)},
        {"median_error_m", percentile_interpolated(errors, 0.5)},
        {"p75_error_m", percentile_interpolated(errors, 0.75)},
        {"p95_error_m", percentile_interpolated(errors, 0.95)},
        {"mean_error_evaal_m", metrics::mean(evaal)},
        {"us_per_query", us / n},
    };
}

void print_table(const nlohmann::json& rows, const std::string& label) {
    int width = 9;  // the tune grid's candidate names are longer than a matcher's
    for (const auto& o : rows) width = std::max(width, static_cast<int>(o["algorithm"].get<std::string>().size()));
    if (!label.empty()) std::printf("%-10s ", label.c_str());
    std::printf("%-*s %7s %9s %9s %8s %8s %8s %8s %8s %9s\n", width, "algo", "queries", "building", "floor", "mean_m",
                "median_m", "p75_m", "p95_m", "evaal_m", "us/query");
    for (const auto& o : rows) {
        if (!label.empty()) std::printf("%-10s ", o.value(label, std::string()).c_str());
        std::printf("%-*s %7d %8.2f%% %8.2f%% %8.2f %8.2f %8.2f %8.2f %8.2f %9.1f\n", width,
                    o["algorithm"].get<std::string>().c_str(), o["queries"].get<int>(),
                    100.0 * o["building_hit_rate"].get<double>(), 100.0 * o["floor_hit_rate"].get<double>(),
                    o["mean_error_m"].get<double>(), o["median_error_m"].get<double>(),
                    o["p75_error_m"].get<double>(), o["p95_error_m"].get<double>(),
                    o.value("mean_error_evaal_m", 0.0), o["us_per_query"].get<double>());
    }
}

}  // namespace locus::tools::eval
