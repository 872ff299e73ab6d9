#pragma once
// The accuracy and latency figures Locus reports (`locus eval uji`, `locus sim --evaluate`, the
// load benches), in one place so a figure means the same everywhere it is printed. Pure: no I/O.
//
// Two percentile definitions live here on purpose. Both are behind figures already published in
// README.md and docs/, so neither may change and neither may replace the other:
// - percentile_interpolated: `locus eval uji` (median, p75, p95 error) and the load benches
//   (`bench localize`, `bench connections`: p50, p99 latency);
// - percentile_nearest_rank: `locus sim --evaluate` (p95 error of each fusion method).
// A third, percentile_hazen, is the IPIN competitions' score (MATLAB's quantile), used by
// `locus eval ipin` only.
#include <span>

namespace locus::metrics {

// Linear interpolation between the order statistics around p · (n − 1) (Hyndman and Fan's
// "type 7", the default of R and NumPy). `sorted` must be ascending; p in [0, 1]. NaN when empty.
double percentile_interpolated(std::span<const double> sorted, double p);

// The smallest value with at least p · n values at or below it (never interpolated, so always
// one of the values). `sorted` must be ascending; p in [0, 1]; p = 0 gives the smallest value.
// NaN when empty.
double percentile_nearest_rank(std::span<const double> sorted, double p);

// Piecewise-linear between the order statistics with the k-th (1-based) at p = (k − 0.5) / n,
// clamped to the extremes (Hyndman and Fan's "type 5"; MATLAB's quantile, NumPy's
// method='hazen'): how the IPIN competitions compute the 75th percentile of a walk's errors.
// `sorted` must be ascending; p in [0, 1]. NaN when empty.
double percentile_hazen(std::span<const double> sorted, double p);

// The arithmetic mean, summed in the given order (so a figure does not move with the
// summation order). NaN when empty.
double mean(std::span<const double> values);

}  // namespace locus::metrics
