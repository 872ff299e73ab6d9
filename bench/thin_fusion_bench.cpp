// A thin client's POST /v1/tracks/{id}/steps as the server fuses it (tracks::ThinFusion, no
// HTTP): the copy of the track's filter a request runs on, then the next batch of a real PUTMC
// walk (the steps since the previous WiFi scan, about 4 s, and that scan's radio fix), averaged
// over the twelve walks, with walk_pf (the default) and the particle filter, on the PUTMC
// floor's plan made from its drawing; walk_pf also without a plan. Counters: the
// bytes one live track's filter holds (track_bytes) and those of the floor's shared plan
// structures (floor_bytes: PlanWalkable, built once per plan version). Skipped when the
// shared data folder is absent. And a Kalman track's request (kalman_trilateration, kalman_ranging,
// ekf_ranging): its scan of six transmitters ranged (trilateration, multilateration) and fused
// with 4 steps (ekf_ranging: the scan's six readings are its measurements).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <vector>

#include "datasets/putmc.hpp"
#include "image_file.hpp"
#include "locus/imaging/plan_from_image.hpp"
#include "locus/match/localize.hpp"
#include "locus/match/tune.hpp"
#include "locus/ranging/trilateration.hpp"
#include "putmc_thin.hpp"
#include "tracks/fusion.hpp"
#include "tracks/radio_fix.hpp"
#include "build_paths.hpp"

using namespace locus;

namespace {

const std::string kImage = std::string(LOCUS_DATA_DIR) + "/putmc/map/floorplan.png";
constexpr double kPxPerM = 28.3988631094;

std::shared_ptr<const fusion::Walkable> putmc_floor() {
    static const std::shared_ptr<const fusion::Walkable> floor = []() -> std::shared_ptr<const fusion::Walkable> {
        if (!std::filesystem::exists(kImage)) return nullptr;
        imaging::FromImageOptions o;
        o.px_per_m = kPxPerM;
        return std::make_shared<const fusion::Walkable>(fusion::Walkable::from_plan(imaging::plan_from_image(tools::read_grey_image(kImage), o)));
    }();
    return floor;
}

// The PUTMC walks as a thin client posts them (tools/putmc_thin): per scan, the steps the
// detector confirmed since the previous one (compass headings: walk_pf learns the rotation) and
// the scan's fix as the server's /steps would match it (the radio map's default matcher over
// the survey's RPs, tracks::matched_fix's accuracy). Matched once here: the match is localize's
// cost (localize_request_bench), not the tracker's.
struct Batch {
    std::vector<tracks::Step> steps;
    std::vector<tracks::RadioFix> radio;  // empty when the scan matched nothing
    Point truth;                          // floor frame
};
using Replay = std::vector<Batch>;

const std::vector<Replay>& putmc_walks() {
    static const std::vector<Replay> walks = [] {
        std::vector<Replay> out;
        const std::string dir = std::string(LOCUS_DATA_DIR) + "/putmc";
        if (!std::filesystem::exists(kImage)) return out;
        const auto survey = datasets::putmc::read_survey(dir + "/map");
        const auto image = tools::read_grey_image(kImage);
        const double height_m = image.height / survey.px_per_m;
        std::map<int, std::vector<Scan>> scans_at;
        for (const auto& s : survey.scans)
            if (!s.readings.empty()) scans_at[s.loc_id].push_back(s.readings);
        std::vector<match::IndexedRp> rps;
        for (const auto& [loc, scans] : scans_at) {
            match::IndexedRp rp;
            rp.rp.id = loc;
            rp.rp.at = datasets::putmc::to_floor(survey.at_of(loc), height_m);
            rp.rp.scans = static_cast<std::int64_t>(scans.size());
            rp.rp.measurements = aggregate_scans(scans);
            rp.floor_id = 1;
            rps.push_back(std::move(rp));
        }
        const auto index = match::Index::build(rps);
        const match::Setting setting;  // a radio map's defaults before any tune
        match::Workspace workspace;
        for (const auto& walk_dir : datasets::putmc::walk_dirs(dir)) {
            const auto walk = datasets::putmc::read_walk(walk_dir);
            Replay replay;
            for (const auto& b : tools::walks::thin_batches(walk)) {
                Batch batch;
                batch.truth = datasets::putmc::to_floor(b.truth, height_m);
                for (const auto& s : b.steps) batch.steps.push_back({s.t_s, s.length_m, s.azimuth_rad * 180.0 / std::numbers::pi});
                const auto m = match::localize(index, match::Query::from_scans({b.scan->readings}), setting.algorithm, setting.options, workspace);
                if (m) batch.radio.emplace_back(tracks::matched_fix(b.t_s, 1, m->at, tracks::candidate_spread(*m, setting.options.k)));
                replay.push_back(std::move(batch));
            }
            out.push_back(std::move(replay));
        }
        return out;
    }();
    return walks;
}

// The batch a replay's track starts at: its first scan that matched.
std::size_t first_fix(const Replay& r) {
    std::size_t i = 0;
    while (i < r.size() && r[i].radio.empty()) ++i;
    return i;
}

// Arg 0: 0 = walk_pf, 1 = particle; arg 1: 1 = on the plan, 0 = no plan. Each iteration is
// one request: a walk's requests in turn, then the next walk's, round the twelve (a walk's
// first request, with no filter to continue, starts it untimed at its fix). Counters: steps
// per request; error_m, the mean distance from a request's last answer to its scan's truth
// (a check that the replay is a real walk's); track_bytes, the most one track held, and
// mean_track_bytes its mean over the requests (an adaptive cloud's size).
void BM_ThinFusionRequest(benchmark::State& state) {
    const auto method = state.range(0) ? tracks::FusionMethod::particle : tracks::FusionMethod::walk_pf;
    std::shared_ptr<const fusion::Walkable> plan;
    if (state.range(1)) {
        plan = putmc_floor();
        if (!plan) return state.SkipWithError("no PUTMC data");
    }
    const auto& walks = putmc_walks();
    if (walks.empty()) return state.SkipWithError("no PUTMC data");
    const auto walkable_of = [&plan](std::int64_t) { return plan; };
    std::shared_ptr<tracks::ThinFusion> track;
    std::size_t walk = 0, next = 0, answered = 0, steps = 0;
    double error_sum = 0.0;
    std::size_t most_bytes = 0;
    double bytes_sum = 0.0;
    for (auto _ : state) {
        if (!track || next == walks[walk].size()) {
            state.PauseTiming();
            if (track) walk = (walk + 1) % walks.size();
            next = first_fix(walks[walk]);
            track = std::make_shared<tracks::ThinFusion>(method, 7);
            track->run({}, walks[walk][next].radio, walkable_of);
            ++next;
            state.ResumeTiming();
        }
        const Batch& b = walks[walk][next++];
        steps += b.steps.size();
        // The request runs on a copy, kept once its fixes are stored (tracks::Service::post_raw).
        auto copy = std::make_shared<tracks::ThinFusion>(*track);
        const auto fixes = copy->run(b.steps, b.radio, walkable_of);
        if (!fixes.empty()) {
            error_sum += distance({fixes.back().x, fixes.back().y}, b.truth);
            ++answered;
        }
        track = std::move(copy);
        most_bytes = std::max(most_bytes, track->memory_bytes());
        bytes_sum += static_cast<double>(track->memory_bytes());
    }
    if (answered) state.counters["error_m"] = error_sum / static_cast<double>(answered);
    state.counters["steps"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kAvgIterations);
    // (On the plan) what the floor's tracks share.
    state.counters["track_bytes"] = static_cast<double>(most_bytes);
    state.counters["mean_track_bytes"] = benchmark::Counter(bytes_sum, benchmark::Counter::kAvgIterations);
    if (plan) state.counters["floor_bytes"] = static_cast<double>(plan->floor_plan->memory_bytes());
}
// Run with --benchmark_min_time=3 to go round the walks' ~250 requests at least twice (the
// default 0.5 s takes /0/1 through the first two thirds of them).
BENCHMARK(BM_ThinFusionRequest)->Args({0, 1})->Args({1, 1})->Args({0, 0})->Unit(benchmark::kMicrosecond);

// What a fail-over costs a thin client's track in accuracy: every PUTMC walk replayed whole
// (walk_pf on the plan), and again with the track's replica lost at the walk's middle scan:
// the next request reaches a replica that does not hold the filter, which starts afresh at
// the track's latest stored fix (tracks::FusionSessions), forgetting the compass rotation and
// step scale it had learnt. One iteration replays the twelve walks. Counters: error_m, the
// mean error at the scans with an answer; second_half_m, the same over the scans from the
// middle on (those a fail-over can change). Arg: 0 = no fail-over, 1 = a fail-over per walk.
void BM_ThinFusionFailover(benchmark::State& state) {
    const auto plan = putmc_floor();
    const auto& walks = putmc_walks();
    if (!plan || walks.empty()) return state.SkipWithError("no PUTMC data");
    const auto walkable_of = [&plan](std::int64_t) { return plan; };
    double sum = 0.0, second_sum = 0.0;
    std::size_t n = 0, second_n = 0;
    for (auto _ : state) {
        sum = second_sum = 0.0;
        n = second_n = 0;
        for (const Replay& walk : walks) {
            const std::size_t first = first_fix(walk), middle = first + (walk.size() - first) / 2;
            auto track = std::make_unique<tracks::ThinFusion>(tracks::FusionMethod::walk_pf, 7);
            track->run({}, walk[first].radio, walkable_of);
            std::optional<tracks::Fix> latest;
            for (std::size_t i = first + 1; i < walk.size(); ++i) {
                if (state.range(0) && i == middle && latest) {
                    track = std::make_unique<tracks::ThinFusion>(tracks::FusionMethod::walk_pf, 7);
                    track->resume(*latest, walkable_of);
                }
                const auto fixes = track->run(walk[i].steps, walk[i].radio, walkable_of);
                if (fixes.empty()) continue;
                latest = fixes.back();
                const double e = distance({latest->x, latest->y}, walk[i].truth);
                sum += e, ++n;
                if (i >= middle) second_sum += e, ++second_n;
            }
        }
    }
    state.counters["error_m"] = n ? sum / static_cast<double>(n) : NAN;
    state.counters["second_half_m"] = second_n ? second_sum / static_cast<double>(second_n) : NAN;
}
BENCHMARK(BM_ThinFusionFailover)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);

// The copy alone: each filter holds its own Walkable (client-lib's filters own their map).
void BM_ThinFusionCopy(benchmark::State& state) {
    const auto method = state.range(0) ? tracks::FusionMethod::particle : tracks::FusionMethod::walk_pf;
    const auto plan = putmc_floor();
    if (!plan) return state.SkipWithError("no PUTMC data");
    const auto& walk = putmc_walks().front();
    tracks::ThinFusion track(method, 7);
    track.run({}, walk[first_fix(walk)].radio, [&plan](std::int64_t) { return plan; });
    for (auto _ : state) benchmark::DoNotOptimize(std::make_shared<tracks::ThinFusion>(track));
}
BENCHMARK(BM_ThinFusionCopy)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// A Kalman track's request as POST /v1/tracks/{id}/steps runs it past the HTTP layer and the
// transmitter cache (transmitter_cache_bench): the scan ranged on six transmitters around a 14 m ×
// 12 m room (the Kalman-fusion paper's trilateration or multilateration), then the filter's copy
// runs 4 steps and the ranged fix. Arg 0: 0 = kalman_trilateration, 1 = kalman_ranging, 2 =
// ekf_ranging (the scan multilaterated as the route does, its six readings the update).
void BM_ThinFusionRangingRequest(benchmark::State& state) {
    const bool ekf = state.range(0) == 2;
    const bool ours = state.range(0) >= 1;
    const std::vector<ranging::Transmitter> txs = {{{1, 1}, 1.3, {-40, 2.0}},  {{14, 1}, 1.3, {-42, 2.1}}, {{14, 13}, 1.3, {-41, 2.0}},
                                                   {{1, 13}, 1.3, {-39, 1.9}}, {{7, 7}, 1.6, {-40, 2.0}},  {{11, 7}, 1.0, {-41, 2.0}}};
    const auto method = ekf ? tracks::FusionMethod::ekf_ranging : ours ? tracks::FusionMethod::kalman_ranging : tracks::FusionMethod::kalman_trilateration;
    auto anchors = std::make_shared<tracks::FloorAnchors>();
    for (std::size_t i = 0; i < txs.size(); ++i) anchors->by_floor[1].push_back({"wifi|tx" + std::to_string(i), txs[i]});
    const auto no_plan = [](std::int64_t) { return std::shared_ptr<const fusion::Walkable>(); };
    const auto scan_at = [&](double t, Point p, int k) {
        std::vector<ranging::Heard> heard;
        std::vector<fusion::AnchorReading> readings;
        for (std::size_t i = 0; i < txs.size(); ++i) {
            const double d = std::hypot(distance(txs[i].at, p), txs[i].dz);
            heard.push_back({txs[i], ranging::rss_at(txs[i].model, d) + 2.0 * std::sin(1.7 * k + 2.3 * static_cast<double>(i))});
            if (ekf) readings.push_back({"wifi|tx" + std::to_string(i), t, heard.back().rss});
        }
        const auto f = ours ? ranging::multilaterate(heard) : ranging::trilaterate(heard);
        tracks::RadioFix r;
        r.t = t;
        r.floor_id = 1;
        r.x = f ? f->at.x : p.x;
        r.y = f ? f->at.y : p.y;
        r.accuracy_m = 1.0;
        if (f) r.ranged = *f;
        r.readings = std::move(readings);
        return r;
    };
    auto track = std::make_shared<tracks::ThinFusion>(method, 7);
    track->set_anchors(anchors);
    track->run({}, {scan_at(0, {3, 3}, 0)}, no_plan);
    double t = 0;
    Point at{3, 3};
    int k = 0;
    for (auto _ : state) {
        // Laps of the room's middle: 8 steps east, 8 west.
        const bool east = (k / 2) % 2 == 0;
        std::vector<tracks::Step> steps;
        for (int i = 1; i <= 4; ++i) steps.push_back({t + i, 0.7, east ? 90.0 : 270.0});
        at.x += east ? 2.8 : -2.8;
        auto next = std::make_shared<tracks::ThinFusion>(*track);
        benchmark::DoNotOptimize(next->run(steps, {scan_at(t + 4, at, ++k)}, no_plan));
        track = std::move(next);
        t += 4;
    }
}
BENCHMARK(BM_ThinFusionRangingRequest)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
