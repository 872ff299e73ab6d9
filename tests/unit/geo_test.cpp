// WGS84 ↔ tangent plane and floor georeferences (locus/geo): against published geodesic
// figures and hand-computed values, never against the code's own output.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "locus/geo/georeference.hpp"
#include "locus/geo/tangent_plane.hpp"

namespace geo_test {
namespace {

using namespace locus::geo;
using locus::Point;

constexpr double kRad = std::numbers::pi / 180.0;

// Lengths of one degree on WGS84, as the usual tables publish them (to the metre): latitude
// (along the meridian) and longitude (along the parallel) at 0°, 45° and 60°.
TEST(Wgs84, DegreeLengthsMatchPublishedTables) {
    struct Row {
        double lat, lat_deg_m, lon_deg_m;
    };
    for (const Row& r : {Row{0, 110574, 111320}, Row{45, 111132, 78847}, Row{60, 111412, 55800}}) {
        EXPECT_NEAR(meridian_radius(r.lat) * kRad, r.lat_deg_m, 1.0) << r.lat;
        EXPECT_NEAR(prime_vertical_radius(r.lat) * std::cos(r.lat * kRad) * kRad, r.lon_deg_m, 1.0) << r.lat;
    }
}

// A thousandth of a degree is a thousandth of the tables' lengths (to half a millimetre).
TEST(TangentPlane, MillidegreeOffsetsMatchPublishedDegreeLengths) {
    const TangentPlane equator({0, 0}), mid({45, 7}), north({60, -20});
    EXPECT_NEAR(equator.to_plane({0.001, 0}).north, 110.574, 2e-3);
    EXPECT_NEAR(equator.to_plane({0, 0.001}).east, 111.320, 2e-3);
    EXPECT_NEAR(mid.to_plane({45.001, 7}).north, 111.132, 2e-3);
    EXPECT_NEAR(mid.to_plane({45, 7.001}).east, 78.847, 2e-3);
    EXPECT_NEAR(north.to_plane({60.001, -20}).north, 111.412, 2e-3);
    EXPECT_NEAR(north.to_plane({60, -19.999}).east, 55.800, 2e-3);
    // Going west or south is negative; the origin is the plane's (0, 0).
    EXPECT_LT(mid.to_plane({45, 6.999}).east, -78.8);
    EXPECT_LT(mid.to_plane({44.999, 7}).north, -111.1);
    EXPECT_NEAR(mid.to_plane({45, 7}).east, 0.0, 1e-9);
    EXPECT_NEAR(mid.to_plane({45, 7}).north, 0.0, 1e-9);
}

// Two surveyed reference points of the IPIN 2023 venue (Museum Industriekultur, Nuremberg):
// 9001 (49.4611492539213, 11.1102840572794) and 9005 (49.4614454239615, 11.1118844796720).
// By hand, with the WGS84 radii of curvature at lat 49.46115 (north M = 6 372 360 m, east
// N = 6 390 503 m, both from N = a/√(1 − e² sin²φ), M = a(1 − e²)/(1 − e² sin²φ)^1.5) and
// cos 49.46115° = 0.6499635:
//   Δlat = 0.00029617004°, Δlon = 0.00160042239°
//   north = 6 372 360 × 0.00029617004 × π/180 = 32.940 m
//   east  = 6 390 503 × 0.6499635 × 0.00160042239 × π/180 = 116.021 m
//   distance = √(32.940² + 116.021²) = 120.606 m, at a bearing atan2(116.021, 32.940) = 74.150°.
// Over 120 m this equirectangular sum agrees with the geodesic to well under a centimetre.
TEST(TangentPlane, ShortGeodesicAtTheVenue) {
    const LatLon p9001{49.4611492539213, 11.1102840572794}, p9005{49.4614454239615, 11.1118844796720};
    const EastNorth d = TangentPlane(p9001).to_plane(p9005);
    EXPECT_NEAR(d.east, 116.021, 0.01);
    EXPECT_NEAR(d.north, 32.940, 0.01);
    EXPECT_NEAR(plane_distance(p9001, p9005), 120.606, 0.01);
    EXPECT_NEAR(plane_distance(p9005, p9001), 120.606, 0.01);
}

TEST(TangentPlane, RoundTripsOverACampus) {
    for (const LatLon origin : {LatLon{49.46115, 11.11115}, LatLon{-33.9, 151.2}, LatLon{78.2, 15.6}, LatLon{0, -179.99}}) {
        const TangentPlane plane(origin);
        for (const EastNorth en : {EastNorth{0, 0}, EastNorth{3000, -2000}, EastNorth{-4500, 4500}, EastNorth{0.01, 0.02}}) {
            const LatLon g = plane.to_geodetic(en);
            const EastNorth back = plane.to_plane(g);
            EXPECT_NEAR(back.east, en.east, 1e-6);
            EXPECT_NEAR(back.north, en.north, 1e-6);
        }
    }
    // The date line: a point 1 km east of 179.995° E is on the other side, at about -179.991°.
    const LatLon across = TangentPlane({0, 179.995}).to_geodetic({1000, 0});
    EXPECT_NEAR(across.lon, -180.0 + (0.005 - 1000.0 / 111320.0) * -1.0, 1e-4);
    EXPECT_LT(across.lon, -179.98);
}

TEST(FloorToEarth, BearingConventions) {
    const LatLon at{49.46115, 11.11115};
    const TangentPlane plane(at);
    auto east_north = [&](double bearing, Point p) {
        return plane.to_plane(FloorToEarth({at, {0, 0}, bearing}).to_geodetic(p));
    };
    // Bearing 90°: the floor's +y points east, so its +x (a quarter turn clockwise) points south.
    EXPECT_NEAR(east_north(90, {0, 10}).east, 10.0, 1e-6);
    EXPECT_NEAR(east_north(90, {0, 10}).north, 0.0, 1e-6);
    EXPECT_NEAR(east_north(90, {10, 0}).east, 0.0, 1e-6);
    EXPECT_NEAR(east_north(90, {10, 0}).north, -10.0, 1e-6);
    // Bearing 0: +y north, +x east. Bearing 180: +y south. Bearing 30: +y at 30° east of north.
    EXPECT_NEAR(east_north(0, {3, 4}).east, 3.0, 1e-6);
    EXPECT_NEAR(east_north(0, {3, 4}).north, 4.0, 1e-6);
    EXPECT_NEAR(east_north(180, {0, 10}).north, -10.0, 1e-6);
    EXPECT_NEAR(east_north(30, {0, 10}).east, 5.0, 1e-6);
    EXPECT_NEAR(east_north(30, {0, 10}).north, 10.0 * std::sqrt(3.0) / 2.0, 1e-6);
}

TEST(FloorToEarth, AnchorIsTheGivenPointAndRoundTrips) {
    const Georeference g{{49.46115181, 11.11114911}, {40, 12.5}, 339.264};
    const FloorToEarth f(g);
    const LatLon a = f.to_geodetic({40, 12.5});
    EXPECT_NEAR(a.lat, 49.46115181, 1e-12);
    EXPECT_NEAR(a.lon, 11.11114911, 1e-12);
    for (const Point p : {Point{0, 0}, Point{100, 50}, Point{-250, 900}, Point{40.001, 12.5}}) {
        const Point back = f.to_floor(f.to_geodetic(p));
        EXPECT_NEAR(back.x, p.x, 1e-6);
        EXPECT_NEAR(back.y, p.y, 1e-6);
    }
}

// Control points at the IPIN venue from a known rigid transform: floor (50, 25) at the floor
// maps' calibration centre (49.46115181, 11.11114911), +y at bearing 339.264°. Their Earth
// positions are computed here by the README's equirectangular rule (north radius 6 372 360 m,
// east 6 390 503 m × cos 49.46115°), good to about a centimetre over the venue:
//   east = dx·cos b + dy·sin b, north = −dx·sin b + dy·cos b,
//   lat = lat0 + north / 6 372 360 (rad), lon = lon0 + east / (6 390 503 · 0.6499635) (rad).
std::vector<ControlPoint> venue_points(double floor_scale = 1.0) {
    const double b = 339.264 * kRad;
    std::vector<ControlPoint> out;
    for (const Point p : {Point{0, 0}, Point{100, 0}, Point{100, 50}, Point{0, 50}}) {
        const double dx = p.x - 50, dy = p.y - 25;
        const double e = dx * std::cos(b) + dy * std::sin(b), n = -dx * std::sin(b) + dy * std::cos(b);
        out.push_back({{50 + (p.x - 50) * floor_scale, 25 + (p.y - 25) * floor_scale},
                       {49.46115181 + n / 6372360.0 / kRad, 11.11114911 + e / (6390503.0 * 0.6499635) / kRad}});
    }
    return out;
}

TEST(FitGeoreference, RecoversAKnownRigidTransform) {
    const auto r = fit_georeference(venue_points());
    ASSERT_TRUE(r.fit) << static_cast<int>(*r.problem);
    const auto& f = *r.fit;
    EXPECT_NEAR(f.georeference.anchor.x, 50.0, 1e-9);
    EXPECT_NEAR(f.georeference.anchor.y, 25.0, 1e-9);
    EXPECT_NEAR(f.georeference.at.lat, 49.46115181, 2e-7);  // 2 cm
    EXPECT_NEAR(f.georeference.at.lon, 11.11114911, 3e-7);
    EXPECT_NEAR(f.georeference.bearing_deg, 339.264, 0.01);
    EXPECT_NEAR(f.scale, 1.0, 2e-4);
    ASSERT_EQ(f.residuals_m.size(), 4u);
    for (double res : f.residuals_m) EXPECT_LT(res, 0.03);
    EXPECT_LT(f.rms_m, 0.03);
}

TEST(FitGeoreference, ThreePointsAreEnoughAndBearingWrapsPastNorth) {
    auto pts = venue_points();
    pts.pop_back();
    const auto r = fit_georeference(pts);
    ASSERT_TRUE(r.fit);
    EXPECT_NEAR(r.fit->georeference.bearing_deg, 339.264, 0.01);
    EXPECT_NEAR(r.fit->georeference.anchor.x, 200.0 / 3.0, 1e-9);
    EXPECT_NEAR(r.fit->georeference.anchor.y, 50.0 / 3.0, 1e-9);
}

// Floor coordinates drawn at half scale: the Earth distances are twice the floor's. The fit
// says so (scale 2) and, metres staying metres, the rigid residuals show the disagreement:
// each corner sits half its distance from the centre, √(50² + 25²)/2 = 27.95 m, off.
TEST(FitGeoreference, ReportsScaleAndResidualsWhenControlPointsDisagreeWithMetres) {
    const auto r = fit_georeference(venue_points(0.5));
    ASSERT_TRUE(r.fit);
    EXPECT_NEAR(r.fit->scale, 2.0, 1e-3);
    for (double res : r.fit->residuals_m) EXPECT_NEAR(res, 27.95, 0.05);
    EXPECT_NEAR(r.fit->rms_m, 27.95, 0.05);
    EXPECT_NEAR(r.fit->georeference.bearing_deg, 339.264, 0.01);
}

TEST(FitGeoreference, RefusesWhatCannotBeFitted) {
    auto pts = venue_points();
    pts.resize(2);
    EXPECT_EQ(fit_georeference(pts).problem, FitProblem::too_few);
    EXPECT_EQ(fit_georeference({}).problem, FitProblem::too_few);
    // Three points on one line, and three at one place.
    const LatLon g{49.4611, 11.1111};
    EXPECT_EQ(fit_georeference({{{0, 0}, g}, {{10, 10}, {49.4612, 11.1112}}, {{20, 20}, {49.4613, 11.1113}}}).problem,
              FitProblem::collinear);
    EXPECT_EQ(fit_georeference({{{5, 5}, g}, {{5, 5}, g}, {{5, 5}, g}}).problem, FitProblem::collinear);
    // 0.5° of latitude is 55 km: no campus.
    EXPECT_EQ(fit_georeference({{{0, 0}, g}, {{10, 0}, g}, {{0, 10}, {49.9611, 11.1111}}}).problem, FitProblem::too_spread);
}

TEST(NormaliseBearing, IntoZeroTo360) {
    EXPECT_DOUBLE_EQ(normalise_bearing(-90), 270.0);
    EXPECT_DOUBLE_EQ(normalise_bearing(360), 0.0);
    EXPECT_DOUBLE_EQ(normalise_bearing(720.5), 0.5);
    EXPECT_DOUBLE_EQ(normalise_bearing(0), 0.0);
    EXPECT_LT(normalise_bearing(-1e-17), 360.0);
}

}  // namespace
}  // namespace geo_test
