// Time per localize() query (one iteration = one query, reported in µs) for each matcher
// over the full UJIIndoorLoc map (933 RPs, 520 WAPs), one thread, plus the cost of building
// the index; then the large maps whose query time docs/results.md bounds (≤ 300 µs): TUT6
// (3,116 one-scan RPs, queried with its own test scans) and the raw-scan yardstick on both
// (every UJIIndoorLoc training row an RP).
// The counter bytes_per_rp is the index's heap size over its RPs.
// Run by hand:  build/bin/match_bench
#include <benchmark/benchmark.h>

#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <memory>

#include "locus/match/localize.hpp"
#include "locus/match/quality.hpp"
#include "locus/match/tune.hpp"
// The reader belongs to the CLI sources, which are not a library; compile it in here.
#include "datasets/uji_csv.hpp"
#include "fingerprint_eval.hpp"
#include "build_paths.hpp"

namespace {

using namespace locus;
namespace uji = locus::datasets::uji;

struct Fixture {
    std::vector<match::IndexedRp> rps;
    match::Index index;
    std::vector<match::Query> queries;
};

const Fixture* fixture() {
    static const std::unique_ptr<Fixture> f = []() -> std::unique_ptr<Fixture> {
        const std::string path = std::string(LOCUS_DATA_DIR) + "/ujiindoorloc/trainingData.csv";
        if (!std::ifstream(path)) return nullptr;
        auto out = std::make_unique<Fixture>();
        const uji::Data data = uji::read_file(path);
        out->rps = uji::indexed_rps(data);
        out->index = match::Index::build(out->rps);
        // Every 10th row as an online scan: ~2,000 real queries spread over the 3 buildings.
        for (std::size_t i = 0; i < data.rows.size(); i += 10)
            if (!data.rows[i].heard.empty())
                out->queries.push_back(match::Query::from_scans({uji::scan_of(data, data.rows[i])}));
        return out;
    }();
    return f.get();
}

// floor_knn > 0: bayes with the opt-in knn floor vote (Options::floor_knn). no_cap: bayes
// as it was before the outlier cap (σ floor 8 dB, no cap), to see what the cap costs.
void localize_bench(benchmark::State& state, match::Algorithm algorithm, int floor_knn = 0, bool no_cap = false) {
    const Fixture* f = fixture();
    if (!f) {
        state.SkipWithError("UJIIndoorLoc not found under LOCUS_DATA_DIR/ujiindoorloc");
        return;
    }
    match::Options options;  // the defaults the server uses
    if (floor_knn > 0) options.floor_knn = floor_knn;
    if (no_cap) {
        options.outlier_sigmas = 0.0;
        options.sigma_floor = 8.0;
    }
    match::Workspace workspace;
    std::size_t i = 0;
    for (auto _ : state) {
        auto r = match::localize(f->index, f->queries[i], algorithm, options, workspace);
        benchmark::DoNotOptimize(r);
        if (++i == f->queries.size()) i = 0;
    }
    state.counters["rps"] = static_cast<double>(f->index.size());
}

void build_bench(benchmark::State& state) {
    const Fixture* f = fixture();
    if (!f) {
        state.SkipWithError("UJIIndoorLoc not found under LOCUS_DATA_DIR/ujiindoorloc");
        return;
    }
    for (auto _ : state) {
        auto idx = match::Index::build(f->rps);
        benchmark::DoNotOptimize(idx);
    }
}

// A map from a training file and real queries from a test file (every 10th row of the
// training file when there is none), for `method`'s algorithm, options and index.
struct MethodFixture {
    locus::tools::eval::Method method;
    match::Index index;
    std::vector<match::Query> queries;
};

// How the map's method is chosen: the server's built-in default, the yardstick, or what
// POST /v1/radiomaps/{id}/tune would store for the training map (match::tune, untimed).
enum Mode { kBuiltIn = 0, kYardstick = 1, kTuned = 2 };

std::unique_ptr<MethodFixture> method_fixture(const std::string& db, int mode) {
    const bool yardstick = mode == kYardstick;
    namespace ev = locus::tools::eval;
    const std::string train_path = std::string(LOCUS_DATA_DIR) + "/" + db + "/trainingData.csv";
    const std::string test_path = std::string(LOCUS_DATA_DIR) + "/" + db + "/testData.csv";
    if (!std::ifstream(train_path)) return nullptr;
    auto out = std::make_unique<MethodFixture>();
    const uji::Data train = uji::read_file(train_path);
    std::vector<std::size_t> rows(train.rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = i;
    std::string chosen;
    out->method = yardstick ? ev::yardstick(train, rows)
                : mode == kTuned ? ev::tuned_default(train, rows, chosen)
                                 : ev::server_default();
    out->index = ev::build_index(out->method, train, rows);
    if (std::ifstream(test_path)) {
        const uji::Data test = uji::read_file(test_path);
        for (const auto& row : test.rows)
            if (!row.heard.empty()) out->queries.push_back(match::Query::from_scans({uji::scan_of(test, row)}));
    } else {
        for (std::size_t i = 0; i < train.rows.size(); i += 10)
            if (!train.rows[i].heard.empty())
                out->queries.push_back(match::Query::from_scans({uji::scan_of(train, train.rows[i])}));
    }
    return out;
}

// `algorithm` with the server's options (ignored for the yardstick, which brings its own).
void map_bench(benchmark::State& state, const char* db, int mode, match::Algorithm algorithm) {
    static std::map<std::pair<std::string, int>, std::unique_ptr<MethodFixture>> cache;
    auto& f = cache[{db, mode}];
    if (!f) f = method_fixture(db, mode);
    if (!f) {
        state.SkipWithError("data set not found under LOCUS_DATA_DIR");
        return;
    }
    // The yardstick and the tuned default bring their own algorithm.
    const match::Algorithm alg = mode != kBuiltIn ? f->method.algorithm : algorithm;
    match::Workspace workspace;
    std::size_t i = 0;
    for (auto _ : state) {
        auto r = match::localize(f->index, f->queries[i], alg, f->method.options, workspace);
        benchmark::DoNotOptimize(r);
        if (++i == f->queries.size()) i = 0;
    }
    state.counters["rps"] = static_cast<double>(f->index.size());
    state.counters["bytes_per_rp"] = static_cast<double>(f->index.memory_bytes()) / static_cast<double>(f->index.size());
}

// POST /v1/radiomaps/{id}/tune's work on a whole training map (UJIIndoorLoc: 933 RPs, bound
// < 60 s on one core), without the HTTP and SQLite around it.
void tune_bench(benchmark::State& state, const char* db) {
    const std::string train_path = std::string(LOCUS_DATA_DIR) + "/" + db + "/trainingData.csv";
    if (!std::ifstream(train_path)) {
        state.SkipWithError("data set not found under LOCUS_DATA_DIR");
        return;
    }
    const uji::Data train = uji::read_file(train_path);
    const auto rps = uji::indexed_rps(train);
    const auto grid = match::tune_grid();
    for (auto _ : state) {
        auto r = match::tune(rps, grid, [](long long floor) { return floor % 100; });
        benchmark::DoNotOptimize(r);
    }
    state.counters["rps"] = static_cast<double>(rps.size());
}

// GET /v1/radiomaps/{id}/quality's work: tune's folds with one setting (the built-in default).
void quality_bench(benchmark::State& state, const char* db) {
    const std::string train_path = std::string(LOCUS_DATA_DIR) + "/" + db + "/trainingData.csv";
    if (!std::ifstream(train_path)) {
        state.SkipWithError("data set not found under LOCUS_DATA_DIR");
        return;
    }
    const uji::Data train = uji::read_file(train_path);
    const auto rps = uji::indexed_rps(train);
    for (auto _ : state) {
        auto r = match::held_out_errors(rps, match::Setting{}, [](long long floor) { return floor % 100; });
        benchmark::DoNotOptimize(r);
    }
    state.counters["rps"] = static_cast<double>(rps.size());
}

}  // namespace

BENCHMARK_CAPTURE(localize_bench, bsb, match::Algorithm::bsb)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(localize_bench, nn, match::Algorithm::nn)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(localize_bench, bsbnn, match::Algorithm::bsbnn)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(localize_bench, knn, match::Algorithm::knn)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(localize_bench, wknn, match::Algorithm::wknn)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(localize_bench, bayes, match::Algorithm::bayes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(localize_bench, bayes_no_cap, match::Algorithm::bayes, 0, true)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(localize_bench, bayes_floor_knn5, match::Algorithm::bayes, 5)->Unit(benchmark::kMicrosecond);
BENCHMARK(build_bench)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(map_bench, uji_wknn, "ujiindoorloc", kBuiltIn, match::Algorithm::wknn)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(map_bench, uji_raw_yardstick, "ujiindoorloc", kYardstick, match::Algorithm::knn)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(map_bench, tut6_wknn, "fingerprint-dbs/TUT6", kBuiltIn, match::Algorithm::wknn)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(map_bench, tut6_bayes, "fingerprint-dbs/TUT6", kBuiltIn, match::Algorithm::bayes)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(map_bench, tut6_yardstick, "fingerprint-dbs/TUT6", kYardstick, match::Algorithm::knn)
    ->Unit(benchmark::kMicrosecond);

BENCHMARK_CAPTURE(map_bench, uji_tuned_default, "ujiindoorloc", kTuned, match::Algorithm::bayes)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(map_bench, tut6_tuned_default, "fingerprint-dbs/TUT6", kTuned, match::Algorithm::bayes)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(tune_bench, uji, "ujiindoorloc")->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(tune_bench, tut6, "fingerprint-dbs/TUT6")->Unit(benchmark::kSecond)->Iterations(1);

BENCHMARK_CAPTURE(quality_bench, uji, "ujiindoorloc")->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(quality_bench, tut6, "fingerprint-dbs/TUT6")->Unit(benchmark::kMillisecond)->Iterations(3);

BENCHMARK_MAIN();
