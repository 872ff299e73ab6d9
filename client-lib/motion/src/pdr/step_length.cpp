#include "locus/motion/pdr/step_length.hpp"

#include <cmath>

namespace locus::pdr {

double ssl_length(double height_m, Sex sex) {
    return (sex == Sex::male ? kSslAlphaMale : kSslAlphaFemale) * height_m;
}

double weinberg_length(double amplitude, double k) {
    return amplitude > 0.0 ? k * std::sqrt(std::sqrt(amplitude)) : 0.0;
}

double calibrate_weinberg_k(const double* amplitudes, std::size_t n, double walked_m) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        if (amplitudes[i] > 0.0) sum += std::sqrt(std::sqrt(amplitudes[i]));
    if (!(sum > 0.0) || !(walked_m > 0.0)) return kWeinbergK;
    return walked_m / sum;
}

double StepLengthModel::length(const StepEvent& e) const {
    switch (kind) {
        case StepLengthKind::constant:
            return constant_m;
        case StepLengthKind::ssl:
            return ssl_length(height_m, sex);
        case StepLengthKind::weinberg: {
            const double l = weinberg_length(e.amplitude(), k);
            return l > 0.0 ? l : constant_m;
        }
    }
    return constant_m;
}

}  // namespace locus::pdr
