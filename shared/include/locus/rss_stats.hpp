#pragma once
// Per-AP RSS aggregate (docs/spec.md §3.3): mean, population variance and sample count, merged
// exactly with Chan et al.'s parallel form of Welford's algorithm so that two uploads
// combine to what a single upload of all their samples would give, in any order.
#include <cstdint>
#include <span>

namespace locus {

// The largest sample or scan count stored for an AP or an RP: 2^53, the last count a double
// (the merge's weights) still holds exactly. Uploads that would pass it are refused, so every
// stored count can be exported and imported again.
inline constexpr std::int64_t kMaxCount = std::int64_t{1} << 53;

struct RssStats {
    double mean = 0.0;
    double variance = 0.0;  // population variance, dBm²
    std::int64_t count = 0;

    void add(double sample);
    void merge(const RssStats& other);
    // Whether merge(other) keeps the count within kMaxCount, where writes are refused.
    bool can_merge(const RssStats& other) const;
    static RssStats of(std::span<const double> samples);
};

RssStats merged(RssStats a, const RssStats& b);

}  // namespace locus
