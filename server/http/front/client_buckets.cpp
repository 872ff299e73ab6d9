#include "http/front/client_buckets.hpp"

#include <algorithm>
#include <stdexcept>

namespace locus::http {

ClientBuckets::ClientBuckets(double rate, double burst, std::size_t capacity) : rate_(rate), burst_(burst), capacity_(capacity) {
    if (!(rate > 0) || !(burst >= 1) || capacity < 1) throw std::invalid_argument("ClientBuckets: rate > 0, burst >= 1, capacity >= 1");
}

ClientBuckets::Verdict ClientBuckets::take(const std::string& client, double now, double cost) {
    const double needed = std::min(cost, burst_);
    auto it = index_.find(client);
    double tokens = burst_;
    if (it != index_.end()) {
        const Bucket& b = *it->second;
        // A clock that went back (it is steady, but a caller's may not be) refills nothing.
        tokens = std::min(burst_, b.tokens + std::max(0.0, now - b.at) * rate_);
    }
    if (tokens < needed) {
        // Not stored again: the refill is computed from the bucket's own time, and a refused
        // request must not postpone it.
        lru_.splice(lru_.begin(), lru_, it->second);
        return {false, (needed - tokens) / rate_};
    }
    tokens -= cost;
    if (it == index_.end()) {
        if (lru_.size() >= capacity_) {
            index_.erase(lru_.back().client);
            lru_.pop_back();
        }
        lru_.push_front({client, tokens, now});
        index_.emplace(client, lru_.begin());
    } else {
        Bucket& b = *it->second;
        b.tokens = tokens;
        b.at = std::max(b.at, now);
        lru_.splice(lru_.begin(), lru_, it->second);
    }
    // Buckets that are full again hold nothing a missing one would not: drop them from the
    // idle end, so a quiet table shrinks without a sweeper.
    while (!lru_.empty() && &lru_.back() != &lru_.front()) {
        const Bucket& last = lru_.back();
        if (last.tokens + std::max(0.0, now - last.at) * rate_ < burst_) break;
        index_.erase(last.client);
        lru_.pop_back();
    }
    return {true, 0};
}

}  // namespace locus::http
