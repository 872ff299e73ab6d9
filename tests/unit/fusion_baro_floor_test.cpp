// Floors from the barometer (locus/motion/fusion/baro_floor.hpp) on synthetic pressure series whose
// expected heights were worked out by hand from the hypsometric equation at 15 °C
// (scale height R_d·T/g = 287.05 × 288.15 / 9.80665 = 8434.43 m): from 1000 hPa,
// +3.5 m is 1000·e^(−3.5/8434.43) = 999.5851 hPa, +7.0 m is 999.1704 hPa, +3.2 m is 999.6207 hPa.
// Then the stairs walk of the IPIN 2023 data set (LOCUS_DATA_DIR/ipin2023; skipped when absent).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <vector>

#include "datasets/ipin_log.hpp"
#include "locus/motion/fusion/baro_floor.hpp"
#include "build_paths.hpp"

namespace fusion_baro_floor_test {
namespace {

using namespace locus::fusion;

constexpr double kGround = 1000.0;
constexpr double kUp35 = 999.5851;  // +3.5 m
constexpr double kUp70 = 999.1704;  // +7.0 m
constexpr double kUp32 = 999.6207;  // +3.2 m

// Pressure keyframes (t s, hPa), linear in between, sampled at 10 Hz like the Galaxy S7.
struct Key {
    double t, hpa;
};

double pressure_at(const std::vector<Key>& keys, double t) {
    if (t <= keys.front().t) return keys.front().hpa;
    for (std::size_t i = 1; i < keys.size(); ++i)
        if (t <= keys[i].t) {
            const double u = (t - keys[i - 1].t) / (keys[i].t - keys[i - 1].t);
            return keys[i - 1].hpa + u * (keys[i].hpa - keys[i - 1].hpa);
        }
    return keys.back().hpa;
}

struct Vote {
    double t;
    int floor;
};

struct Trace {
    std::vector<double> t, height;
    std::vector<std::optional<int>> floor;
    // The estimate at the last sample at or before t.
    std::optional<int> floor_at(double when) const {
        std::optional<int> f;
        for (std::size_t i = 0; i < t.size() && t[i] <= when + 1e-9; ++i) f = floor[i];
        return f;
    }
    double height_at(double when) const {
        double h = NAN;
        for (std::size_t i = 0; i < t.size() && t[i] <= when + 1e-9; ++i) h = height[i];
        return h;
    }
    // How many times the estimate changed once it existed.
    int changes() const {
        int n = 0;
        for (std::size_t i = 1; i < floor.size(); ++i)
            if (floor[i - 1] && floor[i] != floor[i - 1]) ++n;
        return n;
    }
};

// Runs the estimator over the keyframes; `noise` adds a Gaussian of that σ (hPa) to each sample.
Trace run(BaroFloor& bf, const std::vector<Key>& keys, std::vector<Vote> votes, double noise = 0.0, int spike_every = 0) {
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss(0.0, noise > 0.0 ? noise : 1.0);
    Trace tr;
    std::size_t next_vote = 0;
    const int n = static_cast<int>(std::lround((keys.back().t - keys.front().t) * 10.0));
    for (int i = 0; i <= n; ++i) {
        const double t = keys.front().t + 0.1 * i;
        double p = pressure_at(keys, t);
        if (noise > 0.0) p += gauss(rng);
        if (spike_every > 0 && i % spike_every == spike_every - 1) p += 1.5;  // a 13 m spike
        bf.add_pressure(t, p);
        while (next_vote < votes.size() && votes[next_vote].t <= t + 1e-9) bf.add_radio_vote(votes[next_vote++].floor);
        tr.t.push_back(t);
        tr.height.push_back(bf.height_m());
        tr.floor.push_back(bf.floor());
    }
    return tr;
}

std::vector<FloorLevel> three_floors() { return {{0, 0.0, true}, {1, 3.5, true}, {2, 7.0, true}}; }

std::vector<Vote> votes_every(double from, double to, double every, int floor) {
    std::vector<Vote> v;
    for (double t = from; t <= to + 1e-9; t += every) v.push_back({t, floor});
    return v;
}

// A two-floor climb: 40 s on the ground, 12 s of stairs to +3.5 m, 30 s there, 12 s more to
// +7.0 m, 30 s there.
std::vector<Key> two_floor_climb() {
    return {{0, kGround}, {40, kGround}, {52, kUp35}, {82, kUp35}, {94, kUp70}, {124, kUp70}};
}

TEST(BaroFloor, HypsometricHeightsMatchTheHandValues) {
    EXPECT_NEAR(hypsometric_height_m(kUp35, kGround), 3.5, 0.002);
    EXPECT_NEAR(hypsometric_height_m(kUp70, kGround), 7.0, 0.002);
    EXPECT_NEAR(hypsometric_height_m(kGround, kUp70), -7.0, 0.002);
    // At 30 °C the column is 303.15 / 288.15 taller per unit of ln p: 7.0 m × 1.05206 = 7.364 m.
    EXPECT_NEAR(hypsometric_height_m(kUp70, kGround, 30.0), 7.364, 0.002);
    // The IPIN 2023 README's floor step: 0.66 hPa more in the basement at ~980 hPa is
    // 8434.43 × ln(980.12 / 980.78) = −5.68 m.
    EXPECT_NEAR(hypsometric_height_m(980.78, 980.12), -5.68, 0.01);
    EXPECT_THROW(hypsometric_height_m(0.0, kGround), std::invalid_argument);
    EXPECT_THROW(hypsometric_height_m(kGround, NAN), std::invalid_argument);
}

TEST(BaroFloor, TheHeightIsRelativeToTheFirstSecondsMedian) {
    BaroHeight h;
    // The first 5 s (the reference): 1000.00 with one 1000.30 outlier; the median is 1000.00.
    for (int i = 0; i <= 50; ++i) h.add(i * 0.1, i == 20 ? 1000.30 : kGround);
    EXPECT_TRUE(h.reference_fixed());
    EXPECT_DOUBLE_EQ(h.reference_hpa(), kGround);
    for (int i = 51; i <= 100; ++i) h.add(i * 0.1, kUp70);
    EXPECT_NEAR(h.height_m(), 7.0, 0.002);
    EXPECT_DOUBLE_EQ(h.reference_hpa(), kGround);  // fixed: later samples do not move it
    EXPECT_THROW(h.add(5.0, kGround), std::invalid_argument);  // time going back
    EXPECT_THROW(h.add(11.0, -1.0), std::invalid_argument);
    EXPECT_THROW(BaroHeight(BaroHeightConfig{5.0, 0.0, 15.0}), std::invalid_argument);
}

TEST(BaroFloor, AClimbOfTwoFloors) {
    BaroFloor bf(three_floors());
    const auto tr = run(bf, two_floor_climb(), {{1.0, 0}});
    EXPECT_EQ(tr.floor_at(0.5), std::nullopt);  // no vote and no start floor yet
    EXPECT_EQ(tr.floor_at(39.0), 0);
    EXPECT_EQ(tr.floor_at(81.0), 1);
    EXPECT_EQ(tr.floor_at(124.0), 2);
    EXPECT_NEAR(tr.height_at(81.0), 3.5, 0.01);
    EXPECT_NEAR(tr.height_at(124.0), 7.0, 0.01);
    EXPECT_EQ(tr.changes(), 2);  // 0 → 1 → 2, no flicker on the stairs
    // Half-way up the first flight (46 s: +1.75 m, less the 1 s lag of the median) it is
    // still the ground floor; 2 s after the landing it is the first floor.
    EXPECT_EQ(tr.floor_at(46.0), 0);
    EXPECT_EQ(tr.floor_at(54.0), 1);
    const auto p = bf.start_probabilities();
    ASSERT_EQ(p.size(), 3u);
    EXPECT_GT(p[0], 0.99);  // the walk started on floor 0
}

TEST(BaroFloor, NoiseAndSpikesDoNotMakeItFlicker) {
    BaroFloor bf(three_floors());
    // σ 0.03 hPa (0.25 m) on every sample and a +1.5 hPa spike (−13 m) every 3.7 s.
    const auto tr = run(bf, two_floor_climb(), {{1.0, 0}}, 0.03, 37);
    EXPECT_EQ(tr.floor_at(39.0), 0);
    EXPECT_EQ(tr.floor_at(81.0), 1);
    EXPECT_EQ(tr.floor_at(124.0), 2);
    EXPECT_EQ(tr.changes(), 2);
    EXPECT_NEAR(tr.height_at(81.0), 3.5, 0.3);
    EXPECT_NEAR(tr.height_at(124.0), 7.0, 0.3);
}

TEST(BaroFloor, SlowDriftIsAbsorbed) {
    // A basement 3.5 m down. The walker stays on the ground for 600 s while the weather raises
    // the pressure by 0.6 hPa (what the barometer alone reads as about −5 m, i.e. the
    // basement), then climbs 3.5 m to floor 1 on top of the drifted pressure.
    // By hand, at 600 s: the reference is the median of the first 5 s, the pressure at 2.5 s
    // (1000.0025 hPa); the smoothed pressure the median of (598, 600], the pressure at 599.05 s
    // (1000.59905 hPa); 8434.43 × ln(1000.0025 / 1000.59905) = −5.0288 m.
    const std::vector<FloorLevel> floors{{-1, -3.5, true}, {0, 0.0, true}, {1, 3.5, true}};
    const double drifted = 1000.6;
    const double up = drifted * kUp35 / kGround;  // the same 3.5 m above the drifted ground
    BaroFloor bf(floors);
    const auto tr = run(bf, {{0, kGround}, {600, drifted}, {612, up}, {650, up}}, {{1.0, 0}});
    EXPECT_NEAR(tr.height_at(600.0), -5.0288, 0.002);  // the raw height did drift
    for (double t = 1.0; t <= 600.0; t += 10.0) ASSERT_EQ(tr.floor_at(t), 0) << "t = " << t;
    EXPECT_EQ(tr.floor_at(650.0), 1);
    EXPECT_EQ(tr.changes(), 1);
}

TEST(BaroFloor, AWrongRadioVoteIsOutvoted) {
    {
        // The first vote is wrong (2), the next ones say 0: the estimate comes back to 0 and stays.
        BaroFloor bf(three_floors());
        std::vector<Vote> votes{{1.0, 2}};
        for (const auto& v : votes_every(3.0, 39.0, 2.0, 0)) votes.push_back(v);
        const auto tr = run(bf, {{0, kGround}, {40, kGround}}, votes);
        EXPECT_EQ(tr.floor_at(1.0), 2);  // one vote: all the evidence there is
        for (double t = 5.0; t <= 40.0; t += 1.0) ASSERT_EQ(tr.floor_at(t), 0) << "t = " << t;
    }
    {
        // One vote in three wrong on the ground, then after the climb to floor 1 three votes in
        // a row for floor 2: the pressure says floor 1 and the estimate stays there.
        BaroFloor bf(three_floors());
        std::vector<Vote> votes;
        int i = 0;
        for (double t = 1.0; t <= 39.0; t += 2.0, ++i) votes.push_back({t, i % 3 == 2 ? 2 : 0});
        for (double t = 60.0; t <= 64.0; t += 2.0) votes.push_back({t, 2});
        const auto tr = run(bf, {{0, kGround}, {40, kGround}, {52, kUp35}, {80, kUp35}}, votes);
        for (double t = 4.0; t <= 40.0; t += 1.0) ASSERT_EQ(tr.floor_at(t), 0) << "t = " << t;
        for (double t = 54.0; t <= 80.0; t += 1.0) ASSERT_EQ(tr.floor_at(t), 1) << "t = " << t;
    }
}

TEST(BaroFloor, AFloorNoSurveyCoversIsReachedFromPressureAndElevation) {
    // The IPIN venue's floors: 0, the mezzanine −1 at +3.2 m (no radio map) and −2 at −5.7 m.
    // The walker starts on 0, climbs 3.2 m and stays 60 s; the radio goes on naming 0 (the
    // radio cannot name −1), every 4 s.
    const std::vector<FloorLevel> floors{{0, 0.0, true}, {-1, 3.2, false}, {-2, -5.7, true}};
    BaroFloor bf(floors);
    const auto tr = run(bf, {{0, kGround}, {40, kGround}, {50, kUp32}, {110, kUp32}}, votes_every(2.0, 110.0, 4.0, 0));
    EXPECT_EQ(tr.floor_at(39.0), 0);
    for (double t = 52.0; t <= 110.0; t += 1.0) ASSERT_EQ(tr.floor_at(t), -1) << "t = " << t;
    EXPECT_NEAR(tr.height_at(110.0), 3.2, 0.01);
}

TEST(BaroFloor, AKnownStartFloorNeedsNoVote) {
    BaroFloor bf(three_floors(), {}, 1);
    // Starting on floor 1 (3.5 m), a 3.5 m climb ends on floor 2.
    const auto tr = run(bf, {{0, kGround}, {20, kGround}, {32, kUp35}, {50, kUp35}}, {});
    EXPECT_EQ(tr.floor_at(0.0), 1);
    EXPECT_EQ(tr.floor_at(50.0), 2);
}

TEST(BaroFloor, BadSetupsAreRefused) {
    using Floors = std::vector<FloorLevel>;
    EXPECT_THROW(BaroFloor(Floors{}), std::invalid_argument);
    EXPECT_THROW(BaroFloor(Floors{{0, 0.0, true}, {0, 3.0, true}}), std::invalid_argument);  // a floor twice
    EXPECT_THROW(BaroFloor(Floors{{0, NAN, true}}), std::invalid_argument);
    EXPECT_THROW(BaroFloor(three_floors(), {}, 5), std::invalid_argument);  // start floor not in the list
    BaroFloorConfig c;
    c.vote_error = 1.0;
    EXPECT_THROW(BaroFloor(three_floors(), c), std::invalid_argument);
    c = {};
    c.anchor_tau_s = 0.0;
    EXPECT_THROW(BaroFloor(three_floors(), c), std::invalid_argument);
    BaroFloor bf(three_floors());
    EXPECT_FALSE(bf.add_radio_vote(9));  // not a floor of the building: ignored
    EXPECT_EQ(bf.floor(), std::nullopt);
}

// The stairs walk of IPIN 2023 (T52 repetition 01: down and up between floors 0 and −2 five
// times, 12 landmarks), from its pressure and its start floor (the first landmark's, 0) alone.
// Tolerance: none on the floor (every landmark right); the height at each landmark within
// 1.5 m of its floor's elevation (0 m, −5.7 m; the README: ≤ 0.16 hPa ≈ 1.4 m of wander on a floor).
TEST(BaroFloorData, TheStairsWalkLandmarksFloorsFromPressureAndTheStartFloor) {
    const std::string file =
        std::string(LOCUS_DATA_DIR) + "/ipin2023/trials/IPIN2023_T3_TrainingTrial52_repetition01.txt";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not found: the shared data folder is absent";
    const auto log = locus::datasets::ipin::read_log(file);
    const auto pressure = locus::datasets::ipin::pressure_series(log);
    ASSERT_GT(pressure.size(), 1000u);
    ASSERT_EQ(log.posi.size(), 12u);
    const std::vector<FloorLevel> floors{{0, 0.0, true}, {-1, 3.2, false}, {-2, -5.7, true}};
    BaroFloor bf(floors, {}, log.posi.front().floor);
    std::size_t next = 0;
    int right = 0;
    for (const auto& posi : log.posi) {
        while (next < pressure.size() && pressure[next].t_s <= posi.app_s) {
            bf.add_pressure(pressure[next].t_s, pressure[next].hpa);
            ++next;
        }
        const double elevation = posi.floor == 0 ? 0.0 : -5.7;
        EXPECT_EQ(bf.floor(), posi.floor) << "landmark at " << posi.app_s << " s";
        EXPECT_NEAR(bf.height_m(), elevation, 1.5) << "landmark at " << posi.app_s << " s";
        if (bf.floor() == posi.floor) ++right;
    }
    EXPECT_EQ(right, 12);
}

// Every walk of the folder (36 on one floor, the stairs walk), pressure and start floor alone:
// no false floor change on a single-floor walk (their heights wander ≤ ±1.2 m, less than the
// 1.6 m + 0.5 m hysteresis to the mezzanine), every landmark's floor right. About a second.
TEST(BaroFloorData, EveryWalksLandmarksFloorsFromPressureAndTheStartFloor) {
    const std::string dir = std::string(LOCUS_DATA_DIR) + "/ipin2023/trials";
    if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << dir << " not found: the shared data folder is absent";
    const std::vector<FloorLevel> floors{{0, 0.0, true}, {-1, 3.2, false}, {-2, -5.7, true}};
    int walks = 0, landmarks = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".txt") continue;
        const auto log = locus::datasets::ipin::read_log(entry.path().string());
        const auto pressure = locus::datasets::ipin::pressure_series(log);
        ASSERT_FALSE(log.posi.empty()) << entry.path();
        BaroFloor bf(floors, {}, log.posi.front().floor);
        std::size_t next = 0;
        for (const auto& posi : log.posi) {
            for (; next < pressure.size() && pressure[next].t_s <= posi.app_s; ++next)
                bf.add_pressure(pressure[next].t_s, pressure[next].hpa);
            EXPECT_EQ(bf.floor(), posi.floor) << entry.path().filename() << " landmark at " << posi.app_s << " s";
            ++landmarks;
        }
        ++walks;
    }
    EXPECT_EQ(walks, 37);
    EXPECT_EQ(landmarks, 528);
}

}  // namespace
}  // namespace fusion_baro_floor_test
