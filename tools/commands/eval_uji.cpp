// `locus eval uji`: the localize pipeline in-process on UJIIndoorLoc, one JSON object of
// accuracy and speed per matcher (docs/spec.md §7.1).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/uji_csv.hpp"
#include "fingerprint_eval.hpp"
#include "locus/match/localize.hpp"
#include "locus/metrics.hpp"

namespace locus_cli_eval_uji {
namespace {

using namespace locus;
namespace uji = locus::datasets::uji;
namespace eval = locus::tools::eval;
using metrics::percentile_interpolated;

struct Args {
    std::string train, test;
    std::optional<int> holdout_user, holdout_phone;
    std::vector<int> exclude_users;
    std::string algorithm = "all";
    eval::MatcherFlags flags;
    bool oracle = false;
    std::optional<double> covered_within;
    bool json = false;
    bool tune = false;
    std::string tune_blocks;  // empty: the server's shuffled folds
    std::string per_query;
};

nlohmann::json oracle(const match::Index& index, const std::vector<eval::Truth>& truth) {
    std::vector<double> errors;
    std::size_t no_floor = 0;
    for (const auto& t : truth) {
        const double best = eval::nearest_on_true_floor(index, t);
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

    match::TuneLimits tune_limits;
    if (!a.tune_blocks.empty()) {
        if (!a.tune) throw CommandError("--tune-blocks needs --tune");
        tune_limits.blocks = eval::fold_scheme("--tune-blocks", a.tune_blocks);
    }
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
    std::vector<eval::Method> methods = eval::methods_named(a.algorithm, a.flags, train, train_rows);
    if (a.tune)
        for (auto& m : methods)
            if (m.name == "default") {
                std::string chosen;
                m = eval::tuned_default(train, train_rows, chosen, tune_limits);
                std::cerr << "eval uji: tuned default: " << chosen << "\n";
            }

    // The RP map (one RP per surveyed position) the oracle and --covered-within measure
    // coverage on, whatever map each method localizes in.
    eval::Method rp_map;
    rp_map.params = a.flags.params();
    const match::Index index = eval::build_index(rp_map, train, train_rows);

    eval::Queries q = eval::queries_of(test, test_rows);
    if (a.covered_within) {
        // Only the queries the map covers: separates matching errors from coverage gaps.
        std::size_t kept = 0;
        for (std::size_t i = 0; i < q.queries.size(); ++i) {
            if (eval::nearest_on_true_floor(index, q.truth[i]) > *a.covered_within) continue;
            if (kept != i) {  // a self-move would empty the query
                q.queries[kept] = std::move(q.queries[i]);
                q.truth[kept] = q.truth[i];
            }
            ++kept;
        }
        std::cerr << "eval uji: " << kept << " of " << q.queries.size() << " queries within " << *a.covered_within
                  << " m of an RP on their floor\n";
        q.queries.resize(kept);
        q.truth.resize(kept);
    }
    if (q.queries.empty())
        throw CommandError(a.covered_within ? "no query left within --covered-within" : "no test rows with a detected WAP");
    std::cerr << "eval uji: " << index.size() << " RPs, " << index.ap_count() << " APs, " << q.queries.size()
              << " queries (" << q.skipped_empty << " rows without any detected WAP skipped)\n";

    nlohmann::json out = nlohmann::json::array();
    if (a.oracle) out.push_back(oracle(index, q.truth));
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> per_query(nullptr, std::fclose);
    if (!a.per_query.empty()) {
        per_query.reset(std::fopen(a.per_query.c_str(), "w"));
        if (!per_query) throw CommandError("cannot write " + a.per_query);
        if (std::fputs("algorithm,query,building,floor,x,y,est_building,est_floor,est_x,est_y,error_m,oracle_m\n",
                       per_query.get()) < 0)
            throw CommandError("cannot write " + a.per_query);
    }
    for (const auto& method : methods) {
        const match::Index own = eval::build_index(method, train, train_rows);
        std::size_t unanswered = 0;
        auto o = eval::evaluate(own, q, method, unanswered, per_query.get());
        if (unanswered > 0)
            std::cerr << "eval uji: " << method.name << ": " << unanswered
                      << " queries shared no AP with any RP (counted as misses, no error)\n";
        out.push_back(std::move(o));
    }
    // A full disk often shows only when the buffer is flushed, so the close is checked too.
    if (per_query && std::fclose(per_query.release()) != 0) throw CommandError("cannot write " + a.per_query);
    if (a.json) {
        std::cout << (out.size() > 1 ? out : out.front()).dump() << "\n";
        return;
    }
    eval::print_table(out);
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
    cmd->add_option("--algorithm", a->algorithm,
                    "bsb, nn, bsbnn, knn, wknn, bayes, default (the server's), yardstick (raw-scan kNN-3, "
                    "powed, Sørensen), all, or grid (tune's candidates and the yardstick)")
        ->capture_default_str();
    a->flags.add_to(*cmd);
    cmd->add_flag("--oracle", a->oracle,
                  "also report 'oracle': the nearest remaining RP on the true floor, a bound set by coverage");
    cmd->add_option("--covered-within", a->covered_within,
                    "only queries within this many metres of a remaining RP on their true floor");
    cmd->add_option("--per-query", a->per_query,
                    "write one CSV line per answered query (truth, estimate, error, oracle distance) to this file");
    cmd->add_flag("--json", a->json, "print JSON (an array for --algorithm all or grid)");
    cmd->add_flag("--tune", a->tune,
                  "--algorithm default first tunes the training map as POST /v1/radiomaps/{id}/tune does");
    cmd->add_option("--tune-blocks", a->tune_blocks,
                    "with --tune, the tune's folds take out whole blocks: position, spatial:G (metres) or order:N "
                    "(match::assign_folds) instead of shuffled single RPs");
    cmd->callback([a] { run(*a); });
});

}  // namespace locus_cli_eval_uji
