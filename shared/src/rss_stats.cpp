#include "locus/rss_stats.hpp"

namespace locus {

void RssStats::add(double sample) { merge(RssStats{sample, 0.0, 1}); }

void RssStats::merge(const RssStats& other) {
    if (other.count <= 0) return;
    if (count <= 0) {
        *this = other;
        return;
    }
    const double na = static_cast<double>(count);
    const double nb = static_cast<double>(other.count);
    const double n = na + nb;
    const double delta = other.mean - mean;
    // Work with sums of squared deviations (M2) so the merge is exact, then back to variance.
    const double m2 = variance * na + other.variance * nb + delta * delta * na * nb / n;
    mean += delta * nb / n;
    variance = m2 / n;
    if (variance < 0.0) variance = 0.0;  // rounding can dip a hair below zero
    count += other.count;
}

bool RssStats::can_merge(const RssStats& other) const {
    const std::int64_t a = count > 0 ? count : 0, b = other.count > 0 ? other.count : 0;  // merge ignores an empty side
    return a <= kMaxCount && b <= kMaxCount - a;
}

RssStats RssStats::of(std::span<const double> samples) {
    RssStats s;
    for (double v : samples) s.add(v);
    return s;
}

RssStats merged(RssStats a, const RssStats& b) {
    a.merge(b);
    return a;
}

}  // namespace locus
