// What the ranging localize's transmitter cache saves per request: reading a floor's
// transmitters from SQLite (as every ranging localize did before) against a cache hit.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "store/sql_store.hpp"
#include "transmitters/floor_transmitters.hpp"
#include "transmitters/transmitter_cache.hpp"

namespace {

using locus::store::kind;

struct Floor {
    std::filesystem::path dir;
    std::unique_ptr<locus::store::SqlStore> store;
    std::int64_t floor = 0;

    explicit Floor(int transmitters) {
        std::string tmpl = (std::filesystem::temp_directory_path() / "locus-txbench-XXXXXX").string();
        dir = mkdtemp(tmpl.data());
        store = std::make_unique<locus::store::SqlStore>((dir / "b.db").string());
        const auto map = store->create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
        const auto building = store->create(kind("buildings"), map, {{"name", "B"}}).id;
        floor = store->create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 100.0}, {"height", 50.0}}).id;
        std::vector<locus::store::RowWrite> rows;
        for (int i = 0; i < transmitters; ++i) {
            char bssid[32];
            std::snprintf(bssid, sizeof bssid, "02:00:00:00:%02x:%02x", i / 256, i % 256);
            rows.push_back({std::nullopt,
                            {{"type", std::string("wifi")}, {"bssid", std::string(bssid)}, {"x", 1.0 + i % 90}, {"y", 1.0 + i % 40},
                             {"tx_power", -40.0}}});
        }
        store->write_rows(kind("transmitters"), floor, rows);
    }
    ~Floor() {
        store.reset();
        std::filesystem::remove_all(dir);
    }
};

void BM_ReadFromStore(benchmark::State& state) {
    Floor f(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(locus::transmitters::transmitters_of_floor(*f.store, f.floor));
}
BENCHMARK(BM_ReadFromStore)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

void BM_CacheHit(benchmark::State& state) {
    Floor f(static_cast<int>(state.range(0)));
    locus::transmitters::TransmitterCache cache(*f.store);
    cache.of_floor(f.floor);
    for (auto _ : state) benchmark::DoNotOptimize(cache.of_floor(f.floor));
}
BENCHMARK(BM_CacheHit)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
