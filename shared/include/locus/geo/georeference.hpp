#pragma once
// A floor's georeference (docs/geo.md): where its frame (docs/spec.md §2.1, metres, x right,
// y up) lies on Earth. One point (x, y) of the floor is at `at` (WGS84), and the floor's +y
// axis points `bearing_deg` clockwise from true (geographic) north. Metres stay metres: the
// map from floor to tangent plane is a rotation and a translation, never a scale. (The
// magnetic north_offset_deg of a floor, for PDR headings, is a different angle.)
// Conversions are a tangent-plane conversion (tangent_plane.hpp) plus a rotation: O(1).
#include <optional>
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/geo/tangent_plane.hpp"

namespace locus::geo {

struct Georeference {
    LatLon at;            // WGS84 position of floor point `anchor`
    Point anchor;         // in the floor's frame, metres
    double bearing_deg = 0.0;  // the floor's +y axis, clockwise from true north, [0, 360)
};

// Floor metres ↔ WGS84 through one georeference. Builds its tangent plane once.
class FloorToEarth {
public:
    explicit FloorToEarth(const Georeference& g);
    const Georeference& georeference() const { return g_; }
    LatLon to_geodetic(Point floor) const;
    Point to_floor(LatLon p) const;

private:
    Georeference g_;
    TangentPlane plane_;
    double sin_b_, cos_b_;
};

// A surveyed correspondence between the floor and the Earth.
struct ControlPoint {
    Point floor;
    LatLon earth;
};

struct GeoreferenceFit {
    Georeference georeference;  // rigid: the anchor is the control points' floor centroid
    // The least-squares similarity's scale (tangent-plane metres per floor metre). Not
    // applied; far from 1 means the control points (or the floor's drawing scale) disagree
    // with metres.
    double scale = 1.0;
    std::vector<double> residuals_m;  // per control point, of the rigid georeference, metres
    double rms_m = 0.0;
};

// Why a set of control points cannot be fitted, else nullopt.
enum class FitProblem { too_few, collinear, too_spread };
// Least-squares fit (2-D Procrustes: the rotation that best maps the centred floor points onto
// the centred tangent-plane points; Umeyama 1991, IEEE TPAMI 13(4)) of ≥ 3 control points whose
// floor positions are not collinear and whose Earth positions are within kMaxFitSpreadM of
// their mean (a tangent plane is for a campus, not a country). O(n).
inline constexpr double kMaxFitSpreadM = 20000.0;
struct FitResult {
    std::optional<GeoreferenceFit> fit;
    std::optional<FitProblem> problem;
};
FitResult fit_georeference(const std::vector<ControlPoint>& points);

// Angle in degrees brought into [0, 360).
double normalise_bearing(double deg);

}  // namespace locus::geo
