#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "locus/motion/pdr/step_length.hpp"

namespace pdr_step_length_test {
namespace {

using namespace locus::pdr;

TEST(StepLength, StaticSsl) {
    EXPECT_NEAR(ssl_length(1.80, Sex::male), 0.747, 1e-12);    // 0.415 · 1.80
    EXPECT_NEAR(ssl_length(1.60, Sex::female), 0.6608, 1e-12); // 0.413 · 1.60
}

TEST(StepLength, WeinbergFourthRoot) {
    EXPECT_NEAR(weinberg_length(16.0), 1.04, 1e-12);  // 0.52 · 16^¼ = 0.52 · 2
    EXPECT_NEAR(weinberg_length(1.0), 0.52, 1e-12);
    EXPECT_NEAR(weinberg_length(81.0, 0.4), 1.2, 1e-12);  // 0.4 · 3
    EXPECT_EQ(weinberg_length(0.0), 0.0);
    EXPECT_EQ(weinberg_length(-2.0), 0.0);
}

TEST(StepLength, CalibrateKFromAWalkedDistance) {
    // Fourth roots 2 + 2 + 1 = 5; 3 m walked gives K = 0.6.
    const std::vector<double> amps{16.0, 16.0, 1.0};
    const double k = calibrate_weinberg_k(amps.data(), amps.size(), 3.0);
    EXPECT_NEAR(k, 0.6, 1e-12);
    double sum = 0.0;
    for (double a : amps) sum += weinberg_length(a, k);
    EXPECT_NEAR(sum, 3.0, 1e-12);
    // No information: keep the default.
    EXPECT_EQ(calibrate_weinberg_k(amps.data(), 0, 3.0), kWeinbergK);
    const std::vector<double> zeros{0.0, 0.0};
    EXPECT_EQ(calibrate_weinberg_k(zeros.data(), zeros.size(), 3.0), kWeinbergK);
}

TEST(StepLength, ModelKindsAndFallback) {
    StepEvent e{0.0, 8.0, -8.0};  // amplitude 16
    StepLengthModel m;
    EXPECT_NEAR(m.length(e), 1.04, 1e-12);
    m.kind = StepLengthKind::ssl;
    m.height_m = 1.6;
    m.sex = Sex::female;
    EXPECT_NEAR(m.length(e), 0.6608, 1e-12);
    m.kind = StepLengthKind::constant;
    EXPECT_EQ(m.length(e), kConstantStepLength);
    m.kind = StepLengthKind::weinberg;
    EXPECT_EQ(m.length(StepEvent{1.0, 0.0, 0.0}), kConstantStepLength);  // platform step, no amplitude
}

}  // namespace
}  // namespace pdr_step_length_test
