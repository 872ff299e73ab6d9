#pragma once
// A radio map from a model instead of a survey (Le, Saragas and Webb 2009): at each point of a
// grid, each transmitter's RSS by the multi-wall model
//   rss = tx_power − 10·n·log10(d) − wall_attenuation · (walls crossed by the straight path)
// Walls are bucketed in a uniform grid so that a path tests only the walls of the cells it
// crosses: 10,000 points × 200 transmitters × 2,000 walls stays within seconds.
#include <optional>
#include <span>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/ranging/path_loss.hpp"

namespace locus::ranging {

struct ModelledTransmitter {
    Transmitter tx;
    std::optional<double> wall_attenuation;  // dB per wall; none: walls are not modelled
};

// Not safe to share between threads (a query marks the walls it tested): one per thread.
class WallIndex {
public:
    WallIndex(std::vector<Segment> walls, double cell = 2.0);
    // Walls the open segment ab crosses (touching counts), each wall once.
    int crossed(Point a, Point b) const;
    std::size_t size() const { return walls_.size(); }

private:
    std::vector<Segment> walls_;
    double cell_ = 2.0;
    double x0_ = 0, y0_ = 0;
    int nx_ = 0, ny_ = 0;
    std::vector<std::vector<int>> cells_;   // wall indexes per cell
    mutable std::vector<unsigned> stamp_;   // last query that tested each wall
    mutable unsigned query_ = 0;
};

struct ModelledReading {
    std::size_t transmitter = 0;  // index into the transmitters given
    double rss = 0.0;
};

// The RSS of every transmitter heard at `at` above `min_rss` (a phone's detection floor),
// clamped to at most 0 dBm.
std::vector<ModelledReading> modelled_rss(Point at, std::span<const ModelledTransmitter> txs, const WallIndex& walls,
                                          double min_rss);

// The centres of a grid of `step` over the area: (xmin + step/2 + i·step, ymin + step/2 + j·step).
std::vector<Point> grid_points(const Rect& area, double step);

}  // namespace locus::ranging
