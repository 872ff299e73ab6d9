#pragma once
// Floors from the barometer: a phone's pressure samples turned into a height relative to the
// walk's start, and a causal floor estimator that fuses that height with the floors'
// elevations (`elevation_m`, docs/spec.md: a floor's height above the building's reference)
// and the radio fixes' floors, which may be wrong or missing. Causal throughout: every answer
// uses only the samples and votes added before it (feed them in time order).
//
// Height (BaroHeight). The hypsometric equation of an isothermal air column,
//     h − h0 = (R_d · T / g) · ln(p0 / p),   R_d = 287.05 J/(kg·K), g = 9.80665 m/s²,
// about 8.43 km of height per unit of ln p at 15 °C, i.e. 8.6 cm per 0.01 hPa near 980 hPa
// (Wallace & Hobbs, *Atmospheric Science*, 2nd ed., 2006, §3.2.2, the hypsometric equation).
// A temperature off by 10 K scales every height by 3.5 %, far below what tells floors apart, so
// T is a setting, not a measurement. The reference p0 is the median of the walk's first
// `reference_s` seconds (until then the median so far): absolute pressure moves by hPa from day
// to day and by ~0.5 hPa from phone to phone, so only changes from a per-walk reference say
// anything about floors. Each height is computed from the median of the samples of the last
// `median_window_s` seconds, which rejects a phone's single-sample spikes and its ~0.02 hPa
// noise at the cost of about half a window of lag.
//
// Floor (BaroFloor). What the height cannot tell is which floor the walk started on; what the
// radio cannot always tell is the floor now. So the estimator keeps one hypothesis per floor,
// "the walk was on floor s at the pressure reference" — a Bayes filter over that one static
// unknown, whose weight the evidence moves:
//  - under hypothesis s the absolute height is z_s = offset_s + h, offset_s starting at s's
//    elevation; the hypothesis's floor now is the floor whose elevation is nearest z_s, left
//    only when another floor is nearer by `hysteresis_m` (no flicker half-way up a stair);
//  - a radio vote for floor f multiplies each hypothesis's weight by P(f | its floor now):
//    1 − vote_error when they agree, vote_error / (n − 1) otherwise (n floors with a radio
//    map); a floor without a radio map cannot be named by the radio, so under it a vote is
//    uninformative (1/n): a floor no survey covers is reached from pressure and elevation alone;
//  - while the height is at rest (it moved less than rest_rise_m over rest_window_s), the
//    misfit between z_s and the hypothesis's floor elevation is evidence too (a Gaussian of
//    height_sigma_m, one independent look per height_evidence_s): a hypothesis that puts the
//    walker between floors or above the roof loses;
//  - at rest, offset_s also relaxes so that z_s meets the floor's elevation (time constant
//    anchor_tau_s): weather and ventilation drift (tenths of a hPa per hour, a metre or two) is
//    absorbed between floor changes, which take seconds (stairs ~0.3 m/s, lifts ~1 m/s);
//  - log-weights are kept within max_lead of the best, so a hypothesis ruled out long ago
//    can come back if the evidence turns (bounded memory of old votes).
// The estimate is the floor now of the heaviest hypothesis. A start floor, when known (the
// competition gives its walks' first position), fixes the hypothesis instead of the votes.
//
// Cost: BaroHeight::add is O(w log w) for the w samples of the median window (about 10–20 at a
// phone's 5–10 Hz) plus O(1) amortised; BaroFloor::add_pressure adds O(F²) for F floors (each
// hypothesis finds its nearest floor; F is a building's floor count), add_radio_vote O(F),
// floor() O(F). Memory O(w + the reference window's samples + F).
#include <deque>
#include <optional>
#include <vector>

namespace locus::fusion {

// h − h0 of the hypsometric equation above: the height (m) of pressure p above the pressure p0
// (both hPa, > 0) in an isothermal column at temperature_c. Throws std::invalid_argument on a
// pressure that is not finite and positive.
double hypsometric_height_m(double p_hpa, double p0_hpa, double temperature_c = 15.0);

struct BaroHeightConfig {
    double reference_s = 5.0;      // p0: median of the samples of the walk's first seconds
    double median_window_s = 2.0;  // each height from the median of the last seconds' samples
    double temperature_c = 15.0;   // of the air column (indoor air; see above for its weight)
};

// Relative height from a pressure series. Throws std::invalid_argument on a bad config (a
// window ≤ 0), a pressure that is not finite and positive, or a time going back.
class BaroHeight {
public:
    explicit BaroHeight(const BaroHeightConfig& config = {});

    // One sample: t in seconds on any clock, non-decreasing; pressure in hPa (= mbar).
    void add(double t_s, double hpa);

    bool empty() const { return !last_t_; }
    // Height above the reference (m) as of the last sample; 0 before any.
    double height_m() const { return height_; }
    // The smoothed pressure of the last sample and the reference (hPa); 0 before any sample.
    double smoothed_hpa() const { return smoothed_; }
    double reference_hpa() const { return reference_; }
    bool reference_fixed() const { return reference_fixed_; }
    std::optional<double> last_t() const { return last_t_; }

private:
    BaroHeightConfig config_;
    std::deque<double> window_t_, window_p_;
    std::vector<double> reference_samples_;
    std::vector<double> scratch_;
    std::optional<double> first_t_, last_t_;
    double reference_ = 0.0, smoothed_ = 0.0, height_ = 0.0;
    bool reference_fixed_ = false;
};

// A floor as the estimator sees it: its id (a map's `level`, e.g. the IPIN POSI floor), its
// elevation above the building's reference (m), and whether the radio can name it (it has a
// radio map; a floor no survey covers is never a radio fix's floor).
struct FloorLevel {
    int floor = 0;
    double elevation_m = 0.0;
    bool radio = true;
};

struct BaroFloorConfig {
    BaroHeightConfig height;
    double vote_error = 0.2;         // P(a radio vote names a floor other than the true one)
    double hysteresis_m = 0.5;       // a hypothesis changes floor only when another is nearer by this
    double rest_window_s = 4.0;      // at rest: the height spanned less than rest_rise_m over this
    double rest_rise_m = 0.5;
    double anchor_tau_s = 60.0;      // at rest, drift is absorbed with this time constant
    double height_sigma_m = 1.0;     // at rest, the height's misfit to its floor's elevation
    double height_evidence_s = 10.0; // one independent height look per this many seconds at rest
    double max_lead = 20.0;          // log-weights are kept within this of the best
};

class BaroFloor {
public:
    // Throws std::invalid_argument on no floor, a floor id twice, a non-finite elevation, a
    // config outside its domain (vote_error not in (0, 1), a window, tau, sigma, evidence span
    // or lead ≤ 0, hysteresis or rise < 0), or a start_floor that is not one of `floors`.
    explicit BaroFloor(std::vector<FloorLevel> floors, const BaroFloorConfig& config = {},
                       std::optional<int> start_floor = std::nullopt);

    // A pressure sample (BaroHeight::add's contract).
    void add_pressure(double t_s, double hpa);
    // The floor a radio fix was on. A floor not in the list is ignored (returns false).
    bool add_radio_vote(int floor);

    // The estimate now: the heaviest hypothesis's floor; nullopt before any pressure sample,
    // or before the first radio vote when no start floor was given.
    std::optional<int> floor() const;
    // Each hypothesis's posterior (normalised weights), in the order of `floors`: P(the walk was
    // on floors[i] at the pressure reference).
    std::vector<double> start_probabilities() const;
    // The height above the reference (m), as BaroHeight.
    double height_m() const { return height_.height_m(); }
    const std::vector<FloorLevel>& floors() const { return floors_; }

private:
    struct Hypothesis {
        double offset_m = 0.0;  // absolute elevation of the reference pressure under it
        std::size_t at = 0;     // index into floors_ of its floor now
        double log_weight = 0.0;
    };
    std::size_t nearest(double z, std::size_t current) const;
    bool at_rest() const;
    void clamp_weights();

    std::vector<FloorLevel> floors_;
    BaroFloorConfig config_;
    BaroHeight height_;
    std::vector<Hypothesis> hyps_;
    std::deque<double> recent_t_, recent_h_;  // the rest window's heights
    std::size_t radio_floors_ = 0;
    bool decided_ = false;  // a vote or the start floor has weighed in
};

}  // namespace locus::fusion
