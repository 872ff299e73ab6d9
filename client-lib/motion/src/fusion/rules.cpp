#include "locus/motion/fusion/rules.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace locus::fusion {

namespace {

constexpr std::array kRules{Rule::only_wifi, Rule::midpoint, Rule::midpoint_threshold, Rule::proportional,
                            Rule::proportional2};
constexpr std::array<std::string_view, 5> kNames{"only_wifi", "midpoint", "midpoint_threshold", "proportional",
                                                 "proportional2"};

Point blend(Point pdr, Point wifi, double wifi_weight) {
    return {(1.0 - wifi_weight) * pdr.x + wifi_weight * wifi.x, (1.0 - wifi_weight) * pdr.y + wifi_weight * wifi.y};
}

void check(const FusionInput& in, const RuleParams& p) {
    if (p.n_max < 1) throw std::invalid_argument("n_max must be at least 1");
    if (p.gamma < 1) throw std::invalid_argument("gamma must be a natural number, at least 1");
    if (!(p.lambda_m >= 0.0)) throw std::invalid_argument("lambda must be >= 0");
    if (!(p.midpoint_wifi_weight >= 0.0 && p.midpoint_wifi_weight <= 1.0))
        throw std::invalid_argument("midpoint_wifi_weight must be in [0, 1]");
    if (!(p.proportional2_min_r >= 0.0 && p.proportional2_min_r <= 1.0))
        throw std::invalid_argument("proportional2_min_r must be in [0, 1]");
    if (in.aps < 0) throw std::invalid_argument("the number of APs cannot be negative");
}

}  // namespace

std::optional<Rule> parse_rule(std::string_view name) {
    for (std::size_t i = 0; i < kRules.size(); ++i)
        if (kNames[i] == name) return kRules[i];
    return std::nullopt;
}

std::string_view to_string(Rule r) { return kNames[static_cast<std::size_t>(r)]; }

std::span<const Rule> all_rules() { return kRules; }

double proportional_alpha(double d_pdr, double d_wifi, int aps, const RuleParams& params) {
    const double sum = d_pdr + d_wifi;
    if (sum <= 0.0) return 0.0;
    const double coverage = static_cast<double>(std::min(aps, params.n_max)) / params.n_max;
    return d_wifi / sum * (1.0 - std::pow(coverage, params.gamma));
}

double proportional2_r(double d_pdr, double d_wifi) {
    const double sum = d_pdr + d_wifi;
    if (sum <= 0.0) return 0.0;
    return d_pdr / sum;
}

Point fuse(Rule rule, const FusionInput& in, const RuleParams& params) {
    check(in, params);
    // Without a previous position the PDR position has no anchor: the fix is all we know.
    if (!in.prev) return in.wifi;
    const Point prev = *in.prev;
    switch (rule) {
        case Rule::only_wifi:
            return in.wifi;
        case Rule::midpoint:
            return blend(in.pdr, in.wifi, params.midpoint_wifi_weight);
        case Rule::midpoint_threshold:
            // Strict as in Traini 2017 (δ < λ, docs/spec.md §6.4): at δ == λ the PDR is deemed broken.
            return distance(in.pdr, in.wifi) < params.lambda_m ? blend(in.pdr, in.wifi, params.midpoint_wifi_weight) : in.wifi;
        case Rule::proportional: {
            const double alpha = proportional_alpha(distance(in.pdr, prev), distance(in.wifi, prev), in.aps, params);
            return blend(in.pdr, in.wifi, 1.0 - alpha);
        }
        case Rule::proportional2: {
            // Lu et al.: a fix identical to the previous one says the scan did not change, not
            // that the user stood still, so fusing would shorten the walked path.
            if (in.prev_wifi && in.prev_wifi->x == in.wifi.x && in.prev_wifi->y == in.wifi.y) return in.pdr;
            return blend(in.pdr, in.wifi,
                        std::max(params.proportional2_min_r, proportional2_r(distance(in.pdr, prev), distance(in.wifi, prev))));
        }
    }
    throw std::invalid_argument("unknown fusion rule");
}

}  // namespace locus::fusion
