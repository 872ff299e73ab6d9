#pragma once
// A phone's steps as the evaluations on real walks see them (`locus eval walks` on PUTMC,
// `locus eval ipin`): client-lib's step detector and Weinberg length over the accelerometer,
// each step pointing where the phone's compass pointed when the step was taken, and known
// from when the detector confirmed it (a bout confirms several steps at once). Cost: one pass
// over the accelerometer samples, O(log n) per step for its azimuth.
#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/motion/pdr/step_detector.hpp"
#include "locus/motion/pdr/step_length.hpp"

namespace locus::tools {

// A detected step, in the phone's compass frame.
struct PhoneStep {
    double t_s = 0.0;          // when the detector confirmed it (what the phone knows when)
    double length_m = 0.0;     // Weinberg
    double azimuth_rad = 0.0;  // the compass azimuth at the step's own time
};

// The sample of a time-ordered, non-empty series in force at t: the last at or before t, else
// the first. `time_of(sample)` is a sample's time.
template <typename Series, typename TimeOf>
const auto& sample_at(const Series& series, double t, TimeOf time_of) {
    auto it = std::upper_bound(series.begin(), series.end(), t, [&](double v, const auto& s) { return v < time_of(s); });
    return it == series.begin() ? *it : *(it - 1);
}

// Every step of `acc` (samples in time order, up to `until_s`). `accel(sample)` gives the
// sample's {t_s, x, y, z} (m/s², gravity included); `azimuth_at(t)` the compass azimuth in
// force at t.
template <typename Samples, typename Accel, typename AzimuthAt>
std::vector<PhoneStep> detect_phone_steps(const Samples& acc, Accel accel, AzimuthAt azimuth_at, double until_s = INFINITY) {
    pdr::StepDetector detector;
    const pdr::StepLengthModel length;
    std::vector<PhoneStep> out;
    for (const auto& s : acc) {
        const auto [t_s, x, y, z] = accel(s);
        if (t_s > until_s) break;
        auto e = detector.push(t_s, x, y, z);
        while (e) {
            out.push_back({t_s, length.length(*e), azimuth_at(e->t_s)});
            e = detector.poll();
        }
    }
    return out;
}

}  // namespace locus::tools
