#pragma once
// Streaming step detector (SPEC §5). Feed accelerometer samples (m/s², gravity included, device
// frame) with monotonic timestamps in seconds at any rate from ~50 to ~400 Hz, regular or not;
// get a StepEvent back on the sample that completes a step.
//
// Pipeline: gravity estimate (time-constant low-pass of the raw vector) → signal = component of
// the acceleration along gravity minus |g| (or |a| − |g|) → box-averaged onto a fixed internal
// grid (so behaviour does not depend on the input rate, and high-rate noise is not aliased) →
// moving average → peak/valley detector with hysteresis (seed 001's local-extremum search),
// an adaptive amplitude threshold and timing gates.
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

// Defaults were chosen on the Oxford step-counter traces; see docs/pdr.md for the search and the
// leave-one-user-out figures. Every field is documented where the default is defined.
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

    StepDetectorConfig();
};

class StepDetector {
public:
    explicit StepDetector(const StepDetectorConfig& config = StepDetectorConfig());

    // Accelerometer sample. Samples whose time does not move forward are ignored.
    std::optional<StepEvent> push(double t_s, double ax, double ay, double az);

    // A platform step event (Android TYPE_STEP_DETECTOR, iOS CMPedometer) used instead of the
    // accelerometer: counted as a step, with the amplitude of the last detected step (or 0) so a
    // Weinberg model falls back to its caller's choice.
    StepEvent push_platform_step(double t_s);

    void reset();
    std::uint64_t steps() const { return steps_; }
    const StepDetectorConfig& config() const { return config_; }

private:
    void on_grid_value(double t, double v, std::optional<StepEvent>& out);
    void detect(double t, double y, std::optional<StepEvent>& out);

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
    double last_step_t_ = -1e300;
    double last_amplitude_ = 0.0;
};

}  // namespace locus::pdr
