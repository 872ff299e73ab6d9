#include "locus/match/device_offset.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace locus::match {

DeviceOffset::DeviceOffset(const DeviceOffsetConfig& config) : config_(config) {
    if (config.min_shared_aps < 1) throw std::invalid_argument("min_shared_aps must be at least 1");
    if (!(config.prior_scans >= 0.0)) throw std::invalid_argument("prior_scans must be at least 0");
    if (!(config.max_abs_db > 0.0)) throw std::invalid_argument("max_abs_db must be positive");
}

bool DeviceOffset::add(const Scan& scan, const Fingerprint& placed_at) {
    std::vector<double> d;
    d.reserve(scan.size());
    for (const Reading& r : scan)
        if (const auto it = placed_at.find(r.bssid.str()); it != placed_at.end()) d.push_back(it->second - r.rss);
    if (static_cast<int>(d.size()) < config_.min_shared_aps) return false;
    const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
    std::nth_element(d.begin(), mid, d.end());
    double median = *mid;
    if (d.size() % 2 == 0) median = (median + *std::max_element(d.begin(), mid)) / 2.0;
    sum_ += median;
    ++looks_;
    return true;
}

double DeviceOffset::offset_db() const {
    if (looks_ == 0) return 0.0;
    return std::clamp(sum_ / (static_cast<double>(looks_) + config_.prior_scans), -config_.max_abs_db, config_.max_abs_db);
}

}  // namespace locus::match
