#include "locus/match/index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace locus::match {

namespace {
struct Posting {
    std::uint32_t rp;
    double mean;
    double rep[3];
    LikelihoodTerms likelihood;
};
}  // namespace

double Index::represent(double rss, int representation) const {
    const double m = params_.missing_rss;
    const double pos = rss > m ? rss - m : 0.0;
    switch (representation) {
        case 0:
            return pos;
        case 1:
            // Torres-Sospedra's exp(pos/α)/exp(-m/α), shifted by its value at pos = 0 so that
            // "not heard" is exactly 0 like in the other forms; differences are unchanged.
            return (std::exp(pos / params_.exponential_alpha) - 1.0) / std::exp(-m / params_.exponential_alpha);
        default: {
            const double x = pos / -m;
            // β = 2 (the default) is every query AP of every knn/wknn request: a multiply
            // gives the same value as pow and costs a fraction of it.
            return params_.powed_beta == 2.0 ? x * x : std::pow(x, params_.powed_beta);
        }
    }
}

Index Index::build(const std::vector<IndexedRp>& rps, const IndexParams& params) {
    Index idx;
    idx.params_ = params;
    idx.rps_.reserve(rps.size());
    idx.rep_sum_.assign(rps.size() * 3, 0.0);
    idx.rep_sq_sum_.assign(rps.size() * 3, 0.0);
    idx.log_miss_sum_.assign(rps.size(), 0.0);
    std::vector<std::vector<Posting>> lists;
    const double lo = params.min_detection, hi = 1.0 - params.min_detection;
    for (std::size_t i = 0; i < rps.size(); ++i) {
        const auto& in = rps[i];
        RpInfo info{in.rp.id, in.rp.at, in.floor_id, in.building_id, 0};
        for (const auto& m : in.rp.measurements) {
            if (m.stats.count <= 0 || !std::isfinite(m.stats.mean)) continue;
            auto [it, inserted] = idx.ap_ids_.try_emplace(ApKey{m.type, m.bssid.str()}, static_cast<std::uint32_t>(lists.size()));
            if (inserted) lists.emplace_back();
            auto& list = lists[it->second];
            // Two measurements of one AP at one RP would be a store bug; keep the first.
            if (!list.empty() && list.back().rp == i) continue;
            // An RP with an unknown scan count cannot give a detection rate: treat its APs
            // as always heard (the most the data says).
            const double rate = in.rp.scans > 0 ? static_cast<double>(m.stats.count) / static_cast<double>(in.rp.scans) : 1.0;
            const double p = std::clamp(rate, lo, hi);
            Posting post{};
            post.rp = static_cast<std::uint32_t>(i);
            post.mean = m.stats.mean;
            auto& lik = post.likelihood;
            lik.variance = std::max(0.0, m.stats.variance);
            lik.log_variance = lik.variance > 0 ? std::log(lik.variance) : -std::numeric_limits<double>::infinity();
            lik.log_detect = std::log(p);
            lik.log_miss = std::log1p(-p);
            for (int r = 0; r < 3; ++r) {
                post.rep[r] = (params.expected_representation ? std::min(rate, 1.0) : 1.0) * idx.represent(post.mean, r);
                idx.rep_sum_[i * 3 + r] += post.rep[r];
                idx.rep_sq_sum_[i * 3 + r] += post.rep[r] * post.rep[r];
            }
            idx.log_miss_sum_[i] += lik.log_miss;
            list.push_back(post);
            ++info.ap_count;
        }
        idx.rps_.push_back(info);
    }
    for (const auto& list : lists) {
        const auto strongest = std::max_element(list.begin(), list.end(),
                                                [](const Posting& a, const Posting& b) { return a.mean < b.mean; });
        idx.strongest_rp_.push_back(strongest->rp);
        for (const auto& post : list) {
            idx.post_rp_.push_back(post.rp);
            idx.post_mean_.push_back(post.mean);
            for (int r = 0; r < 3; ++r) idx.post_rep_[r].push_back(post.rep[r]);
            idx.post_likelihood_.push_back(post.likelihood);
        }
        idx.offsets_.push_back(idx.post_rp_.size());
    }
    return idx;
}

std::size_t Index::memory_bytes() const {
    auto bytes = [](const auto& v) { return v.capacity() * sizeof(typename std::decay_t<decltype(v)>::value_type); };
    std::size_t n = bytes(rps_) + bytes(offsets_) + bytes(post_rp_) + bytes(post_mean_) + bytes(post_likelihood_) +
                    bytes(rep_sum_) + bytes(rep_sq_sum_) + bytes(log_miss_sum_) + bytes(strongest_rp_);
    for (const auto& r : post_rep_) n += bytes(r);
    // A node holds the key, the value, the next pointer and the cached hash; short BSSIDs
    // fit the strings' inline buffers.
    n += ap_ids_.size() * (sizeof(ApKey) + sizeof(std::uint32_t) + 2 * sizeof(void*)) +
         ap_ids_.bucket_count() * sizeof(void*);
    return n;
}

PostingList Index::postings(std::size_t ap) const {
    const std::size_t b = offsets_[ap], n = offsets_[ap + 1] - b;
    PostingList l;
    l.rp = std::span(post_rp_).subspan(b, n);
    l.mean = std::span(post_mean_).subspan(b, n);
    for (int r = 0; r < 3; ++r) l.rep[r] = std::span(post_rep_[r]).subspan(b, n);
    l.likelihood = std::span(post_likelihood_).subspan(b, n);
    return l;
}

long Index::ap_of(std::string_view type, std::string_view bssid) const {
    return ap_of(type, bssid, std::hash<std::string_view>{}(bssid));
}

long Index::ap_of(std::string_view type, std::string_view bssid, std::size_t bssid_hash) const {
    const auto it = ap_ids_.find(ApKeyView{type, bssid, bssid_hash});
    return it == ap_ids_.end() ? -1 : static_cast<long>(it->second);
}

}  // namespace locus::match
