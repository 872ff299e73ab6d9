#pragma once
// Bonjorn López 2016's close-range acoustic ranging (its section 5, after BeepBeep): both phones record
// while each plays one linear up-chirp; each finds both chirps in its own recording with a
// matched filter and counts the samples between them. Sample counts on each phone's own clock
// only, so clock offsets and the delay between "play" and the sound leaving the speaker cancel:
//   d = v/2 · ((n_remote − n_own)_A + (n_remote − n_own)_B) / f_s     (Bonjorn López 2016 eq. 5.1, 5.2)
// Pure code: the app supplies PCM samples and exchanges the two counts over its link.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace locus::relative {

struct ChirpParams {
    // The thesis's chirp: 13–18 kHz (nearly inaudible), 44.1 kHz, 1500 samples (34 ms).
    double f0 = 13000.0;
    double f1 = 18000.0;
    double sample_rate = 44100.0;
    std::size_t samples = 1500;
};

inline constexpr double kSpeedOfSound = 343.0;  // m/s in air at 20 °C

// The chirp's value at time t (s) from its start, 0 outside [0, duration). The phase is the
// integral of f(t) = f0 + k·t (Bonjorn López 2016 eq. 5.4); the thesis's per-sample
// sin(2π f_k k/f_s) would sweep to 2·f1 − f0 instead.
double chirp_at(const ChirpParams& p, double t);
// The chirp as samples, amplitude 1.
std::vector<double> chirp(const ChirpParams& p);
// The chirp as 16-bit PCM at `amplitude` (≤ 32767), what the app plays.
std::vector<std::int16_t> chirp_pcm(const ChirpParams& p, double amplitude = 30000.0);

// Matched-filter output: y[n] = Σ_k x[n + k]·s[k] for every n where the template fits
// (Bonjorn López 2016 eq. 5.25, real signals).
std::vector<double> matched_filter(std::span<const double> recording, std::span<const double> templ);

struct Detection {
    std::size_t sample = 0;  // start of the chirp in the recording
    double strength = 0.0;   // |matched-filter peak|
};

// The `count` strongest chirps in `recording`, at least one chirp length apart, in time order.
// Fewer when the recording is shorter than the chirp.
std::vector<Detection> detect_chirps(std::span<const double> recording, const ChirpParams& p, std::size_t count = 2);
std::vector<Detection> detect_chirps(std::span<const std::int16_t> recording, const ChirpParams& p,
                                     std::size_t count = 2);

// One phone's share of a two-way exchange: where its own chirp and the other's start in its
// recording. Its own is the louder one (its speaker is centimetres from its microphone).
struct TwoWayCounts {
    double own = 0.0;
    double remote = 0.0;
};
// The counts from a recording holding both chirps; false when fewer than two were found.
bool own_and_remote(std::span<const double> recording, const ChirpParams& p, TwoWayCounts& out);

// The distance (m) from both phones' counts. `self_a`/`self_b` are each phone's speaker-to-
// microphone distance (m), which BeepBeep adds back; the thesis takes them as 0.
double two_way_distance(const TwoWayCounts& a, const TwoWayCounts& b, double sample_rate,
                        double speed_of_sound = kSpeedOfSound, double self_a = 0.0, double self_b = 0.0);

}  // namespace locus::relative
