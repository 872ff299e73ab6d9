// The directory search over 10,000 names: a synthetic campus of 8,000 rooms ("Room 3.21",
// "Lab 12.04", "Meeting room Rossini", …, a third with one or two people's names as tags, many
// accented) and 2,000 POIs of a dozen kinds. Each query kind runs as its own benchmark; the
// queries rotate through a fixed list so no answer is cached anywhere. p50/p99/max of the
// single queries' CPU time are counters, as route_bench reports them. Run by hand:
//   build/bin/search_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>
#include <string>
#include <time.h>
#include <vector>

#include "locus/directory/index.hpp"
#include "locus/metrics.hpp"

namespace {

using namespace locus::directory;

const char* const kFirst[] = {"Anna", "José", "Zoë", "François", "Jürgen", "Ingrid", "Łukasz", "Søren", "Chloé",
                              "Björn", "Inés", "Mateo", "Aiko", "Olúwadámilọ́lá", "Marco", "Élodie", "Nikolaj",
                              "Renée", "Tomás", "Ayşe", "Dagný", "Hélène", "Ömer", "Paolo"};
const char* const kLast[] = {"Müller", "Núñez", "Rossi", "Dvořák", "García", "Łęcki", "Jørgensen", "Öztürk",
                             "Lefèvre", "Schäfer", "Andrés", "Kovač", "Ibáñez", "Nakamura", "Brontë", "Håkansson",
                             "Weiß", "Çelik", "Sánchez", "Fournier", "Bianchi", "Nowak", "O'Brien", "Petrović"};
const char* const kRoomWords[] = {"Room", "Lab", "Office", "Seminar room", "Meeting room", "Studio", "Workshop"};
const char* const kPoiKinds[] = {"toilet", "printer", "coffee", "exit", "elevator", "stairs",
                                 "defibrillator", "water", "kitchen", "cafeteria", "reception", "shower"};

template <typename T, std::size_t N>
const T& pick(const T (&list)[N], std::mt19937& rng) {
    return list[std::uniform_int_distribution<std::size_t>(0, N - 1)(rng)];
}

const std::vector<Document>& campus() {
    static const std::vector<Document> docs = [] {
        std::vector<Document> out;
        std::mt19937 rng(11);
        for (int i = 0; i < 8000; ++i) {
            const int floor = i / 400, number = i % 400;
            Document d;
            d.name = std::string(pick(kRoomWords, rng)) + " " + std::to_string(floor) + "." + (number < 10 ? "0" : "") +
                     std::to_string(number);
            if (i % 50 == 0) d.name = std::string("Meeting room ") + pick(kLast, rng);
            d.category = "office";
            if (i % 3 == 0) d.tags.push_back(std::string(pick(kFirst, rng)) + " " + pick(kLast, rng));
            if (i % 9 == 0) d.tags.push_back(std::string("Dr. ") + pick(kFirst, rng) + " " + pick(kLast, rng));
            out.push_back(std::move(d));
        }
        for (int i = 0; i < 2000; ++i) {
            const std::string kind = pick(kPoiKinds, rng);
            std::string name = kind;
            name[0] = static_cast<char>(name[0] - 'a' + 'A');
            out.push_back({name + " " + std::to_string(i / 12), kind, {}});
        }
        return out;
    }();
    return docs;
}

const Index& campus_index() {
    static const Index index(campus());
    return index;
}

void BM_BuildIndex(benchmark::State& state) {
    for (auto _ : state) {
        Index index(campus());
        benchmark::DoNotOptimize(index);
    }
    state.counters["names"] = static_cast<double>(campus().size());
}
BENCHMARK(BM_BuildIndex)->Unit(benchmark::kMillisecond);

// Thread CPU time: the machine is shared, and the target is one core's work.
double cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

void search_bench(benchmark::State& state, std::vector<std::string> queries) {
    const Index& index = campus_index();
    std::vector<double> ms;
    std::size_t i = 0, hits = 0;
    for (auto _ : state) {
        const double c0 = cpu_ms();
        const auto found = index.search(queries[i++ % queries.size()], 10);
        ms.push_back(cpu_ms() - c0);
        hits += found.size();
        benchmark::DoNotOptimize(found);
    }
    std::sort(ms.begin(), ms.end());
    state.counters["p50_ms"] = locus::metrics::percentile_interpolated(ms, 0.50);
    state.counters["p99_ms"] = locus::metrics::percentile_interpolated(ms, 0.99);
    state.counters["max_ms"] = ms.back();
    state.counters["hits"] = static_cast<double>(hits) / static_cast<double>(ms.size());
}
BENCHMARK_CAPTURE(search_bench, exact, std::vector<std::string>{"Room 3.21", "Lab 12.104", "printer", "Rossi", "Nakamura"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(search_bench, prefix, std::vector<std::string>{"ro", "lab 1", "mül", "caf", "defib", "s"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(search_bench, typo, std::vector<std::string>{"mueller", "cafetria", "nakamuar", "defibrilator", "fourneir"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(search_bench, multi_word,
                  std::vector<std::string>{"anna muller", "dr jose nunez", "meeting room rossi", "room 3.2", "seminar 7"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(search_bench, no_hit, std::vector<std::string>{"xylophone", "qqq", "zebra crossing", "room 99.99"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
