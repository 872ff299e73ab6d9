#pragma once
// What `locus eval uji` and `locus eval fingerprints` share: the methods a run compares
// (a matcher with its options and index, or the literature's yardstick), the matcher flags
// both commands take, one evaluation pass over a set of queries and its row of figures, and
// the table both print. One place, so a figure means the same in every command.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "datasets/uji_csv.hpp"
#include "locus/match/cv_folds.hpp"
#include "locus/match/localize.hpp"
#include "locus/match/tune.hpp"

namespace locus::tools::eval {

namespace uji = locus::datasets::uji;

// One way to localize a query: a matcher, its per-query options, and how the radio map is
// built from the training rows.
struct Method {
    std::string name;  // what the report calls it
    match::Algorithm algorithm = match::Algorithm::bayes;
    match::Options options;
    match::IndexParams params;
    // Every training row its own RP (a "raw fingerprint"), instead of one RP per surveyed
    // position holding the per-AP mean, variance and count of its scans.
    bool raw_scans = false;
};

// The yardstick of Torres-Sospedra et al. ("Comprehensive analysis of distance and
// similarity measures for Wi-Fi fingerprinting indoor positioning systems", Expert Systems
// with Applications 42, 2015): kNN with k = 3 over the raw training scans, the "powed"
// representation (RSS − min)^β / (−min)^β with β = e and min one below the lowest RSS of the
// training rows, the Sørensen (Bray–Curtis) distance, the floor by vote among the k and the
// position the mean of the k, whatever their floor.
Method yardstick(const uji::Data& train, const std::vector<std::size_t>& train_rows);

// What a request with no algorithm and no options gets from the server.
Method server_default();

// What it gets once the radio map built from the training rows has been tuned
// (POST /v1/radiomaps/{id}/tune's code, match::tune, over those RPs only): the chosen
// setting, named "default"; `chosen` gets the candidate's name.
// `limits` as the server's by default; `locus eval … --tune-blocks` sets its fold blocks.
Method tuned_default(const uji::Data& train, const std::vector<std::size_t>& train_rows, std::string& chosen,
                     const match::TuneLimits& limits = {});

// A --cv-blocks / --tune-blocks value (match::parse_fold_scheme); throws CommandError naming
// the option on a bad one.
match::FoldScheme fold_scheme(const std::string& option, const std::string& text);

// The matcher knobs both eval commands take; unset ones keep the server's defaults.
struct MatcherFlags {
    std::optional<int> k, bayes_k, floor_knn, floor_aps;
    std::optional<double> floor_temperature, floor_knn_weight, floor_ap_weight;
    bool floor_knn_floor_only = false;  // --floor-knn-floor-only: Options::floor_knn_position false
    std::optional<double> outlier_sigmas;
    std::optional<double> offset_sigma, temperature, tolerance, gamma, sigma_floor, missing_rss, min_detection, alpha,
        beta;
    std::string representation, distance, estimate;
    std::optional<bool> expected;
    bool raw_scans = false;

    void add_to(CLI::App& cmd);
    // Throws CommandError on an unknown name.
    match::Options options() const;
    match::IndexParams params() const;
};

// The methods `--algorithm` names: one matcher (with the flags), `all` (every matcher with the
// flags, then the yardstick), `default` (the server's, flags ignored) or `yardstick`.
// Throws CommandError on an unknown name.
std::vector<Method> methods_named(const std::string& name, const MatcherFlags& flags, const uji::Data& train,
                                  const std::vector<std::size_t>& train_rows);

// Throws CommandError unless `methods_named` knows the name (checked before any file is read).
void check_algorithm_name(const std::string& name);

// The radio map a method localizes in, from the given training rows.
match::Index build_index(const Method& method, const uji::Data& train, const std::vector<std::size_t>& train_rows);

struct Truth {
    Point at;
    int building, floor;
};

// Online scans, one per test row with at least one valid reading (a scan with none is not a
// query: the API rejects it with 422), and where each was taken.
struct Queries {
    std::vector<match::Query> queries;
    std::vector<Truth> truth;
    std::size_t skipped_empty = 0;
};
Queries queries_of(const uji::Data& test, const std::vector<std::size_t>& test_rows);

// What no matcher answering an RP of the right floor can beat: the nearest RP of the map on
// the query's true building and floor; infinite when that floor has no RP.
double nearest_on_true_floor(const match::Index& index, const Truth& t);

// Localizes every query with the method and returns its row of figures: hit rates, mean,
// median, p75, p95 horizontal error (m), the EvAAL-style mean (horizontal + 4 m per floor
// of difference + 50 m for a wrong building) and µs per query (the matcher alone, not the
// index build). A query that shares no AP with the map counts as a building and floor miss
// and has no error; `unanswered` says how many. `per_query`, if set, gets one CSV line per
// answered query.
nlohmann::json evaluate(const match::Index& index, const Queries& q, const Method& method, std::size_t& unanswered,
                        std::FILE* per_query = nullptr);

// The figure rows as a text table; `label` names an extra first column (e.g. "database")
// read from each row, or is empty.
void print_table(const nlohmann::json& rows, const std::string& label = "");

}  // namespace locus::tools::eval
