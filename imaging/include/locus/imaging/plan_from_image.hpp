#pragma once
// A floor plan from a scanned or exported drawing: the dark strokes become walls and the area
// they enclose becomes walkable space, in floor metres, ready to be edited and PUT. Pure: the
// caller reads the image file (tools/ does) and passes its pixels.
//
// How: ink is every pixel darker than a threshold. Strokes closer than merge_m are merged (a
// wall drawn as two thin lines becomes one stroke, a hatched block a solid one), specks
// dropped, and each stroke's middle line, simplified, is a wall (one polyline per stretch
// between junctions). The building's inside is what a
// disc close_m across cannot reach from the image's border without touching a stroke, so
// entrances, windows and dashed outer walls narrower than that do not let the outside in; it
// becomes one space per separate piece, with ink blocks thicker than solid_m (shafts, columns)
// as holes. Door gaps between rooms stay open (only the outside is found with the disc).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "locus/plan/plan.hpp"

namespace locus::imaging {

// 8-bit grey pixels, row by row from the top-left: 0 black, 255 white.
struct GreyImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;  // width × height
};

struct FromImageOptions {
    double px_per_m = 0.0;     // the drawing's scale: pixels per metre (required, > 0)
    int threshold = 128;       // grey below this is ink (lighter lines: glass, furniture, hatching of floors)
    double merge_m = 0.25;     // strokes closer than this are one wall
    double close_m = 3.0;      // gaps in the outline up to this (entrances, windows) are bridged to find the inside
    double simplify_m = 0.05;  // largest distance of a simplified outline from the pixels
    double min_wall_m = 0.3;   // strokes whose extent is shorter are noise (text, dots, marks)
    double solid_m = 0.6;      // ink at least this thick everywhere is a hole in the space
    double min_space_m2 = 2.0; // inside pieces smaller than this are dropped
};

struct FromImageStats {
    std::size_t walls = 0;
    std::size_t wall_points = 0;
    std::size_t spaces = 0;
    std::size_t space_points = 0;  // outer rings and holes
    std::size_t holes = 0;
};

// Throws std::invalid_argument for an empty image, pixels that do not match the size, or
// options out of range (naming the option). The result passes plan::check_plan: a ring that
// would self-intersect once simplified is simplified less.
plan::Plan plan_from_image(const GreyImage& image, const FromImageOptions& options, FromImageStats* stats = nullptr);

}  // namespace locus::imaging
