#include "ipin_eval.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "locus/metrics.hpp"

namespace locus::tools::ipin {

namespace {

double error_of(const Fix& e, const Fix& t, double floor_penalty_m) {
    return distance(e.at, t.at) + floor_penalty_m * std::abs(e.floor - t.floor);
}

}  // namespace

Errors score_instants(const std::vector<Fix>& estimates, const std::vector<Fix>& truth, double floor_penalty_m,
                      double lag_s) {
    Errors out;
    for (const auto& t : truth) {
        // The first estimate later than t + lag; the one before it is the latest that counts.
        const auto it = std::upper_bound(estimates.begin(), estimates.end(), t.t + lag_s,
                                         [](double v, const Fix& f) { return v < f.t; });
        if (it == estimates.begin()) {
            ++out.unscored;
            continue;
        }
        const Fix& e = *(it - 1);
        out.errors.push_back(error_of(e, t, floor_penalty_m));
        if (e.floor == t.floor) ++out.floor_hits;
    }
    return out;
}

Errors score_pairs(const std::vector<Fix>& estimates, const std::vector<Fix>& truth, double floor_penalty_m) {
    Errors out;
    for (std::size_t i = 0; i < estimates.size() && i < truth.size(); ++i) {
        out.errors.push_back(error_of(estimates[i], truth[i], floor_penalty_m));
        if (estimates[i].floor == truth[i].floor) ++out.floor_hits;
    }
    return out;
}

void pool(Errors& a, const Errors& b) {
    a.errors.insert(a.errors.end(), b.errors.begin(), b.errors.end());
    a.floor_hits += b.floor_hits;
    a.unscored += b.unscored;
}

nlohmann::json figures(const Errors& e) {
    std::vector<double> sorted = e.errors;
    std::sort(sorted.begin(), sorted.end());
    nlohmann::json j = {{"n", sorted.size()}, {"unscored", e.unscored}};
    if (sorted.empty()) {
        j["p75_m"] = nullptr;
        j["mean_m"] = nullptr;
        j["floor_hit_rate"] = nullptr;
    } else {
        j["p75_m"] = metrics::percentile_hazen(sorted, 0.75);
        j["mean_m"] = metrics::mean(e.errors);
        j["floor_hit_rate"] = static_cast<double>(e.floor_hits) / static_cast<double>(sorted.size());
    }
    return j;
}

}  // namespace locus::tools::ipin
