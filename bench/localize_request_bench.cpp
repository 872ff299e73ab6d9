// The server's own work for one POST .../localize, without the network: parsing the JSON body
// into a query, and matching plus writing the JSON answer, with real scans as the bench client
// sends them, over the full UJIIndoorLoc map (933 RPs) and over the one-floor radio map that
// `locus bench localize --radiomap 5` queries (76 RPs). The gap between the one-floor figure
// and `locus bench localize` is the HTTP layer and the kernel.
// Run by hand:  build/bin/localize_request_bench
#include <benchmark/benchmark.h>

#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "datasets/uji_csv.hpp"
#include "http/localize/localize_answer.hpp"
#include "localize_body.hpp"
#include "build_paths.hpp"

namespace {

using namespace locus;
namespace uji = locus::datasets::uji;

struct Fixture {
    localize::Snapshot snapshot, one_floor;  // the whole map; building 1 floor 0 alone (76 RPs)
    std::vector<std::string> bodies;  // {"algorithm": ..., "scans": [[{bssid, rss}...]]}
};

const Fixture* fixture(const char* algorithm) {
    static std::map<std::string, std::unique_ptr<Fixture>> cache;
    auto& slot = cache[algorithm];
    if (slot) return slot.get();
    const std::string path = std::string(LOCUS_DATA_DIR) + "/ujiindoorloc/trainingData.csv";
    if (!std::ifstream(path)) return nullptr;
    auto out = std::make_unique<Fixture>();
    const uji::Data data = uji::read_file(path);
    const std::vector<match::IndexedRp> rps = uji::indexed_rps(data);
    std::vector<match::IndexedRp> floor_rps;
    for (const auto& rp : rps)
        if (rp.floor_id == uji::floor_id(1, 0)) floor_rps.push_back(rp);
    out->snapshot.index = match::Index::build(rps);
    out->one_floor.index = match::Index::build(floor_rps);
    http::prepare_answers(out->snapshot);
    http::prepare_answers(out->one_floor);
    for (std::size_t i = 0; i < data.rows.size(); i += 10)
        if (!data.rows[i].heard.empty()) out->bodies.push_back(tools::localize_body({uji::scan_of(data, data.rows[i])}, algorithm));
    slot = std::move(out);
    return slot.get();
}

void parse_bench(benchmark::State& state, const char* algorithm) {
    const Fixture* f = fixture(algorithm);
    if (!f) return state.SkipWithError("UJIIndoorLoc not found under LOCUS_DATA_DIR/ujiindoorloc");
    std::size_t i = 0, bytes = 0;
    for (auto _ : state) {
        const std::string& body = f->bodies[i];
        auto request = http::parse_localize_request(body);
        benchmark::DoNotOptimize(request);
        bytes += body.size();
        if (++i == f->bodies.size()) i = 0;
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
}

// one_floor: the radio map `locus bench localize --radiomap 5` queries after `locus import uji`.
// Bodies sharing no AP with it are answered 422 by the server and skipped here, as the
// HTTP bench skips them.
void request_bench(benchmark::State& state, const char* algorithm, bool one_floor) {
    const Fixture* f = fixture(algorithm);
    if (!f) return state.SkipWithError("UJIIndoorLoc not found under LOCUS_DATA_DIR/ujiindoorloc");
    const localize::Snapshot& snapshot = one_floor ? f->one_floor : f->snapshot;
    std::vector<const std::string*> bodies;
    for (const auto& b : f->bodies) {
        try {
            (void)http::answer(snapshot, http::parse_localize_request(b));
            bodies.push_back(&b);
        } catch (const std::exception&) {
        }
    }
    if (bodies.empty()) return state.SkipWithError("no scan shares an access point with the radio map");
    std::size_t i = 0;
    for (auto _ : state) {
        auto text = http::answer(snapshot, http::parse_localize_request(*bodies[i]));
        benchmark::DoNotOptimize(text);
        if (++i == bodies.size()) i = 0;
    }
}

}  // namespace

BENCHMARK_CAPTURE(parse_bench, wknn, "wknn")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(request_bench, wknn, "wknn", false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(request_bench, bayes, "bayes", false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(request_bench, wknn_one_floor, "wknn", true)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(request_bench, bayes_one_floor, "bayes", true)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
