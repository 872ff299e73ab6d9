// Bonjorn López 2016's acoustic ranging on synthetic recordings: two phones at 0.3–1.3 m, each recording
// both chirps with its own clock offset, white noise at 10 dB SNR against the remote chirp, and
// 1–5 ms between "play" and the sound actually leaving each speaker. Target: error ≤ 2 cm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "locus/motion/relative/acoustic.hpp"

namespace relative_acoustic_test {
namespace {

using namespace locus::relative;

struct Emission {
    double at;         // global time the chirp leaves the speaker (s)
    double amplitude;  // as heard by this microphone
    double delay;      // propagation (s)
};

// A recording starting at global time `start`, `n` samples, the chirps plus noise.
std::vector<double> record(const ChirpParams& p, double start, std::size_t n, const std::vector<Emission>& e,
                           double noise_sigma, std::mt19937& rng) {
    std::normal_distribution<double> noise(0.0, noise_sigma);
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double t = start + double(i) / p.sample_rate;
        double v = noise(rng);
        for (const auto& s : e) v += s.amplitude * chirp_at(p, t - s.at - s.delay);
        x[i] = v;
    }
    return x;
}

TEST(AcousticRanging, ChirpSweepsFromF0ToF1) {
    ChirpParams p;
    const auto s = chirp(p);
    ASSERT_EQ(s.size(), 1500u);
    // Zero crossings in the first and last 200 samples give the local frequency.
    auto freq = [&](std::size_t from) {
        int crossings = 0;
        for (std::size_t i = from + 1; i < from + 200; ++i) crossings += (s[i - 1] < 0) != (s[i] < 0);
        return crossings / 2.0 / (200.0 / p.sample_rate);
    };
    EXPECT_NEAR(freq(0), 13300.0, 500.0);
    EXPECT_NEAR(freq(1300), 17700.0, 500.0);
    const auto pcm = chirp_pcm(p, 1000.0);
    EXPECT_EQ(pcm.size(), 1500u);
    EXPECT_LE(*std::max_element(pcm.begin(), pcm.end()), 1000);
}

TEST(AcousticRanging, TwoWayWithin2cmAt10dBSnrAndProcessingDelay) {
    ChirpParams p;
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> delay(0.001, 0.005), clock(0.0, 0.02);
    const double v = kSpeedOfSound;
    const double self = 0.05;  // speaker to microphone on one phone
    const double duration = double(p.samples) / p.sample_rate;
    double worst = 0.0;
    for (double d = 0.3; d <= 1.3001; d += 0.1) {
        for (int trial = 0; trial < 3; ++trial) {
            // A plays at 30 ms (+ its delay); B plays once A's chirp has passed, + its delay.
            const double ta = 0.03 + delay(rng);
            const double tb = ta + duration + 0.02 + delay(rng);
            const double remote_amp = 0.1 * self / d;  // spherical spreading from the own level
            const double sigma = std::sqrt(remote_amp * remote_amp / 2.0 / 10.0);  // 10 dB SNR
            const std::size_t n = std::size_t(0.2 * p.sample_rate);
            const auto rec_a = record(p, clock(rng), n, {{ta, 0.1, self / v}, {tb, remote_amp, d / v}}, sigma, rng);
            const auto rec_b = record(p, clock(rng), n, {{ta, remote_amp, d / v}, {tb, 0.1, self / v}}, sigma, rng);
            TwoWayCounts a, b;
            ASSERT_TRUE(own_and_remote(rec_a, p, a));
            ASSERT_TRUE(own_and_remote(rec_b, p, b));
            EXPECT_LT(a.own, a.remote);  // A played first
            EXPECT_GT(b.own, b.remote);
            const double est = two_way_distance(a, b, p.sample_rate, v, self, self);
            EXPECT_NEAR(est, d, 0.02) << "at " << d << " m, trial " << trial;
            worst = std::max(worst, std::abs(est - d));
        }
    }
    RecordProperty("worst_error_m", std::to_string(worst));
}

TEST(AcousticRanging, NoChirpInATooShortRecording) {
    ChirpParams p;
    std::vector<double> short_rec(100, 0.0);
    EXPECT_TRUE(detect_chirps(short_rec, p).empty());
    TwoWayCounts c;
    EXPECT_FALSE(own_and_remote(short_rec, p, c));
}

TEST(AcousticRanging, Finds16BitPcmChirpsWhereTheyWerePlaced) {
    // What the app records: 16-bit PCM. The played chirp (chirp_pcm) at samples 500 and 4000,
    // the second at a tenth of the level, over ±300 LSB uniform noise.
    ChirpParams p;
    const auto played = chirp_pcm(p, 20000.0);
    std::vector<std::int16_t> rec(8000, 0);
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> noise(-300, 300);
    for (auto& s : rec) s = std::int16_t(noise(rng));
    for (std::size_t k = 0; k < played.size(); ++k) {
        rec[500 + k] = std::int16_t(rec[500 + k] + played[k]);
        rec[4000 + k] = std::int16_t(rec[4000 + k] + played[k] / 10);
    }
    const auto d = detect_chirps(std::span<const std::int16_t>(rec), p);
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].sample, 500u);
    EXPECT_EQ(d[1].sample, 4000u);
    EXPECT_GT(d[0].strength, 5.0 * d[1].strength);
}

}  // namespace
}  // namespace relative_acoustic_test
