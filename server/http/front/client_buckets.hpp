#pragma once
// Token buckets kept per client (docs/deploy.md "Per-client limits"): each client may spend
// `burst` requests (or bytes, or localizations: whatever a token stands for) at once and then
// `rate` a second. Pure bookkeeping: the caller passes the
// time (seconds on a steady clock), so tests drive it without sleeping, and locks it.
//
// Memory is bounded whatever the number of clients: at most `capacity` buckets are held. A
// client not held has a full bucket, so a bucket is dropped as soon as it would be full again,
// and when the table is full the bucket idle longest goes first (a least-recently-used list).
// Dropping one only hands that client a full bucket: with the default capacity a client must
// wait behind 65,536 other clients' requests for that to happen.
//
// Cost: take() is O(1) expected (one hash lookup, a list splice, at most one eviction);
// the table holds some 220 bytes per bucket, its key's two copies included (about 15 MB at
// the default capacity).
#include <cstddef>
#include <list>
#include <string>
#include <unordered_map>

namespace locus::http {

class ClientBuckets {
public:
    // rate > 0 (tokens a second), burst >= 1 (the bucket's size), capacity >= 1 (buckets held).
    ClientBuckets(double rate, double burst, std::size_t capacity);

    struct Verdict {
        bool allowed = true;
        double wait_s = 0;  // refused: seconds until a token is there again
    };
    // Spends `cost` of `client`'s tokens at time `now`, or says how long until they are there.
    // A cost above the burst is allowed on a full bucket and leaves it in debt (negative), so
    // a batch of many is admitted but the client's average rate stays `rate`.
    Verdict take(const std::string& client, double now, double cost = 1);

    std::size_t size() const { return lru_.size(); }
    std::size_t capacity() const { return capacity_; }
    double rate() const { return rate_; }
    double burst() const { return burst_; }

private:
    struct Bucket {
        std::string client;
        double tokens = 0;  // at `at`
        double at = 0;
    };
    using List = std::list<Bucket>;  // most recently used first
    double rate_, burst_;
    std::size_t capacity_;
    List lru_;
    std::unordered_map<std::string, List::iterator> index_;
};

}  // namespace locus::http
