#include "locus/motion/fusion/fast_random.hpp"

#include <algorithm>
#include <cmath>

namespace locus::fusion {

namespace {

// Marsaglia and Tsang's constants for 128 layers: where the tail starts, and each layer's area.
constexpr double kTailStart = 3.442619855899;
constexpr double kLayerArea = 9.91256303526217e-3;

double density(double x) { return std::exp(-0.5 * x * x); }

}  // namespace

namespace detail {

const Ziggurat& ziggurat() {
    static const Ziggurat z = [] {
        Ziggurat t{};
        t.x[0] = kLayerArea / density(kTailStart);
        t.x[1] = kTailStart;
        for (int i = 1; i < 127; ++i) t.x[i + 1] = std::sqrt(std::max(0.0, -2.0 * std::log(density(t.x[i]) + kLayerArea / t.x[i])));
        t.x[128] = 0.0;
        for (int i = 0; i < 128; ++i) t.ratio[i] = t.x[i + 1] / t.x[i];
        for (int i = 0; i <= 128; ++i) t.f[i] = density(t.x[i]);
        return t;
    }();
    return z;
}

}  // namespace detail

FastRandom::FastRandom(std::uint64_t seed) {
    // splitmix64: every seed, 0 included, gives a state that is not all zeros.
    std::uint64_t z = seed;
    for (auto& word : s_) {
        std::uint64_t v = (z += 0x9e3779b97f4a7c15ULL);
        v = (v ^ (v >> 30)) * 0xbf58476d1ce4e5b9ULL;
        v = (v ^ (v >> 27)) * 0x94d049bb133111ebULL;
        word = v ^ (v >> 31);
    }
}

double FastRandom::normal_slow(int layer, double u) {
    const detail::Ziggurat& z = detail::ziggurat();
    for (;;) {
        if (layer == 0) {
            // The tail beyond kTailStart (Marsaglia 1964): exponential proposals, accepted
            // with the ratio of the densities.
            double a, b;
            do {
                a = -std::log(1.0 - uniform()) / kTailStart;
                b = -std::log(1.0 - uniform());
            } while (b + b < a * a);
            return u < 0 ? -(kTailStart + a) : kTailStart + a;
        }
        const double x = u * z.x[layer];
        if (z.f[layer] + uniform() * (z.f[layer + 1] - z.f[layer]) < density(x)) return x;
        const std::uint64_t bits = next();
        layer = static_cast<int>(bits & 127u);
        u = static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0;
        if (std::abs(u) < z.ratio[layer]) return u * z.x[layer];
    }
}

}  // namespace locus::fusion
