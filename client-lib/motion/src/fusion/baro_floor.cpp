#include "locus/motion/fusion/baro_floor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

namespace locus::fusion {

namespace {

constexpr double kDryAirGasConstant = 287.05;  // J/(kg·K)
constexpr double kGravity = 9.80665;           // m/s², standard gravity
constexpr double kZeroCelsius = 273.15;

bool good_pressure(double hpa) { return std::isfinite(hpa) && hpa > 0.0; }

// Median of v (reordered); v not empty.
double median(std::vector<double>& v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    if (v.size() % 2 == 1) return *mid;
    const double upper = *mid;
    const double lower = *std::max_element(v.begin(), mid);
    return 0.5 * (lower + upper);
}

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
}

}  // namespace

double hypsometric_height_m(double p_hpa, double p0_hpa, double temperature_c) {
    require(good_pressure(p_hpa) && good_pressure(p0_hpa), "pressure must be finite and positive (hPa)");
    require(std::isfinite(temperature_c) && temperature_c > -kZeroCelsius, "temperature must be above absolute zero");
    const double scale_height = kDryAirGasConstant * (temperature_c + kZeroCelsius) / kGravity;
    return scale_height * std::log(p0_hpa / p_hpa);
}

BaroHeight::BaroHeight(const BaroHeightConfig& config) : config_(config) {
    require(config.reference_s >= 0.0 && std::isfinite(config.reference_s), "reference_s must be finite and >= 0");
    require(config.median_window_s > 0.0 && std::isfinite(config.median_window_s), "median_window_s must be finite and > 0");
    require(std::isfinite(config.temperature_c) && config.temperature_c > -kZeroCelsius, "temperature must be above absolute zero");
}

void BaroHeight::add(double t_s, double hpa) {
    require(std::isfinite(t_s), "time must be finite");
    require(good_pressure(hpa), "pressure must be finite and positive (hPa)");
    require(!last_t_ || t_s >= *last_t_, "pressure samples must come in time order");
    if (!first_t_) first_t_ = t_s;
    last_t_ = t_s;

    window_t_.push_back(t_s);
    window_p_.push_back(hpa);
    // The window is (t − w, t]; the newest sample always stays.
    while (window_t_.size() > 1 && window_t_.front() <= t_s - config_.median_window_s) {
        window_t_.pop_front();
        window_p_.pop_front();
    }
    scratch_.assign(window_p_.begin(), window_p_.end());
    smoothed_ = median(scratch_);

    if (!reference_fixed_) {
        if (t_s - *first_t_ <= config_.reference_s) {
            reference_samples_.push_back(hpa);
            scratch_ = reference_samples_;
            reference_ = median(scratch_);
        }
        if (t_s - *first_t_ >= config_.reference_s) {
            reference_fixed_ = true;
            reference_samples_.clear();
            reference_samples_.shrink_to_fit();
        }
    }
    height_ = hypsometric_height_m(smoothed_, reference_, config_.temperature_c);
}

BaroFloor::BaroFloor(std::vector<FloorLevel> floors, const BaroFloorConfig& config, std::optional<int> start_floor)
    : floors_(std::move(floors)), config_(config), height_(config.height) {
    require(!floors_.empty(), "no floor");
    std::set<int> ids;
    for (const auto& f : floors_) {
        require(ids.insert(f.floor).second, "floor " + std::to_string(f.floor) + " given twice");
        require(std::isfinite(f.elevation_m), "floor " + std::to_string(f.floor) + ": elevation must be finite");
        if (f.radio) ++radio_floors_;
    }
    const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    require(config.vote_error > 0.0 && config.vote_error < 1.0, "vote_error must be in (0, 1)");
    require(positive(config.rest_window_s) && positive(config.anchor_tau_s) && positive(config.height_sigma_m) &&
                positive(config.height_evidence_s) && positive(config.max_lead),
            "rest_window_s, anchor_tau_s, height_sigma_m, height_evidence_s and max_lead must be > 0");
    require(std::isfinite(config.hysteresis_m) && config.hysteresis_m >= 0.0 && std::isfinite(config.rest_rise_m) &&
                config.rest_rise_m >= 0.0,
            "hysteresis_m and rest_rise_m must be >= 0");
    hyps_.resize(floors_.size());
    for (std::size_t i = 0; i < floors_.size(); ++i) {
        hyps_[i].offset_m = floors_[i].elevation_m;
        hyps_[i].at = i;
    }
    if (start_floor) {
        const auto it = std::find_if(floors_.begin(), floors_.end(), [&](const FloorLevel& f) { return f.floor == *start_floor; });
        require(it != floors_.end(), "start floor " + std::to_string(*start_floor) + " is not one of the floors");
        for (std::size_t i = 0; i < floors_.size(); ++i)
            hyps_[i].log_weight = (static_cast<std::ptrdiff_t>(i) == it - floors_.begin()) ? 0.0 : -config_.max_lead;
        decided_ = true;
    }
}

std::size_t BaroFloor::nearest(double z, std::size_t current) const {
    std::size_t best = current;
    double best_d = std::abs(z - floors_[current].elevation_m);
    for (std::size_t j = 0; j < floors_.size(); ++j) {
        const double d = std::abs(z - floors_[j].elevation_m);
        if (d < best_d) {
            best_d = d;
            best = j;
        }
    }
    // Hysteresis: the current floor is kept unless the nearest one beats it by the margin.
    if (best != current && best_d + config_.hysteresis_m >= std::abs(z - floors_[current].elevation_m)) return current;
    return best;
}

bool BaroFloor::at_rest() const {
    if (recent_t_.size() < 2 || recent_t_.back() - recent_t_.front() < 0.75 * config_.rest_window_s) return false;
    const auto [lo, hi] = std::minmax_element(recent_h_.begin(), recent_h_.end());
    return *hi - *lo < config_.rest_rise_m;
}

void BaroFloor::clamp_weights() {
    double best = -std::numeric_limits<double>::infinity();
    for (const auto& h : hyps_) best = std::max(best, h.log_weight);
    // Renormalised so that the best is 0: the weights never run off to −∞ over a long walk.
    for (auto& h : hyps_) h.log_weight = std::max(h.log_weight - best, -config_.max_lead);
}

void BaroFloor::add_pressure(double t_s, double hpa) {
    const auto previous_t = height_.last_t();
    height_.add(t_s, hpa);
    const double h = height_.height_m();
    recent_t_.push_back(t_s);
    recent_h_.push_back(h);
    while (recent_t_.size() > 1 && recent_t_.front() < t_s - config_.rest_window_s) {
        recent_t_.pop_front();
        recent_h_.pop_front();
    }
    const double dt = previous_t ? t_s - *previous_t : 0.0;
    const bool rest = at_rest() && dt > 0.0;
    const double pull = rest ? 1.0 - std::exp(-dt / config_.anchor_tau_s) : 0.0;
    const double look = rest ? dt / config_.height_evidence_s : 0.0;
    const double inv_var = 1.0 / (config_.height_sigma_m * config_.height_sigma_m);
    for (auto& hyp : hyps_) {
        const double z = hyp.offset_m + h;
        hyp.at = nearest(z, hyp.at);
        if (!rest) continue;
        const double misfit = z - floors_[hyp.at].elevation_m;
        hyp.log_weight -= 0.5 * misfit * misfit * inv_var * look;
        hyp.offset_m -= misfit * pull;
    }
    if (rest) clamp_weights();
}

bool BaroFloor::add_radio_vote(int floor) {
    const auto it = std::find_if(floors_.begin(), floors_.end(), [&](const FloorLevel& f) { return f.floor == floor; });
    if (it == floors_.end()) return false;
    decided_ = true;
    if (radio_floors_ < 2 || !it->radio) return true;  // a vote that cannot be wrong, or for a floor the radio lacks
    const double agree = std::log(1.0 - config_.vote_error);
    const double disagree = std::log(config_.vote_error / static_cast<double>(radio_floors_ - 1));
    const double uninformative = std::log(1.0 / static_cast<double>(radio_floors_));
    for (auto& hyp : hyps_) {
        const auto& now = floors_[hyp.at];
        hyp.log_weight += !now.radio ? uninformative : (now.floor == floor ? agree : disagree);
    }
    clamp_weights();
    return true;
}

std::optional<int> BaroFloor::floor() const {
    if (height_.empty() || !decided_) return std::nullopt;
    std::size_t best = 0;
    for (std::size_t i = 1; i < hyps_.size(); ++i)
        if (hyps_[i].log_weight > hyps_[best].log_weight) best = i;
    return floors_[hyps_[best].at].floor;
}

std::vector<double> BaroFloor::start_probabilities() const {
    std::vector<double> p(hyps_.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < hyps_.size(); ++i) sum += (p[i] = std::exp(hyps_[i].log_weight));
    for (auto& v : p) v /= sum;
    return p;
}

}  // namespace locus::fusion
