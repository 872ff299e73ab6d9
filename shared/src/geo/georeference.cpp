#include "locus/geo/georeference.hpp"

#include <cmath>
#include <numbers>

namespace locus::geo {

double normalise_bearing(double deg) {
    double b = std::fmod(deg, 360.0);
    if (b < 0.0) b += 360.0;
    if (b >= 360.0) b = 0.0;  // -1e-17 + 360 rounds to 360
    return b;
}

FloorToEarth::FloorToEarth(const Georeference& g)
    : g_(g), plane_(g.at), sin_b_(std::sin(g.bearing_deg * kRadPerDeg)), cos_b_(std::cos(g.bearing_deg * kRadPerDeg)) {}

// The floor's +y is (sin b, cos b) in (east, north); its +x, a quarter turn clockwise from +y
// in a right-handed frame, is (cos b, −sin b).
LatLon FloorToEarth::to_geodetic(Point floor) const {
    const double dx = floor.x - g_.anchor.x, dy = floor.y - g_.anchor.y;
    return plane_.to_geodetic({dx * cos_b_ + dy * sin_b_, -dx * sin_b_ + dy * cos_b_});
}

Point FloorToEarth::to_floor(LatLon p) const {
    const EastNorth en = plane_.to_plane(p);
    return {g_.anchor.x + en.east * cos_b_ - en.north * sin_b_, g_.anchor.y + en.east * sin_b_ + en.north * cos_b_};
}

FitResult fit_georeference(const std::vector<ControlPoint>& points) {
    FitResult out;
    const auto n = static_cast<double>(points.size());
    if (points.size() < 3) {
        out.problem = FitProblem::too_few;
        return out;
    }
    // The tangent plane at the mean position: over a campus the mean of degrees is as good a
    // centre as any, and the fit is then done in metres on both sides.
    LatLon mean;
    for (const auto& p : points) {
        mean.lat += p.earth.lat / n;
        mean.lon += p.earth.lon / n;
    }
    const TangentPlane plane(mean);
    std::vector<EastNorth> world;
    world.reserve(points.size());
    Point fc;
    EastNorth wc;
    for (const auto& p : points) {
        world.push_back(plane.to_plane(p.earth));
        if (std::hypot(world.back().east, world.back().north) > kMaxFitSpreadM) {
            out.problem = FitProblem::too_spread;
            return out;
        }
        fc.x += p.floor.x / n;
        fc.y += p.floor.y / n;
        wc.east += world.back().east / n;
        wc.north += world.back().north / n;
    }
    // Collinear floor points leave the rotation undetermined: the smaller eigenvalue of their
    // scatter (the mean squared distance from the best line) must not vanish beside the larger.
    double sxx = 0, syy = 0, sxy = 0;
    for (const auto& p : points) {
        const double dx = p.floor.x - fc.x, dy = p.floor.y - fc.y;
        sxx += dx * dx / n;
        syy += dy * dy / n;
        sxy += dx * dy / n;
    }
    const double half_trace = (sxx + syy) / 2.0;
    const double root = std::sqrt(std::max(0.0, (sxx - syy) * (sxx - syy) / 4.0 + sxy * sxy));
    const double minor = std::max(0.0, half_trace - root), major = half_trace + root;
    // Under 1 mm RMS off the line, or a width under 1e-4 of the length: no rotation to trust.
    if (std::sqrt(minor) < 1e-3 || std::sqrt(minor) < 1e-4 * std::sqrt(major)) {
        out.problem = FitProblem::collinear;
        return out;
    }
    // The rotation α (counter-clockwise, floor → east/north) maximising Σ w·R(α)f over the
    // centred pairs: tan α = Σ(f × w) / Σ(f · w).
    double dot = 0, cross = 0, ff = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double fx = points[i].floor.x - fc.x, fy = points[i].floor.y - fc.y;
        const double we = world[i].east - wc.east, wn = world[i].north - wc.north;
        dot += fx * we + fy * wn;
        cross += fx * wn - fy * we;
        ff += fx * fx + fy * fy;
    }
    const double alpha = std::atan2(cross, dot);
    GeoreferenceFit fit;
    fit.scale = std::hypot(dot, cross) / ff;
    // A counter-clockwise turn α of the floor is a bearing of −α (clockwise from north).
    fit.georeference = {plane.to_geodetic(wc), fc, normalise_bearing(-alpha / kRadPerDeg)};
    // Residuals of what is stored, through the same conversion every answer uses.
    const FloorToEarth stored(fit.georeference);
    double sum2 = 0;
    for (const auto& p : points) {
        const double r = plane_distance(p.earth, stored.to_geodetic(p.floor));
        fit.residuals_m.push_back(r);
        sum2 += r * r;
    }
    fit.rms_m = std::sqrt(sum2 / n);
    out.fit = std::move(fit);
    return out;
}

}  // namespace locus::geo
