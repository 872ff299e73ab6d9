#pragma once
// Where B stands, from every distance A measured along its own PDR walk (Bonjorn López 2016,
// docs/spec.md §8, with RSSI): the point whose distances to A's positions best match the measured
// ones in log terms (RSSI shadowing is Gaussian in dB, so in ln d), by Gauss–Newton from several
// starts. Unlike the thesis's estimator, which can only weigh directions A has walked, this uses
// how fast the distance falls and how that changes as A turns, so it can find B off A's path. A
// straight walk leaves B's side (left or right) ambiguous; the caller's `prefer` breaks the tie.
#include <optional>
#include <span>

#include "locus/geometry.hpp"

namespace locus::relative {

// `at[i]` A's PDR position where `distance[i]` (m, > 0) was measured; at least three
// measurements, else none. `around`: the start guesses lie on a circle of `radius` about it
// (A's position now and the current distance estimate). Among equally good fits the one
// closest in bearing (from `around`) to `prefer_deg` wins.
std::optional<Point> fit_target(std::span<const Point> at, std::span<const double> distance, Point around, double radius,
                                double prefer_deg);

}  // namespace locus::relative
