#pragma once
// A particle filter for phones in buildings nobody calibrated (docs/fusion.md, "Real walks"):
// it starts from nothing (the first fix), and each particle carries not only where the person
// is but the unknowns a real phone brings — the rotation φ between the compass and the floor,
// whether the plan is mirrored against east-north-up (s = ±1), and the walker's step-length
// scale c. A step at compass azimuth ψ moves a particle by c·L at θ = φ + sψ; the fixes then
// weed out the wrong rotations, mirrors and scales along with the wrong places. Indoors the
// compass drifts by tens of degrees along a corridor, so φ random-walks per step; and where
// the plan's walls run along two axes, a heading within snap_rad of one of them is taken as
// that axis (people walk along corridors, not at the compass's 20° to them). Walls block
// moves as in ParticleFilter. A share of the particles is re-drawn around every fix with
// fresh φ, s and c, so a cloud that settled on a wrong hypothesis can always recover.
//
// Cost, n particles (fewer once the cloud has settled: min_particles): a step is O(n) and, on
// a floor plan, independent of how many walls it has (PlanWalkable::can_move: cell lookups,
// segment tests only against the walls in the cells a move passes); a fix O(n) (the
// likelihoods, systematic resampling, the bins KLD-resampling counts, the fresh particles);
// the estimate (position(), spread()) is worked out once per step or fix, O(n) per mean-shift
// iteration, and only read after. The particles are stored as arrays of floats (21 bytes
// each: memory_bytes()), and the random numbers come from FastRandom, seeded with
// config.seed, so a filter's output is reproducible from its seed and inputs.
#include <Eigen/Dense>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "locus/motion/fusion/fast_random.hpp"
#include "locus/motion/fusion/walkable.hpp"

namespace locus::fusion {

// Tuned on the PUTMC walks xperia_traj1–5 only (docs/fusion.md); reported on the other seven.
struct WalkFilterConfig {
    int particles = 2000;              // the cloud's size; with min_particles below it, its most
    // KLD-resampling (Fox, "Adapting the sample size in particle filters through KLD-sampling",
    // IJRR 2003; Li, Sun and Sattar, "Adapting sample size in particle filters through
    // KLD-resampling", Electronics Letters 2013): at each fix the cloud is resampled to as
    // many particles as keep, with probability 0.99, the KL divergence between the sampled and
    // the true posterior under kld_epsilon, given how many bins of kld_bin_m × kld_bin_m ×
    // kld_bin_rad of rotation (× mirror) the posterior occupies; never fewer than
    // min_particles. A cloud that has settled on one place and rotation needs a few hundred,
    // a cold start or one that a fix surprised (its fresh particles spread) up to all of them.
    // min_particles at or above particles: a fixed size, resampled only when degenerate.
    int min_particles = 2000;
    double kld_epsilon = 0.05;
    double kld_bin_m = 1.0;
    double kld_bin_rad = 0.2;
    std::uint64_t seed = 1;
    double initial_sigma_m = 2.0;      // spread around the first fix
    double scale_mean = 1.15;          // initial step scale: lognormal around this...
    double scale_sigma = 0.25;         // ...with this σ of its log
    double heading_sigma_rad = 0.12;   // per-step heading noise
    double offset_walk_rad = 0.15;     // per-step random walk of φ (compass drift)
    double scale_walk = 0.01;          // per-step relative random walk of c
    double length_sigma = 0.1;         // per-step relative length noise
    double snap_rad = 0.45;            // headings this close to a corridor axis take the axis
    int blocked_retries = 2;
    double blocked_weight = 0.02;
    double fix_sigma_m = 2.2;          // σ of the fix likelihood (at least; the fix's own cov when larger)
    double outlier_floor = 0.02;
    double reseed_fraction = 0.3;      // slots re-drawn around each fix (with replacement: ≈ 26 % of the particles)...
    // ...rising towards this share the less the cloud expects the fix (1 − its mean likelihood
    // of it): a cloud that drifted off with a wrong rotation is rebuilt round the fix sooner,
    // one that agrees keeps its history. At or below reseed_fraction: a fixed share.
    double reseed_max_fraction = 0.0;
    double resample_fraction = 0.5;
    // > 0: position() is the cloud's mode, found by mean shift from the weighted mean with a
    // flat kernel of this radius, not the mean (particles heading the wrong way pull a mean back).
    double estimate_radius_m = 0.0;
    // With a rotation hint (HeadingAlignment's, learnt from the fixes so far), this share of
    // the fresh particles takes it, ±hint_sigma_rad; the rest draw φ and s uniformly.
    double hint_share = 0.0;
    double hint_sigma_rad = 0.35;
    // Without one, this share of the fresh particles takes the rotation and mirror of a
    // particle of the cloud drawn at random, ±cloud_sigma_rad, and the rest draw them
    // uniformly: a cloud that has learnt the compass's rotation from the walk keeps it in its
    // fresh particles too, so it stays tight enough for KLD-resampling to shrink it, while the
    // uniform draws still let a wrong rotation be replaced.
    double cloud_share = 0.0;
    double cloud_sigma_rad = 0.2;

    // The setting for real phones on real walks, chosen on PUTMC walks 1–5 (docs/fusion.md,
    // "Real walks"): a larger step-scale prior (the first walker's detected steps cover about
    // 60 % of the distance walked) and a wider fix likelihood (WiFi errors are spatially
    // correlated, so one fix says less than its spread) took walks 1–5 from 2.39 / 2.41 to
    // 2.24 / 2.17 m (seeds 1, 2); the cloud's mode within 3 m as the estimate (fresh particles'
    // random rotations pull a mean back along the corridor) and up to 70 % re-drawn round a fix
    // the cloud did not expect took the mean over seeds 1–4 from 2.20 to 1.88 m. `walk_eval`
    // and the server's live tracks run it; simulated walks keep the defaults above. The step
    // scale's prior and the fix σ were set again for one setting that serves the IPIN 2023
    // walks too (docs/results.md, "What a phone gets"): 1.5 ± 0.25 and 2.6 m were PUTMC's first
    // walker's, whose detected steps were short; other phones' are near their true length, and
    // PUTMC's filter, re-drawing up to 70 % of its cloud on a plan, hardly minds the prior
    // (all 12 walks 2.06 / 2.11 / 1.97 m at seeds 1–3 against 2.06 / 2.01 / 1.97; walks 6–12
    // 1.94 / 2.05 / 1.85 against 2.13 / 2.05 / 1.97). The cloud's size then adapts (700 to
    // 2,000 particles, KLD-resampling) with 70 % of the fresh particles taking the cloud's own
    // rotation: a live request on the PUTMC plan costs 2.2× less for 2.07 m against 2.04 m
    // (all 12 walks, seeds 1–6; docs/results.md, "Tracking cost").
    static WalkFilterConfig real_walks() {
        WalkFilterConfig c;
        c.scale_mean = 1.0;
        c.scale_sigma = 0.15;
        c.fix_sigma_m = 4.0;
        c.estimate_radius_m = 3.0;
        c.reseed_max_fraction = 0.7;
        c.cloud_share = 0.7;
        c.min_particles = 700;
        c.kld_epsilon = 0.25;
        c.kld_bin_rad = 0.5;
        return c;
    }

    // The same walker where the rotation from the steps' headings to the floor is known but for
    // the compass's own error (a compass azimuth on a floor whose georeference says where north
    // is): 95 % of the fresh particles draw the rotation round the hint, σ 11.5°, it drifts 2.9°
    // a step (a phone's rotation vector), and only 2–10 % of the cloud is re-drawn round a fix,
    // for re-drawn particles are what finds a rotation nobody knows (on the IPIN 2023 walks
    // 30–70 % made the track follow the WiFi answers: docs/results.md).
    static WalkFilterConfig known_rotation(WalkFilterConfig c) {
        c.hint_share = 0.95;
        c.hint_sigma_rad = 0.2;
        c.offset_walk_rad = 0.05;
        c.reseed_fraction = 0.02;
        c.reseed_max_fraction = 0.1;
        // A fixed size: so few fresh particles are what lets a cloud that started on a wrong fix
        // find the walker, and a smaller cloud has fewer still (KLD-resampling from 700 took the
        // IPIN 2023 folds' eval walk_pf from 2.99 / 3.33 / 3.90 to 3.17 / 3.35 / 4.22 m cold,
        // p75 over seeds 1–4; docs/results.md, "Tracking cost").
        c.min_particles = c.particles;
        return c;
    }
};

// The dominant wall direction of a plan, modulo 90° (rad in [0, π/2)), from a length-weighted
// histogram; nullopt when the walls show no clear axis.
std::optional<double> corridor_axis(const locus::plan::Plan& plan);

class WalkFilter {
public:
    // map: walls and spaces (may be empty: then moves are free and headings are not snapped).
    explicit WalkFilter(std::optional<Walkable> map, const WalkFilterConfig& config = {});

    bool started() const { return !x_.empty(); }
    // A step in the compass frame (ignored before the first fix).
    void step(double length_m, double azimuth_rad);
    void fix(Point at, const Eigen::Matrix2d& cov);
    // The rotation and mirror the fixes suggest so far: fresh particles lean on it.
    void hint(double offset_rad, bool mirrored) { hint_ = {offset_rad, mirrored ? -1.0 : 1.0}; }
    // The walker went to another floor (stairs, a lift): the cloud keeps what each particle has
    // learnt (rotation, mirror, scale), moves by `shift` (from where the stairs stand on the
    // floor left to where they stand on this one; zero where the floors share a frame and no
    // stairs are known) and walks the new floor's map from now on; a particle the new floor's
    // walls shut out is placed anew round the estimate, within the cloud's spread. O(particles).
    void change_floor(std::optional<Walkable> map, Point shift = {0.0, 0.0});

    // The weighted mean, or the cloud's mode when estimate_radius_m > 0 (the real-walk preset);
    // only meaningful once started().
    Point position() const { return estimate_; }
    // How far the cloud is spread: the weighted RMS distance of the particles from position(),
    // an honest accuracy for the estimate (0 before the first fix).
    double spread() const { return spread_; }
    // What the filter holds: itself and its particles (not the shared floor plan).
    std::size_t memory_bytes() const;
    // How many particles the cloud has now (config.particles, or fewer: min_particles).
    std::size_t size() const { return x_.size(); }

private:
    // Particle i drawn anew; from_cloud: the cloud holds what the walk taught it (cloud_share).
    void fresh(std::size_t i, Point around, double sigma, bool from_cloud);
    double snapped(double heading) const;
    bool can_move(Point from, Point to) const;
    bool inside(Point p) const;
    void resample();
    std::size_t kld_size(const std::vector<std::uint32_t>& picks) const;  // the particles the picked cloud needs
    void estimate();  // position() and spread() of the cloud as it now is

    std::optional<Walkable> map_;
    // map_'s floor plan, when it has one: the shared object map_'s shared_ptr keeps alive, so a
    // copied filter's pointer stays valid (the copy holds the same shared_ptr).
    const PlanWalkable* plan_ = nullptr;
    std::optional<double> axis_;
    std::optional<std::pair<double, double>> hint_;  // offset, mirror
    WalkFilterConfig config_;
    FastRandom rng_;
    // The particles, one array per field: position, φ, s (±1), c and weight (mean 1 after each
    // step and fix, so a long run of blocked steps cannot underflow them).
    std::vector<float> x_, y_, offset_, scale_, weight_;
    std::vector<std::int8_t> mirror_;
    Point estimate_;
    double spread_ = 0.0;
};

}  // namespace locus::fusion
