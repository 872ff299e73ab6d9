#include "locus/motion/fusion/heading_alignment.hpp"

#include <cmath>

namespace locus::fusion {

HeadingAlignment::HeadingAlignment(const HeadingAlignmentConfig& config) : config_(config) {}

void HeadingAlignment::add_step(double length_m, double azimuth_rad) {
    pdr_[0] += std::polar(length_m, azimuth_rad);
    pdr_[1] += std::polar(length_m, -azimuth_rad);
}

void HeadingAlignment::add_fix(Point at) {
    const std::complex<double> w_now(at.y, at.x);
    const std::size_t n = fix_at_.size();
    for (std::size_t lag = 1; lag <= n; ++lag) {
        const std::size_t j = n - lag;
        const std::complex<double> w = w_now - fix_at_[j];
        const std::complex<double> p0 = pdr_[0] - pdr_at_fix_[0][j], p1 = pdr_[1] - pdr_at_fix_[1][j];
        if (std::abs(p0) < config_.min_pdr_m) continue;
        cross_[0] += w * std::conj(p0);
        cross_[1] += w * std::conj(p1);
        ww_ += std::norm(w);
        pp_[0] += std::norm(p0);
        pp_[1] += std::norm(p1);
        ++pairs_;
    }
    fix_at_.push_back(w_now);
    pdr_at_fix_[0].push_back(pdr_[0]);
    pdr_at_fix_[1].push_back(pdr_[1]);
    if (static_cast<int>(fix_at_.size()) > config_.max_lag) {
        fix_at_.pop_front();
        pdr_at_fix_[0].pop_front();
        pdr_at_fix_[1].pop_front();
    }
    refit();
}

void HeadingAlignment::refit() {
    if (pairs_ < config_.min_pairs) return;
    double corr[2];
    for (int s = 0; s < 2; ++s) corr[s] = pp_[s] > 0.0 && ww_ > 0.0 ? std::abs(cross_[s]) / std::sqrt(ww_ * pp_[s]) : 0.0;
    const int s = corr[1] > corr[0] ? 1 : 0;
    mirrored_ = s == 1;
    offset_ = std::arg(cross_[s]);
    correlation_ = corr[s];
    scale_ = pp_[s] > 0.0 ? std::abs(cross_[s]) / pp_[s] : 1.0;
}

}  // namespace locus::fusion
