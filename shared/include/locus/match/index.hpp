#pragma once
// Immutable in-memory index of one radio map or of a whole map: an inverted index from AP
// to the RPs that store it, in contiguous arrays, so a query touches only the RPs it
// shares an AP with. Built once from the stored RPs; on a write the owner builds a new
// one and swaps it in (building 933 UJIIndoorLoc RPs takes a few milliseconds).
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/radio_map.hpp"

namespace locus::match {

// An RP with the labels a whole-map index needs to answer a building and a floor.
struct IndexedRp {
    ReferencePoint rp;
    long long floor_id = 0;
    long long building_id = 0;
};

// Fixed per index because the precomputed per-RP sums depend on them.
struct IndexParams {
    // The value an AP heard on one side only stands for (docs/spec.md §4.7: -100 dBm); RSS
    // below it counts as not heard by knn/wknn.
    double missing_rss = -100.0;
    double exponential_alpha = 24.0;          // exponential representation: exp(pos/α)
    // powed representation: (pos/|missing|)^β. Torres-Sospedra use e; β = 2 did slightly
    // better on the tuning users (2, 4, …, 18) of UJIIndoorLoc (docs/matchers.md).
    double powed_beta = 2.0;
    // Detection rates count/scans are clamped into [min_detection, 1 - min_detection] so a
    // single contrary observation never makes a likelihood zero.
    double min_detection = 0.05;  // tuned on the tuning users (2, 4, …, 18) of UJIIndoorLoc
    // knn/wknn compare the RP's expected representation, detection rate × rep(mean), i.e.
    // the average fingerprint with "not heard" scans counted as 0, instead of rep(mean).
    bool expected_representation = true;
};

struct RpInfo {
    long long id = 0;
    Point at;
    long long floor_id = 0;
    long long building_id = 0;
    std::uint32_t ap_count = 0;
};

// Gaussian-model terms of one (AP, RP) pair, read by bayes only.
struct LikelihoodTerms {
    double variance = 0.0;      // dBm², as stored
    double log_variance = 0.0;  // log(variance), or -inf when it is 0
    double log_detect = 0.0;    // log of the clamped detection rate
    double log_miss = 0.0;      // log(1 - clamped detection rate)
};

// One AP's posting list: parallel arrays with one entry per RP storing the AP, in RP order.
// Split by field so bsb/nn stream only RP positions and means (a query over UJIIndoorLoc
// walks ~3,000 postings).
struct PostingList {
    std::span<const std::uint32_t> rp;  // position of the RP in the index, not its id
    std::span<const double> mean;       // dBm
    std::span<const double> rep[3];     // mean in each Representation, by its enum value
    std::span<const LikelihoodTerms> likelihood;
    std::size_t size() const { return rp.size(); }
};

class Index {
public:
    static Index build(const std::vector<IndexedRp>& rps, const IndexParams& params = {});

    std::size_t size() const { return rps_.size(); }
    bool empty() const { return rps_.empty(); }
    std::size_t ap_count() const { return offsets_.size() - 1; }
    const IndexParams& params() const { return params_; }
    const RpInfo& rp(std::size_t i) const { return rps_[i]; }

    // Position of an AP in the index, or -1 if no RP stores it. `bssid` must be normalised.
    long ap_of(std::string_view type, std::string_view bssid) const;
    // The same with std::hash<std::string_view> of the bssid already known (QueryAp has it),
    // so a query hashes each AP once.
    long ap_of(std::string_view type, std::string_view bssid, std::size_t bssid_hash) const;
    PostingList postings(std::size_t ap) const;
    // Position of the RP storing the AP with the strongest mean (the first such RP on a tie):
    // where the AP most likely is, floor included.
    std::uint32_t strongest_rp(std::size_t ap) const { return strongest_rp_[ap]; }

    // Per RP, over all its stored APs, for fast distances with missing-AP handling:
    // Σ rep and Σ rep² per Representation, and Σ log(1 - detection).
    double rep_sum(std::size_t rp, int representation) const { return rep_sum_[rp * 3 + representation]; }
    double rep_sq_sum(std::size_t rp, int representation) const { return rep_sq_sum_[rp * 3 + representation]; }
    double log_miss_sum(std::size_t rp) const { return log_miss_sum_[rp]; }

    // Heap bytes the index holds (arrays at their capacity; the AP table estimated from its
    // node and bucket counts), for the memory cost per RP.
    std::size_t memory_bytes() const;

    // RSS in a representation; the missing value (and anything below it) maps to 0.
    double represent(double rss, int representation) const;

private:
    IndexParams params_;
    std::vector<RpInfo> rps_;
    // An AP is keyed by (type, bssid) and hashed by its bssid alone, so a lookup takes a hash
    // the query computed already, and builds no std::string (transparent hash and equality).
    struct ApKey {
        std::string type, bssid;
    };
    struct ApKeyView {
        std::string_view type, bssid;
        std::size_t bssid_hash;
    };
    struct KeyHash {
        using is_transparent = void;
        std::size_t operator()(const ApKey& k) const { return std::hash<std::string_view>{}(k.bssid); }
        std::size_t operator()(const ApKeyView& k) const { return k.bssid_hash; }
    };
    struct KeyEqual {
        using is_transparent = void;
        template <typename A, typename B>  // ApKey or ApKeyView on either side
        bool operator()(const A& a, const B& b) const { return a.bssid == b.bssid && a.type == b.type; }
    };
    std::unordered_map<ApKey, std::uint32_t, KeyHash, KeyEqual> ap_ids_;
    std::vector<std::size_t> offsets_{0};  // AP j's postings are [offsets_[j], offsets_[j+1])
    std::vector<std::uint32_t> post_rp_;
    std::vector<double> post_mean_;
    std::vector<double> post_rep_[3];
    std::vector<LikelihoodTerms> post_likelihood_;
    std::vector<double> rep_sum_, rep_sq_sum_, log_miss_sum_;
    std::vector<std::uint32_t> strongest_rp_;
};

}  // namespace locus::match
