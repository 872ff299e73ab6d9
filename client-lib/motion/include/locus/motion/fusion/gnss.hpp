#pragma once
// GNSS indoors as a walk filter's position measurement: how much a fix is trusted and how often
// one is taken. One place for the settings `locus eval ipin`'s trackers (tools/ipin_track.hpp) and
// the server's live tracks (server/tracks/fusion.hpp) both run, chosen on the IPIN 2023 walks
// (docs/results.md, "IPIN 2023"): a receiver's accuracy indoors is honest on the ground floor
// (3-5 m off) and optimistic below it (~10 m, tail 17-26 m: the data set's README), and its
// errors last (multipath moves slowly), so fixes a second apart are not independent looks.
// Every fix at σ ≥ 5 m pulled the track off (walk_pf's p75 1.7 m worse on fold 01); σ ≥ 10 m,
// one fix per 10 s was kept.
namespace locus::fusion {

// A fix's σ (m) is its reported accuracy, at least this.
inline constexpr double kGnssMinSigmaM = 10.0;
// At most one fix per this many seconds.
inline constexpr double kGnssMinIntervalS = 10.0;
// A Kalman filter drops a fix beyond this squared Mahalanobis distance (χ², 2 dof: 99 %).
inline constexpr double kGnssGateChi2 = 9.21;

}  // namespace locus::fusion
