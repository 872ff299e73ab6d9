// `locus eval fingerprints DIR`: every fingerprint database under DIR (one folder each, with
// trainingData.csv as the radio map and testData.csv as the online scans, UJIIndoorLoc
// layout), localized in-process; one row of figures per database and method, the
// yardstick among them, so every comparison is side by side in one run.
//
// --cv K instead leaves the test files unread (it needs no testData.csv): each database's
// training rows are split by surveyed position into K folds, each fold queried against a map
// of the others, pooled. That is the protocol defaults are tuned on, so that the test sets stay
// unseen. --cv-blocks chooses what a fold takes out whole: single positions (round-robin in
// file order), spatial cells or runs of the survey order (match::assign_folds).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/uji_csv.hpp"
#include "fingerprint_eval.hpp"
#include "locus/match/cv_folds.hpp"
#include "locus/metrics.hpp"

namespace locus_cli_eval_fingerprints {
namespace {

using namespace locus;
namespace uji = locus::datasets::uji;
namespace eval = locus::tools::eval;
namespace fs = std::filesystem;

struct Args {
    std::string dir;
    std::string algorithm = "all";
    eval::MatcherFlags flags;
    int cv = 0;
    std::string cv_blocks = "position";
    match::FoldScheme blocks;  // parsed from cv_blocks
    bool json = false;
    bool tune = false;
    std::string tune_blocks;  // empty: the server's shuffled folds
    match::TuneLimits tune_limits;
};

// The folders of `dir` that hold a training file, by name.
std::vector<fs::path> databases(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_directory() && fs::is_regular_file(entry.path() / "trainingData.csv")) out.push_back(entry.path());
    std::sort(out.begin(), out.end());
    return out;
}

// Per training row, its fold: whole blocks of surveyed positions (building, floor, x, y) per
// fold (match::assign_folds), so every scan of a position is in one fold and a query never
// finds its own position in the map.
std::vector<int> row_folds(const uji::Data& data, int k, const match::FoldScheme& scheme) {
    std::vector<match::FoldSite> sites;
    sites.reserve(data.rows.size());
    for (const auto& row : data.rows) sites.push_back({row.building, row.floor, Point{row.longitude, row.latitude}});
    return match::assign_folds(sites, k, scheme);
}

// Hit rates, mean and µs weighted by queries; the percentiles are the queries-weighted mean
// of the folds' (the folds are near equal in size).
nlohmann::json pool(const std::vector<nlohmann::json>& folds) {
    nlohmann::json out = folds.front();
    double n = 0.0;
    for (const auto& f : folds) n += f["queries"].get<double>();
    for (const char* key : {"building_hit_rate", "floor_hit_rate", "mean_error_m", "median_error_m", "p75_error_m",
                            "p95_error_m", "mean_error_evaal_m", "us_per_query"}) {
        double sum = 0.0;
        for (const auto& f : folds) sum += f[key].get<double>() * f["queries"].get<double>();
        out[key] = sum / n;
    }
    out["queries"] = static_cast<std::size_t>(n);
    out["folds"] = folds.size();
    return out;
}

nlohmann::json run_database(const fs::path& db, const Args& a) {
    using tools::CommandError;
    const std::string name = db.filename().string();
    const uji::Data train = uji::read_file((db / "trainingData.csv").string());
    std::vector<std::vector<std::size_t>> train_sets, test_sets;
    uji::Data test_file;
    if (a.cv > 0) {
        const std::vector<int> folds = row_folds(train, a.cv, a.blocks);
        for (int f = 0; f < a.cv; ++f) {
            std::vector<std::size_t> tr, te;
            for (std::size_t i = 0; i < train.rows.size(); ++i) (folds[i] == f ? te : tr).push_back(i);
            if (tr.empty() || te.empty()) continue;
            train_sets.push_back(std::move(tr));
            test_sets.push_back(std::move(te));
        }
        if (train_sets.empty()) throw CommandError(name + ": too few positions for --cv " + std::to_string(a.cv));
    } else {
        const fs::path test_path = db / "testData.csv";
        if (!fs::is_regular_file(test_path)) throw CommandError(name + ": no testData.csv (or use --cv)");
        test_file = uji::read_file(test_path.string());
        if (test_file.waps != train.waps) throw CommandError(name + ": testData.csv has other WAP columns than trainingData.csv");
        std::vector<std::size_t> tr(train.rows.size()), te(test_file.rows.size());
        for (std::size_t i = 0; i < tr.size(); ++i) tr[i] = i;
        for (std::size_t i = 0; i < te.size(); ++i) te[i] = i;
        train_sets.push_back(std::move(tr));
        test_sets.push_back(std::move(te));
    }
    const uji::Data& test = a.cv > 0 ? train : test_file;

    // The methods are named from the first split's training rows (the yardstick's min RSS);
    // each split then builds its own.
    const std::size_t n_methods = eval::methods_named(a.algorithm, a.flags, train, train_sets.front()).size();
    std::vector<std::vector<nlohmann::json>> per_method(n_methods);
    std::size_t skipped = 0, unanswered_total = 0;
    std::vector<std::string> chosen;  // per split, with --tune
    for (std::size_t s = 0; s < train_sets.size(); ++s) {
        auto methods = eval::methods_named(a.algorithm, a.flags, train, train_sets[s]);
        if (a.tune) {
            // The tune sees this split's training rows only, as the server's sees its RPs.
            std::string name;
            for (auto& m : methods)
                if (m.name == "default") m = eval::tuned_default(train, train_sets[s], name, a.tune_limits);
            chosen.push_back(name);
        }
        const eval::Queries q = eval::queries_of(test, test_sets[s]);
        skipped += q.skipped_empty;
        if (q.queries.empty()) continue;
        for (std::size_t m = 0; m < methods.size(); ++m) {
            const match::Index index = eval::build_index(methods[m], train, train_sets[s]);
            std::size_t unanswered = 0;
            per_method[m].push_back(eval::evaluate(index, q, methods[m], unanswered));
            unanswered_total += unanswered;
        }
    }
    if (per_method.front().empty()) throw CommandError(name + ": no test row with a detected WAP");
    std::cerr << "eval fingerprints: " << name << ": " << train.rows.size() << " training rows, "
              << (a.cv > 0 ? std::to_string(train_sets.size()) + "-fold CV of the training rows, blocks " + match::to_string(a.blocks)
                           : std::to_string(test.rows.size()) + " test rows")
              << " (" << skipped << " without any detected WAP skipped";
    if (unanswered_total > 0) std::cerr << ", " << unanswered_total << " answers missing: counted as misses";
    std::cerr << ")\n";
    for (std::size_t s = 0; s < chosen.size(); ++s)
        std::cerr << "eval fingerprints: " << name << ": tuned default" << (chosen.size() > 1 ? " (split " + std::to_string(s + 1) + ")" : "")
                  << ": " << chosen[s] << "\n";

    nlohmann::json rows = nlohmann::json::array();
    for (auto& folds : per_method) {
        nlohmann::json row = folds.size() == 1 ? folds.front() : pool(folds);
        row["database"] = name;
        if (a.cv > 0) row["cv_blocks"] = match::to_string(a.blocks);
        if (row["algorithm"] == "default" && !chosen.empty()) row["tuned"] = chosen;
        rows.push_back(std::move(row));
    }
    return rows;
}

void run(Args& a) {
    using tools::CommandError;
    if (!fs::is_directory(a.dir)) throw CommandError(a.dir + " is not a directory");
    eval::check_algorithm_name(a.algorithm);
    a.blocks = eval::fold_scheme("--cv-blocks", a.cv_blocks);
    if (a.blocks.blocks != match::FoldBlocks::position && a.cv == 0) throw CommandError("--cv-blocks needs --cv K");
    if (!a.tune_blocks.empty()) {
        if (!a.tune) throw CommandError("--tune-blocks needs --tune");
        a.tune_limits.blocks = eval::fold_scheme("--tune-blocks", a.tune_blocks);
    }
    const auto dbs = databases(a.dir);
    if (dbs.empty()) throw CommandError("no <DB>/trainingData.csv under " + a.dir);
    a.flags.options();  // an unknown name fails before any database is read

    nlohmann::json out = nlohmann::json::array();
    for (const auto& db : dbs) {
        nlohmann::json rows;
        try {
            rows = run_database(db, a);
        } catch (const std::runtime_error& e) {
            // A malformed file names its database, not just its line.
            if (dynamic_cast<const CommandError*>(&e)) throw;
            throw CommandError(db.filename().string() + ": " + e.what());
        }
        for (auto& r : rows) out.push_back(std::move(r));
        if (!a.json) std::cout.flush();
    }
    if (a.json) {
        std::cout << out.dump() << "\n";
        return;
    }
    eval::print_table(out, "database");
}

}  // namespace

LOCUS_COMMAND("eval fingerprints", [](CLI::App& app) {
    auto& eval = locus::tools::group(app, "eval", "Measure the matchers on real data sets");
    auto* cmd = eval.add_subcommand(
        "fingerprints", "Localize every DIR/<DB>/testData.csv against DIR/<DB>/trainingData.csv (UJIIndoorLoc layout)");
    auto a = std::make_shared<Args>();
    cmd->add_option("DIR", a->dir, "folder of databases, one folder each")->required()->check(CLI::ExistingDirectory);
    cmd->add_option("--algorithm", a->algorithm,
                    "bsb, nn, bsbnn, knn, wknn, bayes, default (the server's), yardstick (raw-scan kNN-3, "
                    "powed, Sørensen), all, or grid (tune's candidates and the yardstick)")
        ->capture_default_str();
    a->flags.add_to(*cmd);
    cmd->add_option("--cv", a->cv,
                    "leave the test files unread: K-fold CV over each training set, folds by surveyed position")
        ->check(CLI::Range(2, 1000));
    cmd->add_option("--cv-blocks", a->cv_blocks,
                    "with --cv, what a fold deals out whole: position (each surveyed position), spatial:G "
                    "(positions in one G x G metre cell of a floor) or order:N (N consecutive positions in file order)")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "print one JSON array, one object per database and method");
    cmd->add_flag("--tune", a->tune,
                  "--algorithm default first tunes each training map as "
                  "POST /v1/radiomaps/{id}/tune does, on the training rows only");
    cmd->add_option("--tune-blocks", a->tune_blocks,
                    "with --tune, the tune's folds take out whole blocks (as --cv-blocks) instead of "
                    "shuffled single RPs");
    cmd->callback([a] { run(*a); });
});

}  // namespace locus_cli_eval_fingerprints
