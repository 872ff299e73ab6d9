#pragma once
// The rotation (and possible mirror) between the phone's compass frame and the floor's, learnt
// from the WiFi fixes as they come, for buildings whose plan is not drawn north-up and where
// nobody measured north_offset_deg. The PDR track between two fixes is a chain of steps at
// compass azimuths ψ; on the floor the same chain runs at θ = φ + sψ (s = +1, or −1 when the
// plan is mirrored against east-north-up, as a drawing whose y axis points down is). Each
// pair of fixes a few scans apart gives a WiFi displacement w; the PDR displacement p_s over
// the same time is known for both s. Written as complex numbers (y + ix, so that the angle is
// the clockwise azimuth), the least-squares φ for a given s is arg Σ w·conj(p_s), and the s
// whose PDR displacements correlate better with the fixes' (|Σ w·conj p_s| / √(Σ|w|² Σ|p_s|²))
// is chosen. WiFi displacements are noisy, so several lags are pooled and nothing is trusted
// before min_pairs pairs. Causal: it only ever uses what was added before.
#include <complex>
#include <deque>
#include <vector>

#include "locus/geometry.hpp"

namespace locus::fusion {

struct HeadingAlignmentConfig {
    int max_lag = 3;        // fix pairs i−1..i−max_lag are pooled with fix i
    int min_pairs = 3;      // below this, offset 0 and no mirror are assumed
    double min_pdr_m = 2.0; // a pair whose PDR moved less than this says nothing about direction
};

class HeadingAlignment {
public:
    explicit HeadingAlignment(const HeadingAlignmentConfig& config = {});

    // A PDR step in the compass frame: azimuth clockwise from north (rad), length (m).
    void add_step(double length_m, double azimuth_rad);
    void add_fix(Point at);

    // The step's heading in the floor frame (docs/spec.md §2.2: clockwise from +y).
    double floor_heading(double azimuth_rad) const { return offset_ + (mirrored_ ? -azimuth_rad : azimuth_rad); }
    double offset_rad() const { return offset_; }
    bool mirrored() const { return mirrored_; }
    double correlation() const { return correlation_; }  // of the chosen s, in [0, 1]
    int pairs() const { return pairs_; }
    // Distance-weighted ratio of WiFi to PDR displacement: a step-length scale hint.
    double scale() const { return scale_; }

private:
    void refit();

    HeadingAlignmentConfig config_;
    // PDR displacement since the first fix, for s = +1 and s = −1, at each fix so far.
    std::complex<double> pdr_[2];
    std::deque<std::complex<double>> pdr_at_fix_[2];
    std::deque<std::complex<double>> fix_at_;
    std::complex<double> cross_[2];  // Σ w·conj(p_s)
    double ww_ = 0.0, pp_[2] = {0.0, 0.0};
    int pairs_ = 0;
    double offset_ = 0.0;
    bool mirrored_ = false;
    double correlation_ = 0.0;
    double scale_ = 1.0;
};

}  // namespace locus::fusion
