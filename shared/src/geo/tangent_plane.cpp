#include "locus/geo/tangent_plane.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace locus::geo {

namespace {
constexpr double kE2 = kWgs84F * (2.0 - kWgs84F);  // first eccentricity squared
constexpr double kB = kWgs84A * (1.0 - kWgs84F);   // semi-minor axis

struct Ecef {
    double x, y, z;
};

// A point of the ellipsoid (height 0) in Earth-centred, Earth-fixed coordinates.
Ecef ecef_of(LatLon p) {
    const double lat = p.lat * kRadPerDeg, lon = p.lon * kRadPerDeg;
    const double n = prime_vertical_radius(p.lat);
    return {n * std::cos(lat) * std::cos(lon), n * std::cos(lat) * std::sin(lon), n * (1.0 - kE2) * std::sin(lat)};
}
}  // namespace

double prime_vertical_radius(double lat_deg) {
    const double s = std::sin(lat_deg * kRadPerDeg);
    return kWgs84A / std::sqrt(1.0 - kE2 * s * s);
}

double meridian_radius(double lat_deg) {
    const double s = std::sin(lat_deg * kRadPerDeg);
    const double w = 1.0 - kE2 * s * s;
    return kWgs84A * (1.0 - kE2) / (w * std::sqrt(w));
}

TangentPlane::TangentPlane(LatLon origin) : origin_(origin) {
    const Ecef o = ecef_of(origin);
    ox_ = o.x;
    oy_ = o.y;
    oz_ = o.z;
    sin_lat_ = std::sin(origin.lat * kRadPerDeg);
    cos_lat_ = std::cos(origin.lat * kRadPerDeg);
    sin_lon_ = std::sin(origin.lon * kRadPerDeg);
    cos_lon_ = std::cos(origin.lon * kRadPerDeg);
}

EastNorth TangentPlane::to_plane(LatLon p) const {
    const Ecef q = ecef_of(p);
    const double dx = q.x - ox_, dy = q.y - oy_, dz = q.z - oz_;
    return {-sin_lon_ * dx + cos_lon_ * dy, -sin_lat_ * cos_lon_ * dx - sin_lat_ * sin_lon_ * dy + cos_lat_ * dz};
}

LatLon TangentPlane::to_geodetic(EastNorth p) const {
    // The plane point, then along the origin's up axis to the ellipsoid: the root u of
    // ((x+u·ux)² + (y+u·uy)²)/a² + (z+u·uz)²/b² = 1 nearest 0.
    const double ex = -sin_lon_, ey = cos_lon_;
    const double nx = -sin_lat_ * cos_lon_, ny = -sin_lat_ * sin_lon_, nz = cos_lat_;
    const double ux = cos_lat_ * cos_lon_, uy = cos_lat_ * sin_lon_, uz = sin_lat_;
    const double x = ox_ + p.east * ex + p.north * nx;
    const double y = oy_ + p.east * ey + p.north * ny;
    const double z = oz_ + p.north * nz;
    constexpr double a2 = kWgs84A * kWgs84A, b2 = kB * kB;
    const double qa = (ux * ux + uy * uy) / a2 + uz * uz / b2;
    const double qb = 2.0 * ((x * ux + y * uy) / a2 + z * uz / b2);
    const double qc = (x * x + y * y) / a2 + z * z / b2 - 1.0;
    const double disc = std::max(0.0, qb * qb - 4.0 * qa * qc);
    // -2c / (b + √disc): the small root without the cancellation of (-b + √disc) / 2a.
    const double denom = qb + std::sqrt(disc);
    const double u = denom > 0.0 ? -2.0 * qc / denom : -qb / (2.0 * qa);
    const double px = x + u * ux, py = y + u * uy, pz = z + u * uz;
    // On the ellipsoid the geodetic latitude is exact in closed form: tan φ = z / ((1 − e²)·p).
    const double lat = std::atan2(pz, (1.0 - kE2) * std::hypot(px, py)) / kRadPerDeg;
    const double lon = std::atan2(py, px) / kRadPerDeg;
    return {lat, lon};
}

double plane_distance(LatLon a, LatLon b) {
    const EastNorth d = TangentPlane(a).to_plane(b);
    return std::hypot(d.east, d.north);
}

}  // namespace locus::geo
