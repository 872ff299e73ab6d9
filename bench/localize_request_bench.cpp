// The server's own work for one POST .../localize, without the network: parsing the JSON body
// into a query, and matching plus writing the JSON answer, over the full UJIIndoorLoc map
// (933 RPs) with real scans as the bench client sends them. `locus bench localize` measures
// the same request through HTTP; the gap between the two is the HTTP layer and the kernel.
// Run by hand:  build/bin/localize_request_bench
#include <benchmark/benchmark.h>

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "localize/request.hpp"
#include "uji_csv.hpp"

namespace {

using namespace locus;
namespace uji = locus::tools::uji;

struct Fixture {
    localize::Snapshot snapshot;
    std::vector<std::string> bodies;  // {"algorithm": ..., "scans": [[{bssid, rss}...]]}
};

std::string body_of(const Scan& scan, const char* algorithm) {
    nlohmann::json readings = nlohmann::json::array();
    for (const auto& r : scan) readings.push_back({{"bssid", r.bssid}, {"rss", r.rss}});
    return nlohmann::json{{"algorithm", algorithm}, {"scans", {readings}}}.dump();
}

const Fixture* fixture(const char* algorithm) {
    static std::map<std::string, std::unique_ptr<Fixture>> cache;
    auto& slot = cache[algorithm];
    if (slot) return slot.get();
    const std::string path = std::string(LOCUS_DATA_DIR) + "/ujiindoorloc/trainingData.csv";
    if (!std::ifstream(path)) return nullptr;
    auto out = std::make_unique<Fixture>();
    const uji::Data data = uji::read_file(path);
    std::vector<match::IndexedRp> rps;
    for (const auto& g : uji::group_reference_points(data)) {
        match::IndexedRp rp;
        rp.rp.id = static_cast<long long>(rps.size()) + 1;
        rp.rp.at = Point{g.longitude, g.latitude};
        rp.rp.scans = static_cast<std::int64_t>(g.rows.size());
        rp.rp.measurements = g.measurements;
        rp.floor_id = g.building * 100 + g.floor;
        rp.building_id = g.building;
        rps.push_back(std::move(rp));
    }
    out->snapshot.index = match::Index::build(rps);
    for (std::size_t i = 0; i < data.rows.size(); i += 10)
        if (!data.rows[i].heard.empty()) out->bodies.push_back(body_of(uji::scan_of(data, data.rows[i]), algorithm));
    slot = std::move(out);
    return slot.get();
}

void parse_bench(benchmark::State& state, const char* algorithm) {
    const Fixture* f = fixture(algorithm);
    if (!f) return state.SkipWithError("UJIIndoorLoc not found under LOCUS_DATA_DIR/ujiindoorloc");
    std::size_t i = 0, bytes = 0;
    for (auto _ : state) {
        const std::string& body = f->bodies[i];
        auto request = localize::parse_localize_request(body);
        benchmark::DoNotOptimize(request);
        bytes += body.size();
        if (++i == f->bodies.size()) i = 0;
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
}

void request_bench(benchmark::State& state, const char* algorithm) {
    const Fixture* f = fixture(algorithm);
    if (!f) return state.SkipWithError("UJIIndoorLoc not found under LOCUS_DATA_DIR/ujiindoorloc");
    std::size_t i = 0;
    for (auto _ : state) {
        auto text = localize::answer(f->snapshot, localize::parse_localize_request(f->bodies[i]));
        benchmark::DoNotOptimize(text);
        if (++i == f->bodies.size()) i = 0;
    }
}

}  // namespace

BENCHMARK_CAPTURE(parse_bench, wknn, "wknn")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(request_bench, wknn, "wknn")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(request_bench, bayes, "bayes")->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
