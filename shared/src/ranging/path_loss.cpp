#include "locus/ranging/path_loss.hpp"

#include <algorithm>
#include <cmath>

namespace locus::ranging {

double rss_at(const PathLoss& m, double d) { return m.tx_power - 10.0 * m.exponent * std::log10(std::max(d, kMinRange)); }

double range_of(const PathLoss& m, double rss) { return std::pow(10.0, (m.tx_power - rss) / (10.0 * m.exponent)); }

double horizontal(double slant, double dz) { return slant > std::fabs(dz) ? std::sqrt(slant * slant - dz * dz) : 0.0; }

}  // namespace locus::ranging
