#pragma once
// A survey made by walking (docs/survey.md "Walking surveys"): a surveyor walks between marked
// points (landmarks) with a logger that scans as it goes, and stamps the time each landmark is
// stepped on. Between two consecutive landmarks on one floor the walker is taken to move at a
// constant speed along the straight segment, so a scan's position is the linear interpolation
// in time between the landmarks around it. Between landmarks on different floors the walker
// is on stairs or in a lift: no floor position, those scans are skipped (and counted), as are
// scans before the first landmark and after the last.
//
// Then how the radio map stores them: a walking scan's position is uncertain (~1.2 m/s during a
// 2–4 s scan), so consecutive scans may be pooled into bins of `cell` metres along the path,
// one RP per bin at the centroid of its scans (cell 0: one RP per scan).
//
// Pure: no I/O. Costs: positioning is O(landmarks + scans) (both in time order); binning O(scans).
#include <cstddef>
#include <optional>
#include <vector>

#include "locus/geometry.hpp"

namespace locus::survey {

// A marked point the walker stepped on at time t (seconds on the scans' clock), in the frame
// of floor `floor` (metres).
struct Landmark {
    double t = 0.0;
    int floor = 0;
    Point at;
};

// Where the walker was at one instant.
struct WalkPosition {
    int floor = 0;
    Point at;
    // Distance walked along the landmark segments since the first landmark, metres (across
    // floors too: a floor change adds nothing). Used to bin along the path.
    double path_m = 0.0;
    // Index of the same-floor span (a run of consecutive same-floor landmarks) it is in: two
    // positions in different spans are never binned together.
    std::size_t span = 0;
};

// Why an instant has no position.
enum class Unplaced { before_first, after_last, floor_change };

struct Placement {
    std::optional<WalkPosition> position;
    std::optional<Unplaced> why;  // set exactly when position is not
};

// The walk's position at time t. Landmarks must be in non-decreasing time order (throws
// std::invalid_argument otherwise, or when empty). An instant exactly on a landmark gets that
// landmark's position; landmarks sharing a time (a zero-length step) take the later one.
// O(log landmarks).
Placement place(const std::vector<Landmark>& landmarks, double t);

struct PositionedScan {
    std::size_t scan = 0;  // index into the caller's scan times
    double t = 0.0;
    WalkPosition where;
};

struct WalkPlacements {
    std::vector<PositionedScan> placed;  // in the order of the scan times given
    std::size_t before_first = 0, after_last = 0, floor_change = 0;  // skipped, by reason
};

// place() for every scan time (any order). O(scans · log landmarks).
WalkPlacements place_scans(const std::vector<Landmark>& landmarks, const std::vector<double>& scan_times);

// One future RP: the scans pooled into it and their centroid.
struct Bin {
    int floor = 0;
    Point at;                          // centroid of its scans' positions
    std::vector<std::size_t> members;  // indices into the `placed` vector given to bin_along_path
};

// Pools placed scans (in time order) into bins: a scan joins the current bin when it is on
// the same floor and span and at most `cell_m` metres along the path from the bin's first
// scan; otherwise it starts a new bin. cell_m 0 gives one bin per scan; a pause (several scans
// at one place) always shares a bin when cell_m > 0. Throws std::invalid_argument for a
// negative or non-finite cell_m. O(scans).
std::vector<Bin> bin_along_path(const std::vector<PositionedScan>& placed, double cell_m);

}  // namespace locus::survey
