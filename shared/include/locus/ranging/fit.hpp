#pragma once
// Calibration of a transmitter's log-distance model from a survey (Le, Saragas and Webb 2009):
// given the mean RSS of one AP at many surveyed points, the transmit power and path-loss exponent
// that explain it best (least squares: rss = tx_power − 10·n·log10(d) is linear in both), and, when
// the transmitter's position is unknown, the position too (for each candidate position the model is
// solved exactly, so only the position is searched: a grid over the area, then a shrinking pattern
// search). Reports R² and the RMS residual.
#include <optional>
#include <span>

#include "locus/geometry.hpp"
#include "locus/ranging/path_loss.hpp"

namespace locus::ranging {

struct Sample {
    Point at;
    double rss = 0.0;  // mean at that point, dBm
};

struct ModelFit {
    Point at;
    PathLoss model;
    double r2 = 0.0;           // 1 − SS_res / SS_tot (0 when the RSS does not vary)
    double residual_db = 0.0;  // RMS residual
    int samples = 0;
};

struct FitOptions {
    double min_exponent = 1.0, max_exponent = 8.0;  // n is kept within (a fit outside is clamped)
    // The area a position is searched in (the floor).
    Rect area{0, 0, 0, 0};
    double grid_step = 0.0;  // m; 0: a 24 × 24 grid over the area
};

// The model for a transmitter at `at` (height dz above the survey device). nullopt with fewer
// than 3 samples or when every sample is at the same distance.
std::optional<ModelFit> fit_model(std::span<const Sample> samples, Point at, double dz, const FitOptions& options = {});
// Position and model. nullopt with fewer than 4 samples.
std::optional<ModelFit> fit_position_and_model(std::span<const Sample> samples, const FitOptions& options);

}  // namespace locus::ranging
