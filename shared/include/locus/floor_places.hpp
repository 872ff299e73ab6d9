#pragma once
// Where a position is, in words (docs/spec.md: the room a walker is in and the checkpoints near
// them, as StepApp showed after every step): a floor's rooms and points of interest, indexed
// for the lookups every answered position makes (a localize answer, a track's fix, a thin
// client's fused fixes, /positions).
//
// Rooms are unions of rectangles (locus::Room); the room at a point is the first in the rooms'
// order whose rectangles hold it, exactly locus::room_at's answer. The index is a uniform grid
// over the rooms' bounding box, about one cell per rectangle (at most kMaxCells), each cell
// listing the rooms whose rectangles touch it in the rooms' order: a lookup is one cell and a
// test of the few rooms listed there, whatever the floor's number of rooms. POIs are few per
// floor and scanned. Pure: no I/O; built once per floor version and shared read-only.
//
// Cost: building O(rectangles × cells each covers); room_at O(rooms listed in one cell);
// nearby O(POIs).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "locus/geometry.hpp"

namespace locus {

// A POI within the radius of a point, and how far.
struct NearbyPoi {
    const Poi* poi = nullptr;
    double distance_m = 0.0;
};

class FloorPlaces {
public:
    static constexpr std::size_t kMaxCells = 1 << 20;

    FloorPlaces(std::vector<Room> rooms, std::vector<Poi> pois);

    // The first room (in the rooms' order) whose rectangles hold p; nullptr when none does.
    const Room* room_at(Point p) const;
    // The POIs within radius_m of p (inclusive), nearest first, ties by id.
    std::vector<NearbyPoi> nearby(Point p, double radius_m = kDefaultCheckpointRadius) const;

    const std::vector<Room>& rooms() const { return rooms_; }
    const std::vector<Poi>& pois() const { return pois_; }
    // What this object holds on the heap and in itself.
    std::size_t memory_bytes() const;

private:
    int cell_of(Point p) const;  // −1 off the grid

    std::vector<Room> rooms_;
    std::vector<Poi> pois_;
    Point origin_;
    double cell_ = 1.0;
    int cols_ = 0, rows_ = 0;
    // The rooms listed in each cell, in the rooms' order: cell c's are
    // room_index_[first_[c]] … room_index_[first_[c + 1] − 1].
    std::vector<std::uint32_t> first_;
    std::vector<std::uint32_t> room_index_;
};

}  // namespace locus
