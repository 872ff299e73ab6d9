// What keeping a radio map's localize index fresh costs while surveyors upload to it
// (localize::Service over SQLite in memory), for maps of 1,000, 10,000 and 100,000 RPs of 8
// APs each (of 400 on the floor).
//   BM_Rebuild: one full rebuild of the radio map's index after a write (read every RP from
//     the store, build match::Index): what a query on a stale index used to wait for.
//   BM_LookupDuringUploads: a writer merges one scan into a random RP every 10 ms (100
//     uploads/s) while a query looks the index up 20 ms after the previous answer, for 8 s. Arg 1 = 0: as before this change (every
//     stale query rebuilds on its thread, background unpaced); 1: the defaults (big indexes
//     served stale while the paced background rebuilds). Counters: lookup p50/p99 (ms),
//     rebuilds/s (any thread) and the process's CPU in cores (/proc/self/stat).
// Run by hand (nice, under the build lock: it keeps a core busy; about 1.5 min):
//   flock -o /tmp/locus-build.lock nice -n 10 build/bin/localize_rebuild_bench
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "localize/service.hpp"
#include "store/sql_store.hpp"

namespace {

using namespace locus;
using Clock = std::chrono::steady_clock;
using Scope = localize::Service::Scope;

constexpr int kAps = 400, kApsPerRp = 8;

Bssid ap_name(int i) {
    char text[18];
    std::snprintf(text, sizeof text, "aa:00:00:00:%02x:%02x", (i >> 8) & 0xff, i & 0xff);
    return Bssid::stored(text);
}

struct Survey {
    store::SqlStore db{":memory:"};
    std::int64_t radiomap = 0;
    std::vector<std::int64_t> rps;
};

Survey& survey(int n) {
    static std::map<int, std::unique_ptr<Survey>> made;
    auto& slot = made[n];
    if (slot) return *slot;
    slot = std::make_unique<Survey>();
    Survey& s = *slot;
    const auto map = s.db.create(store::kind("maps"), std::nullopt, {{"name", "M"}}).id;
    const auto building = s.db.create(store::kind("buildings"), map, {{"name", "B"}}).id;
    const auto floor = s.db.create(store::kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 400.0}, {"height", 250.0}}).id;
    std::mt19937 rng(7);
    store::RadioMapDocument doc;
    doc.fields = {{"name", "R"}};
    for (int i = 0; i < n; ++i) {
        store::RpDocument rp;
        rp.name = "rp " + std::to_string(i);
        rp.at = {static_cast<double>(i % 400), static_cast<double>(i / 400)};
        rp.scans = 3;
        const int first = static_cast<int>(rng() % kAps);
        for (int k = 0; k < kApsPerRp; ++k)
            rp.measurements.push_back({"wifi", ap_name((first + k * 37) % kAps), RssStats{-50.0 - k * 4.0, 4.0, 3}});
        doc.rps.push_back(std::move(rp));
    }
    const auto imported = s.db.import_radiomap(floor, doc);
    s.radiomap = imported.radiomap.id;
    for (const auto& rp : s.db.rps_of_radiomap(s.radiomap)) s.rps.push_back(rp.rp.id);
    return s;
}

void upload(Survey& s, std::mt19937& rng) {
    const int ap = static_cast<int>(rng() % kAps);
    s.db.merge_scans(s.rps[rng() % s.rps.size()], {std::nullopt, {{"wifi", ap_name(ap), RssStats{-60.0, 0.0, 1}}}, 1});
}

double cpu_seconds() {
    std::ifstream in("/proc/self/stat");
    std::string field;
    for (int i = 1; i <= 13 && in >> field; ++i) {
    }
    double utime = 0, stime = 0;
    in >> utime >> stime;
    return (utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

void BM_Rebuild(benchmark::State& state) {
    Survey& s = survey(static_cast<int>(state.range(0)));
    localize::Service::Options options;
    options.sync_rebuild_max_rps = std::numeric_limits<std::size_t>::max();
    options.settle = std::chrono::hours(1);  // every rebuild is the query's own
    localize::Service service(s.db, {}, options);
    std::mt19937 rng(1);
    for (auto _ : state) {
        state.PauseTiming();
        upload(s, rng);
        state.ResumeTiming();
        benchmark::DoNotOptimize(service.lookup(Scope::radiomap, s.radiomap));
    }
    state.counters["rps"] = static_cast<double>(s.rps.size());
}
BENCHMARK(BM_Rebuild)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_LookupDuringUploads(benchmark::State& state) {
    Survey& s = survey(static_cast<int>(state.range(0)));
    const bool paced = state.range(1) != 0;
    localize::Service::Options options;
    if (!paced) {
        options.sync_rebuild_max_rps = std::numeric_limits<std::size_t>::max();
        options.pace_factor = 0.0;
    }
    std::atomic<long long> builds{0};
    localize::Service service(s.db, [&](localize::Snapshot&) { ++builds; }, options);
    constexpr auto kRun = std::chrono::seconds(8);
    for (auto _ : state) {
        builds = 0;
        std::atomic<bool> stop{false};
        std::thread writer([&] {
            std::mt19937 rng(2);
            while (!stop) {
                upload(s, rng);
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
        });
        std::vector<double> ms;
        const double cpu0 = cpu_seconds();
        const auto t0 = Clock::now();
        while (Clock::now() - t0 < kRun) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            const auto a = Clock::now();
            benchmark::DoNotOptimize(service.lookup(Scope::radiomap, s.radiomap));
            ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - a).count());
        }
        const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
        const double cpu = cpu_seconds() - cpu0;
        stop = true;
        writer.join();
        std::sort(ms.begin(), ms.end());
        state.SetIterationTime(wall);
        state.counters["p50_ms"] = ms[ms.size() / 2];
        state.counters["p99_ms"] = ms[ms.size() * 99 / 100];
        state.counters["rebuilds_per_s"] = static_cast<double>(builds.load()) / wall;
        state.counters["cpu_cores"] = cpu / wall;
        state.counters["queries_per_s"] = static_cast<double>(ms.size()) / wall;
    }
}
BENCHMARK(BM_LookupDuringUploads)
    ->ArgsProduct({{1000, 10000, 100000}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
