#pragma once
// Streaming step detector (docs/spec.md §5.2). Feed accelerometer samples (m/s², gravity included, device
// frame) with monotonic timestamps in seconds at any rate from ~50 to ~400 Hz, regular or not;
// get a StepEvent back on the sample that completes a step.
//
// Pipeline: gravity estimate (time-constant low-pass of the raw vector) → signal = component of
// the acceleration along gravity minus |g| (or |a| − |g|) → box-averaged onto a fixed internal
// grid (so behaviour does not depend on the input rate, and high-rate noise is not aliased) →
// moving average → peak/valley detector with hysteresis (Bonjorn López 2016's local-extremum search),
// an adaptive amplitude threshold and timing gates → cadence gate: a walking bout is confirmed
// only after a few regularly spaced candidates (then all of them are reported, with their own
// times), and within a bout a candidate far too soon after the last step is dropped. This is
// what keeps a purse swinging after the user stops, or a double bump within one slow step, from
// counting. Confirmed steps are therefore reported with a delay of up to bout_steps steps at
// the start of a bout, and immediately afterwards.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace locus::pdr {

struct StepEvent {
    double t_s = 0.0;    // time of the valley that completed the step
    double a_max = 0.0;  // peak of the filtered signal in the step (m/s², gravity removed)
    double a_min = 0.0;  // valley of the filtered signal in the step
    double amplitude() const { return a_max - a_min; }  // Amax − Amin for Weinberg
};

enum class StepSignal {
    vertical,   // projection on the low-passed gravity direction, minus |g|
    magnitude,  // |a| − |g|; needs no orientation at all
};

// Tuned defaults. Chosen by `locus pdr tune-oxford`: a grid search (6,624 settings) scored by the
// mean absolute step-count error over the 48 Oxford optimisation traces; these are the best
// setting on all 48 (1.25 %), and leave-one-user-out over the same grid gives 1.69 % (docs/pdr.md).
// Constants not in the search keep a physical or docs/spec.md §5.2 value.
inline constexpr StepSignal kDefaultSignal = StepSignal::magnitude;  // beat vertical by < 0.1 %: no orientation needed
inline constexpr double kDefaultSmoothingS = 0.06;
inline constexpr double kDefaultMinThreshold = 0.6;     // m/s²
inline constexpr double kDefaultThresholdFactor = 0.2;
inline constexpr double kDefaultHysteresis = 0.25;
inline constexpr int kDefaultBoutSteps = 6;
inline constexpr double kDefaultCadenceMinRatio = 0.7;
inline constexpr double kDefaultCadenceMaxRatio = 1.7;
inline constexpr double kDefaultMinStepIntervalS = 0.25;  // docs/spec.md §5.2 (0.30 lost in an earlier search)
inline constexpr double kDefaultGridHz = 100.0;           // steps are < 3 Hz; 50 Hz input is interpolated
inline constexpr double kDefaultGravityTauS = 1.0;        // other values tried: docs/pdr.md
inline constexpr double kDefaultRmsTauS = 2.0;            // the same
// Peak-to-valley window: 50–600 ms, not docs/spec.md §5.2's 150–400 ms (measurements: docs/pdr.md).
inline constexpr double kDefaultMinPeakToValleyS = 0.05;
inline constexpr double kDefaultMaxPeakToValleyS = 0.6;
inline constexpr double kDefaultMaxGapS = 0.5;
inline constexpr double kDefaultBoutRegularity = 1.5;
inline constexpr double kDefaultMaxStepIntervalS = 2.0;   // a longer pause is not walking

// Every field's meaning is given beside it; defaults are the constants above.
struct StepDetectorConfig {
    StepSignal signal;
    double grid_hz;               // internal resampling rate
    double smoothing_s;           // moving-average window on the resampled signal
    double gravity_tau_s;         // time constant of the gravity low-pass
    double min_threshold;         // m/s²: peak must exceed +T and valley fall below −T, T ≥ this
    double threshold_factor;      // T = max(min_threshold, factor · running RMS of the signal)
    double rms_tau_s;             // time constant of that running RMS
    double hysteresis;            // fraction of T the signal must retreat to confirm an extremum
    double min_peak_to_valley_s;  // timing gate between a peak and the valley that completes it
    double max_peak_to_valley_s;
    double min_step_interval_s;   // at most one step per this interval
    double max_gap_s;             // a longer hole in the timestamps restarts the filters
    // Cadence gate (bout_steps ≤ 1 turns it off: every candidate is a step).
    // Regularity is judged on strides (t_i − t_{i−2}), see step_detector.cpp.
    int bout_steps;               // regular candidates needed to start a walking bout
    double bout_regularity;       // max/min stride ratio allowed among them
    double cadence_min_ratio;     // within a bout, drop a candidate whose stride < this × cadence
    double cadence_max_ratio;     // a longer stride ends the bout
    double max_step_interval_s;   // and so does a pause longer than this

    StepDetectorConfig();
};

class StepDetector {
public:
    explicit StepDetector(const StepDetectorConfig& config = StepDetectorConfig());

    // Accelerometer sample. Samples whose time does not move forward are ignored. Returns one
    // confirmed step, oldest first; when a bout is confirmed several steps are due at once and
    // come out on the following calls (or through poll()).
    std::optional<StepEvent> push(double t_s, double ax, double ay, double az);
    // Next confirmed step not yet returned, without a new sample (e.g. at the end of a log).
    std::optional<StepEvent> poll();

    // A platform step event (Android TYPE_STEP_DETECTOR, iOS CMPedometer) used instead of the
    // accelerometer: counted as a step, with the amplitude of the last detected step (or 0) so a
    // Weinberg model falls back to its caller's choice.
    StepEvent push_platform_step(double t_s);

    void reset();
    // Confirmed steps so far, including those not yet returned by push()/poll().
    std::uint64_t steps() const { return steps_; }
    const StepDetectorConfig& config() const { return config_; }

private:
    void on_grid_value(double t, double v);
    void detect(double t, double y);
    void candidate(const StepEvent& e);
    void confirm(const StepEvent& e);
    double cadence() const;

    StepDetectorConfig config_;
    std::uint64_t steps_ = 0;

    // Gravity and signal.
    bool started_ = false;
    double last_t_ = 0.0;
    double gx_ = 0.0, gy_ = 0.0, gz_ = 0.0;
    double last_s_ = 0.0;

    // Box-average resampler onto the grid.
    double grid_dt_ = 0.0;
    double bin_end_ = 0.0;
    double bin_area_ = 0.0;

    // Moving average over the grid.
    std::vector<double> ring_;
    std::size_t ring_pos_ = 0;
    std::size_t ring_fill_ = 0;
    double ring_sum_ = 0.0;

    // Detector.
    double ms_ = 0.0;  // running mean square of the smoothed signal
    enum class Phase { seek_peak, seek_valley } phase_ = Phase::seek_peak;
    double ext_ = 0.0;       // running extremum in the current phase
    double ext_t_ = 0.0;
    double peak_ = 0.0;
    double peak_t_ = 0.0;
    double last_candidate_t_ = -1e300;
    double last_amplitude_ = 0.0;

    // Cadence gate. Fixed-capacity rings: no allocation per sample or per step.
    static constexpr std::size_t kMaxBout = 16;
    static constexpr std::size_t kCadenceHistory = 5;
    bool walking_ = false;
    StepEvent bout_[kMaxBout];
    std::size_t bout_n_ = 0;
    double last_step_t_ = -1e300;
    double prev_step_t_ = -1e300;
    double intervals_[kCadenceHistory] = {};
    std::size_t intervals_n_ = 0;
    std::size_t intervals_pos_ = 0;
    StepEvent due_[2 * kMaxBout];
    std::size_t due_head_ = 0;
    std::size_t due_n_ = 0;
};

}  // namespace locus::pdr
