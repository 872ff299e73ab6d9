#pragma once
// The five fusion rules of docs/spec.md §6 (Traini 2017 §2.3.6): one WiFi fix meets the PDR position.
// Degenerate cases are defined here once and documented in docs/fusion.md.
#include <optional>
#include <span>
#include <string_view>

#include "locus/geometry.hpp"

namespace locus::fusion {

enum class Rule { only_wifi, midpoint, midpoint_threshold, proportional, proportional2 };

std::optional<Rule> parse_rule(std::string_view name);
std::string_view to_string(Rule r);
std::span<const Rule> all_rules();

struct RuleParams {
    double lambda_m = 4.0;  // midpoint_threshold: mean PDR error (Traini 2017 measured 3.8–4.4 m)
    int n_max = 10;         // proportional: APs that give a good fix
    int gamma = 2;          // proportional: exponent, a natural number ≥ 1
    // Not in Traini 2017 (its values here are Traini 2017's rules exactly); tuned on real walks,
    // where the PDR heading is far worse than Traini's (docs/fusion.md, "Real walks"):
    double midpoint_wifi_weight = 0.5;  // midpoint, midpoint_threshold: the fix's weight, in [0, 1]
    double proportional2_min_r = 0.0;   // proportional2: the fix's weight is at least this, in [0, 1]
};

struct FusionInput {
    Point pdr;                       // PDR position now (continued from the last fused one)
    Point wifi;                      // the fix just received
    std::optional<Point> prev;       // previous fused position; none before the first fix
    int aps = 0;                     // N: APs in the online scan
    std::optional<Point> prev_wifi;  // the previous WiFi fix (proportional2's refinement)
};

// Throws std::invalid_argument on params outside their domain (n_max < 1, gamma < 1,
// lambda < 0, aps < 0).
Point fuse(Rule rule, const FusionInput& in, const RuleParams& params = {});

// The weights themselves, exposed so tests and docs can check them by hand.
// proportional: α, the weight of the PDR position. Both distances zero → 0.
double proportional_alpha(double d_pdr, double d_wifi, int aps, const RuleParams& params);
// proportional2: r, the weight of the WiFi fix, = d_pdr / (d_pdr + d_wifi) (docs/spec.md §6.6,
// its 1/d form cleared). Both distances zero → 0 (the points coincide anyway).
double proportional2_r(double d_pdr, double d_wifi);

}  // namespace locus::fusion
