// Time per localize() query (one iteration = one query, reported in µs) for each matcher
// over the full UJIIndoorLoc map (933 RPs, 520 WAPs), one thread, plus the cost of building
// the index. Run by hand:  build/bin/match_bench
#include <benchmark/benchmark.h>

#include <fstream>
#include <memory>

#include "locus/match/localize.hpp"
// The reader belongs to the CLI sources, which are not a library; compile it in here.
#include "datasets/uji_csv.hpp"

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

BENCHMARK_MAIN();
