#pragma once
// Positions from RSS ranged to transmitters at known positions:
//  - trilaterate: the Kalman-fusion paper's method, every constant an option. Ranges beyond `cutoff` are
//    dropped; each transmitter gets a vote against it from every other one whose range and
//    separation break the triangle inequality by more than `vote_slack`; the one with fewest
//    votes is the reference, and every other range is brought into the interval the reference
//    allows; each triple of transmitters is solved by linear least squares and the answer is
//    the mean of the triples' solutions.
//  - multilaterate: weighted non-linear least squares over every ranged transmitter in the
//    RSS domain (where shadowing is Gaussian), Levenberg–Marquardt with a Cauchy loss (iterated
//    reweighting; a Huber loss still let one 0 dBm glitch pull the fix onto its transmitter),
//    and the fix's covariance from the normal matrix.
// Both are pure and allocation-light: a query is microseconds.
#include <optional>
#include <span>

#include "locus/geometry.hpp"
#include "locus/ranging/path_loss.hpp"

namespace locus::ranging {

// One transmitter heard in a scan.
struct Heard {
    Transmitter tx;
    double rss = 0.0;  // dBm, averaged over the scans (the Kalman-fusion paper: 5 s of readings)
};

// A 1-σ uncertainty ellipse: semi-axes in metres, the major axis at angle_deg counter-clockwise
// from +x.
struct Ellipse {
    double semi_major = 0.0, semi_minor = 0.0, angle_deg = 0.0;
};
// Of a 2×2 covariance [[sxx, sxy], [sxy, syy]].
Ellipse ellipse_of(double sxx, double syy, double sxy);

struct Fix {
    Point at;
    Ellipse uncertainty;
    double sxx = 0, syy = 0, sxy = 0;  // the covariance the ellipse is drawn from (m²), for a filter's R
    int used = 0;             // transmitters that took part
    double rms_residual = 0;  // multilaterate: dB; trilaterate: m (spread of the triples)
    int iterations = 0;       // multilaterate only
};

struct TrilaterationOptions {
    double cutoff = 10.0;     // m: ranges beyond are dropped (the Kalman-fusion paper: the beacons' reach)
    double vote_slack = 1.25; // a vote against n from l when |A_n A_l| − d_n > vote_slack · d_l
    bool correct = true;      // bring ranges into the reference's triangle-inequality interval
    int max_transmitters = 12;  // the strongest kept: C(12, 3) = 220 triples at most
};

struct MultilaterationOptions {
    double sigma_db = 4.0;      // shadowing σ of one averaged reading (dB)
    double loss_scale = 1.5;    // Cauchy loss scale, in σ: a residual of loss_scale·σ weighs ½
    int max_iterations = 30;
    double tolerance = 1e-3;    // m: stop when a step is shorter
};

// nullopt when fewer than three transmitters remain (after the cutoff) or every triple is
// degenerate (collinear).
std::optional<Fix> trilaterate(std::span<const Heard> heard, const TrilaterationOptions& options = {});
// nullopt with fewer than three transmitters.
std::optional<Fix> multilaterate(std::span<const Heard> heard, const MultilaterationOptions& options = {});

}  // namespace locus::ranging
