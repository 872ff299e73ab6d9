#pragma once
// Heading (docs/spec.md §5.4): tilt-compensated compass from low-passed gravity and field, fused with the
// gyroscope by the complementary filter (Bonjorn López 2016) θ = 0.95·(θ + ω·dt) + 0.05·θ_compass (angle
// wrap handled), then expressed in the floor frame: θ_floor = θ_magnetic − north_offset − local
// calibration. While the magnetic field is judged disturbed the compass term is dropped and the
// heading runs on the gyro alone.
#include <optional>

#include "locus/motion/pdr/compass.hpp"
#include "locus/motion/pdr/vec3.hpp"

namespace locus::pdr {

struct HeadingConfig {
    // Compass weight per 20 ms (50 Hz, docs/spec.md §5.4); at other gyro rates the weight is rescaled so
    // that the filter's time constant (≈ 0.39 s) does not depend on the rate.
    double compass_weight = 0.05;
    double input_lowpass_alpha = 0.2;   // docs/spec.md §5.4
    // Disturbance: |B| more than this fraction away from the local norm...
    double field_tolerance = 0.15;
    // ...or the compass turned by more than this many radians more/less than the gyro over
    // the last disagreement_window_s (consecutive windows; the flag clears after a window in
    // which they agree, so the compass swinging back after a disturbance is not trusted either).
    double disagreement_rad = 0.35;     // 20°
    double disagreement_window_s = 1.0;
    // Local field norm in µT; 0 = learn it from the first learn_s seconds of magnetometer data.
    double expected_field_ut = 0.0;
    double learn_s = 2.0;
    double north_offset_deg = 0.0;      // per floor, docs/spec.md §2.1
};

class HeadingEstimator {
public:
    explicit HeadingEstimator(const HeadingConfig& config = HeadingConfig());

    void push_accel(double t_s, Vec3 a);   // m/s², gravity included
    void push_mag(double t_s, Vec3 m);     // µT
    void push_gyro(double t_s, Vec3 w);    // rad/s

    // Floor-frame heading (docs/spec.md §2.2), once the compass or an explicit set_heading has given one.
    std::optional<double> heading() const;
    // Magnetic azimuth of the last compass reading, before any offset (for calibration UIs).
    std::optional<double> compass_heading() const { return compass_; }
    bool magnetic_disturbance() const { return disturbed_; }

    // Local-north calibration: the user holds the phone along a map direction of known floor
    // heading; the current discrepancy is stored and subtracted from then on.
    void calibrate_local_north(double known_floor_heading_rad);
    void set_north_offset_deg(double deg);
    // Forces the fused heading (e.g. from a map-matching or fusion step).
    void set_heading(double floor_heading_rad);

private:
    void update_compass();
    double offset_rad() const;

    HeadingConfig config_;
    LowPass3 gravity_lp_;
    LowPass3 mag_lp_;
    std::optional<double> compass_;   // magnetic azimuth
    std::optional<double> theta_;     // fused magnetic heading
    double calibration_rad_ = 0.0;
    bool disturbed_ = false;

    bool gyro_started_ = false;
    double gyro_t_ = 0.0;

    // Field-norm learning.
    double mag_t0_ = -1.0;
    double norm_sum_ = 0.0;
    long norm_n_ = 0;
    double field_norm_ = 0.0;
    bool field_bad_ = false;

    // Gyro/compass disagreement over a window.
    double window_t0_ = -1.0;
    double window_gyro_turn_ = 0.0;
    std::optional<double> window_compass0_;
    bool disagree_ = false;
};

}  // namespace locus::pdr
