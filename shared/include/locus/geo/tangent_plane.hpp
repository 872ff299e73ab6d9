#pragma once
// WGS84 positions and a local tangent plane (east/north metres about an origin), the frame a
// floor's georeference (georeference.hpp) is placed in. The plane is the orthographic projection
// onto the plane tangent to the WGS84 ellipsoid at the origin (the east and north axes of the
// ENU frame): exact, no series, so over a campus (a few km) distances in it differ from the
// geodesic ones by well under a centimetre (the projection shortens a distance d by about
// d³/(2R²): 0.01 mm at 1 km). Heights are not modelled: every point is on the ellipsoid.
// Pure functions; each conversion is a few dozen floating-point operations, no iteration.
#include <numbers>

namespace locus::geo {

// Radians per degree: positions and bearings are in degrees, the trigonometry in radians.
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// The WGS84 ellipsoid (NIMA TR8350.2): semi-major axis and flattening.
inline constexpr double kWgs84A = 6378137.0;
inline constexpr double kWgs84F = 1.0 / 298.257223563;

struct LatLon {
    double lat = 0.0;  // degrees, north positive, [-90, 90]
    double lon = 0.0;  // degrees, east positive, [-180, 180]
};

struct EastNorth {
    double east = 0.0;   // metres
    double north = 0.0;  // metres
};

// Radii of curvature at a latitude (degrees): the meridian's M (north-south) and the prime
// vertical's N (east-west is N·cos lat). One degree of latitude spans about M·π/180.
double meridian_radius(double lat_deg);
double prime_vertical_radius(double lat_deg);

class TangentPlane {
public:
    explicit TangentPlane(LatLon origin);
    LatLon origin() const { return origin_; }
    // Where a point of the ellipsoid lies on the plane.
    EastNorth to_plane(LatLon p) const;
    // The point of the ellipsoid that projects onto (east, north). Meant for offsets up to
    // hundreds of km; past the horizon (no such point) it answers the nearest one, finite.
    LatLon to_geodetic(EastNorth p) const;

private:
    LatLon origin_;
    double ox_, oy_, oz_;  // the origin in ECEF (m)
    double sin_lat_, cos_lat_, sin_lon_, cos_lon_;
};

// Distance in metres between two nearby points, measured on the tangent plane at the first.
double plane_distance(LatLon a, LatLon b);

}  // namespace locus::geo
