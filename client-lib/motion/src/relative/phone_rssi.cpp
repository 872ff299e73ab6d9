#include "locus/motion/relative/phone_rssi.hpp"

#include <numeric>
#include <stdexcept>

namespace locus::relative {

double phone_distance(const PhoneLink& link, double rssi_dbm) { return ranging::range_of(link.model, rssi_dbm); }

double phone_distance(const PhoneLink& link, std::span<const double> rssi_dbm) {
    if (rssi_dbm.empty()) throw std::invalid_argument("phone_distance: no RSSI readings");
    const double mean = std::accumulate(rssi_dbm.begin(), rssi_dbm.end(), 0.0) / double(rssi_dbm.size());
    return phone_distance(link, mean);
}

}  // namespace locus::relative
