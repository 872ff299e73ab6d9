#pragma once
// Step length models (docs/spec.md §5.3): static SSL (α·h), dynamic DSL (Weinberg, K·(Amax−Amin)^¼) and a
// constant fallback.
#include <cstddef>

#include "locus/motion/pdr/step_detector.hpp"

namespace locus::pdr {

inline constexpr double kSslAlphaMale = 0.415;
inline constexpr double kSslAlphaFemale = 0.413;
inline constexpr double kWeinbergK = 0.52;            // Bonjorn López 2016 (docs/spec.md §5.3)
inline constexpr double kConstantStepLength = 0.70;   // docs/spec.md §5.3

enum class Sex { male, female };

double ssl_length(double height_m, Sex sex);
// Amplitude ≤ 0 (e.g. a platform step without acceleration) gives 0; callers fall back.
double weinberg_length(double amplitude, double k = kWeinbergK);

// K that makes the Weinberg lengths of the given step amplitudes add up to a walked distance.
// Returns kWeinbergK when the amplitudes carry no information (empty or all ≤ 0).
double calibrate_weinberg_k(const double* amplitudes, std::size_t n, double walked_m);

enum class StepLengthKind { constant, ssl, weinberg };

struct StepLengthModel {
    StepLengthKind kind = StepLengthKind::weinberg;
    double constant_m = kConstantStepLength;
    double height_m = 1.75;
    Sex sex = Sex::male;
    double k = kWeinbergK;

    // Weinberg with no usable amplitude falls back to the constant.
    double length(const StepEvent& e) const;
};

}  // namespace locus::pdr
