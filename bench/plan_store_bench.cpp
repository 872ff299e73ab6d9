// What keeping rooms and POIs in step with a plan, and checking a plan image, cost:
//   - plan::rects_of on a rectangle, an L-shape, a 64-sided circle and a room with 4 pillars;
//   - SqlStore::put_plan of a 128-room, 12-connector floor (a temp database file): the
//     same plan again (every room adopted, nothing rewritten but the plan's rows), and a plan
//     whose rooms all change name on every PUT (every room renamed, POIs moved);
//   - read_image_header on a 2000 × 2000 PNG and JPEG (the JPEG decoded at 1/8 scale).
// Run by hand:
//   build/bin/plan_store_bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "http/plans/image_header.hpp"
#include "images/test_images.hpp"
#include "locus/plan/rects.hpp"
#include "store/sql_store.hpp"

namespace {

using namespace locus;
using namespace locus::plan;

Ring rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}; }

void BM_RectsOf(benchmark::State& state) {
    Polygon shape;
    switch (state.range(0)) {
        case 0: shape = {rect(0, 0, 6, 4), {}}; break;
        case 1: shape = {{{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}, {0, 0}}, {}}; break;
        case 2:
            for (int i = 0; i <= 64; ++i) shape.outer.push_back({5 * std::cos(2 * M_PI * (i % 64) / 64), 5 * std::sin(2 * M_PI * (i % 64) / 64)});
            break;
        default: shape = {rect(0, 0, 20, 20), {rect(4, 4, 5, 5), rect(14, 4, 15, 5), rect(4, 14, 5, 15), rect(14, 14, 15, 15)}};
    }
    std::size_t n = 0;
    for (auto _ : state) {
        auto rs = rects_of(shape);
        n = rs.size();
        benchmark::DoNotOptimize(rs);
    }
    state.counters["rects"] = static_cast<double>(n);
}
BENCHMARK(BM_RectsOf)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->ArgNames({"shape"});

// 128 rooms of 6 × 12 m in rows along corridors, 12 connectors.
Plan floor_plan(const std::string& suffix) {
    Plan p;
    for (int i = 0; i < 128; ++i) {
        const double x = (i % 16) * 6.0, y = (i / 16) * 14.0;
        p.spaces.push_back({"Room " + std::to_string(i) + suffix, "room", {"Dept " + std::to_string(i % 7)}, {rect(x, y, x + 6, y + 12), {}}, {}});
    }
    for (int c = 0; c < 12; ++c) {
        Connector k;
        k.id = std::to_string(c);
        k.id.insert(0, 1, 'c');  // not "c" + …: GCC 12 takes that for an overlapping copy (-Wrestrict)
        k.kind = c % 3 == 0 ? ConnectorKind::elevator : ConnectorKind::stairs;
        k.at = {c * 8.0 + (suffix.empty() ? 0.0 : 0.5), 13.0};
        p.connectors.push_back(k);
    }
    return p;
}

void BM_PutPlanKeepingRooms(benchmark::State& state) {
    const std::string dir = "/tmp/locus-plan-bench-" + std::to_string(::getpid());
    std::filesystem::create_directories(dir);
    {
        store::SqlStore st(dir + "/bench.db");
        const auto map = st.create(store::kind("maps"), std::nullopt, store::Fields{{"name", std::string("M")}}).id;
        const auto b = st.create(store::kind("buildings"), map, store::Fields{{"name", std::string("B")}}).id;
        const auto floor = st.create(store::kind("floors"), b,
                                     store::Fields{{"name", std::string("F")}, {"level", std::int64_t{0}}, {"width", 100.0}, {"height", 120.0}})
                               .id;
        const bool renaming = state.range(0) != 0;
        const Plan a = floor_plan(""), other = floor_plan(" (new)");
        st.put_plan(floor, a, nullptr);
        bool flip = false;
        for (auto _ : state) {
            flip = !flip;
            auto stored = st.put_plan(floor, renaming && flip ? other : a, nullptr);
            benchmark::DoNotOptimize(stored);
        }
    }
    std::filesystem::remove_all(dir);
}
BENCHMARK(BM_PutPlanKeepingRooms)->Arg(0)->Arg(1)->ArgNames({"rename_all"})->Unit(benchmark::kMillisecond);

std::string png_of(unsigned w, unsigned h) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<std::uint8_t>((i * 31) % 251);
    return locus::testing::png_bytes(w, h, PNG_FORMAT_GRAY, px);
}

// A smooth gradient, about as compressible as a scanned drawing.
std::string jpeg_of(unsigned w, unsigned h) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h);
    for (unsigned y = 0; y < h; ++y)
        for (unsigned x = 0; x < w; ++x) px[static_cast<std::size_t>(y) * w + x] = static_cast<std::uint8_t>((x * 7 + y * 3) % 256);
    return locus::testing::jpeg_bytes(w, h, px);
}

void BM_ImageHeader(benchmark::State& state) {
    const bool jpeg = state.range(0) != 0;
    const std::string bytes = jpeg ? jpeg_of(2000, 2000) : png_of(2000, 2000);
    for (auto _ : state) {
        auto h = http::read_image_header(bytes, jpeg ? "image/jpeg" : "image/png");
        benchmark::DoNotOptimize(h);
    }
    state.counters["bytes"] = static_cast<double>(bytes.size());
}
BENCHMARK(BM_ImageHeader)->Arg(0)->Arg(1)->ArgNames({"jpeg"})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
