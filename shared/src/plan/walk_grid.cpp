#include "locus/plan/walk_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "locus/plan/check.hpp"
#include "locus/plan/ring.hpp"

namespace locus::plan {

namespace {

struct Interval {
    double t0, t1;
};

// [0, 1] minus the union of `cuts`, as sorted disjoint intervals.
std::vector<Interval> remaining(std::vector<Interval> cuts, Interval whole = {0.0, 1.0}) {
    std::sort(cuts.begin(), cuts.end(), [](Interval a, Interval b) { return a.t0 < b.t0; });
    std::vector<Interval> out;
    double from = whole.t0;
    for (const Interval& c : cuts) {
        if (c.t0 > from) out.push_back({from, std::min(c.t0, whole.t1)});
        from = std::max(from, c.t1);
        if (from >= whole.t1) break;
    }
    if (from < whole.t1) out.push_back({from, whole.t1});
    return out;
}

Point lerp(Point a, Point b, double t) { return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; }

// The part of segment ab inside the disc (centre, radius), as a parameter interval.
bool disc_interval(Point a, Point b, Point centre, double radius, Interval& out) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double fx = a.x - centre.x, fy = a.y - centre.y;
    const double qa = dx * dx + dy * dy, qb = 2.0 * (fx * dx + fy * dy), qc = fx * fx + fy * fy - radius * radius;
    if (qa == 0.0) return false;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc <= 0.0) return false;
    const double root = std::sqrt(disc);
    out = {std::max(0.0, (-qb - root) / (2.0 * qa)), std::min(1.0, (-qb + root) / (2.0 * qa))};
    return out.t0 < out.t1;
}

Point nearest_on_line(Point p, const std::vector<Point>& line, double& dist) {
    Point best = line.front();
    dist = INFINITY;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const Point a = line[i], b = line[i + 1];
        const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
        const double t = len2 == 0.0 ? 0.0 : std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0);
        const Point q = lerp(a, b, t);
        const double d = distance(p, q);
        if (d < dist) {
            dist = d;
            best = q;
        }
    }
    return best;
}

struct DoorGap {
    std::size_t wall;
    Point centre;  // on the wall
    double radius;
};

// A door cuts the nearest wall, and any other wall drawn on top of it (rooms drawn with their
// own walls double the shared one), but not a wall that merely passes near it.
std::vector<DoorGap> door_gaps(const Plan& plan) {
    constexpr double kDuplicateWallSlack = 0.05;
    std::vector<DoorGap> gaps;
    for (const Door& door : plan.doors) {
        const Point mid{(door.a.x + door.b.x) / 2.0, (door.a.y + door.b.y) / 2.0};
        const double width = distance(door.a, door.b) > 0.0 ? distance(door.a, door.b) : kDefaultDoorWidth;
        std::vector<double> dist(plan.walls.size(), INFINITY);
        std::vector<Point> at(plan.walls.size());
        double nearest = INFINITY;
        for (std::size_t w = 0; w < plan.walls.size(); ++w) {
            if (plan.walls[w].line.size() < 2) continue;
            at[w] = nearest_on_line(mid, plan.walls[w].line, dist[w]);
            nearest = std::min(nearest, dist[w]);
        }
        for (std::size_t w = 0; w < plan.walls.size(); ++w)
            if (dist[w] <= kDoorWallTolerance && dist[w] <= nearest + kDuplicateWallSlack) gaps.push_back({w, at[w], width / 2.0});
    }
    return gaps;
}

// Buckets of spaces by bounding box, so "is this point walkable" looks at a few polygons.
class SpaceIndex {
public:
    SpaceIndex(const Plan& plan, Bounds all) : plan_(plan), all_(all) {
        cols_ = std::max(1, static_cast<int>(std::ceil((all.xmax - all.xmin) / kBucket)));
        rows_ = std::max(1, static_cast<int>(std::ceil((all.ymax - all.ymin) / kBucket)));
        buckets_.resize(static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_));
        for (std::size_t s = 0; s < plan.spaces.size(); ++s) {
            const Bounds b = bounds_of(plan.spaces[s].shape.outer);
            boxes_.push_back(b);
            for (int r = row(b.ymin); r <= row(b.ymax); ++r)
                for (int c = col(b.xmin); c <= col(b.xmax); ++c) buckets_[static_cast<std::size_t>(r * cols_ + c)].push_back(s);
        }
    }
    bool walkable(Point p) const {
        if (!all_.contains(p)) return false;
        for (std::size_t s : buckets_[static_cast<std::size_t>(row(p.y) * cols_ + col(p.x))])
            if (boxes_[s].contains(p) && polygon_contains(plan_.spaces[s].shape, p)) return true;
        return false;
    }

private:
    static constexpr double kBucket = 4.0;
    int col(double x) const { return std::clamp(static_cast<int>((x - all_.xmin) / kBucket), 0, cols_ - 1); }
    int row(double y) const { return std::clamp(static_cast<int>((y - all_.ymin) / kBucket), 0, rows_ - 1); }
    const Plan& plan_;
    Bounds all_;
    int cols_ = 1, rows_ = 1;
    std::vector<Bounds> boxes_;
    std::vector<std::vector<std::size_t>> buckets_;
};

// Pieces of the spaces' rings with walkable space on one side only: the outline of the union.
// Rings are cut into cell-sized pieces and each piece is tested on both sides.
void add_outline(const Plan& plan, const SpaceIndex& index, double piece, std::vector<Segment>& out) {
    constexpr double kSide = 0.01;
    const auto add_ring = [&](const Ring& ring) {
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
            const Point a = ring[i], b = ring[i + 1];
            const double len = distance(a, b);
            if (len == 0.0) continue;
            const Point normal{-(b.y - a.y) / len * kSide, (b.x - a.x) / len * kSide};
            const int n = std::max(1, static_cast<int>(std::ceil(len / piece)));
            int run_start = -1;
            for (int k = 0; k <= n; ++k) {
                bool edge = false;
                if (k < n) {
                    const Point m = lerp(a, b, (k + 0.5) / n);
                    edge = index.walkable({m.x + normal.x, m.y + normal.y}) != index.walkable({m.x - normal.x, m.y - normal.y});
                }
                if (edge && run_start < 0) run_start = k;
                if (!edge && run_start >= 0) {
                    out.push_back({lerp(a, b, static_cast<double>(run_start) / n), lerp(a, b, static_cast<double>(k) / n)});
                    run_start = -1;
                }
            }
        }
    };
    for (const Space& s : plan.spaces) {
        add_ring(s.shape.outer);
        for (const Ring& h : s.shape.holes) add_ring(h);
    }
}

Bounds plan_bounds(const Plan& plan) {
    Bounds all{INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (const Space& s : plan.spaces) {
        const Bounds b = bounds_of(s.shape.outer);
        all = {std::min(all.xmin, b.xmin), std::min(all.ymin, b.ymin), std::max(all.xmax, b.xmax), std::max(all.ymax, b.ymax)};
    }
    if (plan.spaces.empty()) return {};
    return all;
}

// Scanline fill of each space at the cell centres' rows; the first space to claim a cell keeps it.
void rasterize(const Plan& plan, WalkGrid& g) {
    const double cell = g.options.cell;
    std::vector<double> xs;
    for (std::size_t s = 0; s < plan.spaces.size(); ++s) {
        const Polygon& shape = plan.spaces[s].shape;
        const Bounds b = bounds_of(shape.outer);
        const int r0 = std::max(0, static_cast<int>(std::floor((b.ymin - g.origin.y) / cell - 0.5)));
        const int r1 = std::min(g.rows - 1, static_cast<int>(std::ceil((b.ymax - g.origin.y) / cell - 0.5)));
        for (int r = r0; r <= r1; ++r) {
            const double y = g.origin.y + (r + 0.5) * cell;
            xs.clear();
            const auto crossings = [&](const Ring& ring) {
                for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
                    const Point a = ring[i], c = ring[i + 1];
                    if ((a.y > y) != (c.y > y)) xs.push_back(a.x + (y - a.y) * (c.x - a.x) / (c.y - a.y));
                }
            };
            crossings(shape.outer);
            for (const Ring& h : shape.holes) crossings(h);
            std::sort(xs.begin(), xs.end());
            for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
                const int c0 = std::max(0, static_cast<int>(std::ceil((xs[k] - g.origin.x) / cell - 0.5)));
                const int c1 = std::min(g.cols - 1, static_cast<int>(std::floor((xs[k + 1] - g.origin.x) / cell - 0.5)));
                for (int c = c0; c <= c1; ++c) {
                    auto& slot = g.space[static_cast<std::size_t>(r * g.cols + c)];
                    if (slot < 0) slot = static_cast<std::int32_t>(s);
                }
            }
        }
    }
}

// Calls f(cell) for every cell whose centre lies in the box around segment ab grown by `margin`.
template <typename F>
void cells_near(const WalkGrid& g, Segment s, double margin, F&& f) {
    const double cell = g.options.cell;
    const int c0 = std::max(0, static_cast<int>(std::floor((std::min(s.a.x, s.b.x) - margin - g.origin.x) / cell)));
    const int c1 = std::min(g.cols - 1, static_cast<int>(std::floor((std::max(s.a.x, s.b.x) + margin - g.origin.x) / cell)));
    const int r0 = std::max(0, static_cast<int>(std::floor((std::min(s.a.y, s.b.y) - margin - g.origin.y) / cell)));
    const int r1 = std::min(g.rows - 1, static_cast<int>(std::floor((std::max(s.a.y, s.b.y) + margin - g.origin.y) / cell)));
    for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c) f(r * g.cols + c);
}

}  // namespace

Point WalkGrid::centre(int cell) const {
    return {origin.x + (cell % cols + 0.5) * options.cell, origin.y + (cell / cols + 0.5) * options.cell};
}

int WalkGrid::cell_at(Point p) const {
    const double fc = std::floor((p.x - origin.x) / options.cell), fr = std::floor((p.y - origin.y) / options.cell);
    if (!(fc >= 0.0 && fr >= 0.0 && fc < cols && fr < rows)) return -1;
    return static_cast<int>(fr) * cols + static_cast<int>(fc);
}

std::vector<std::uint32_t> WalkGrid::barriers_near(Point a, Point b) const {
    std::vector<std::uint32_t> out;
    // Samples every half bucket; the 3 × 3 buckets round each reach past bucket_m / 2 of the segment.
    const int n = std::max(1, static_cast<int>(std::ceil(distance(a, b) / (bucket_m / 2.0))));
    int last_bc = -1000, last_br = -1000;
    for (int i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / n;
        const int bc = static_cast<int>(std::floor((a.x + t * (b.x - a.x) - origin.x) / bucket_m));
        const int br = static_cast<int>(std::floor((a.y + t * (b.y - a.y) - origin.y) / bucket_m));
        if (bc == last_bc && br == last_br) continue;
        last_bc = bc;
        last_br = br;
        for (int r = std::max(0, br - 1); r <= std::min(bucket_rows - 1, br + 1); ++r)
            for (int c = std::max(0, bc - 1); c <= std::min(bucket_cols - 1, bc + 1); ++c) {
                const auto& list = buckets[static_cast<std::size_t>(r * bucket_cols + c)];
                out.insert(out.end(), list.begin(), list.end());
            }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

bool WalkGrid::crosses_barrier(Point a, Point b) const {
    for (std::uint32_t i : barriers_near(a, b)) {
        const Segment& s = i < walls.size() ? walls[i] : jambs[i - walls.size()];
        if (segments_intersect(a, b, s.a, s.b)) return true;
    }
    return false;
}

bool WalkGrid::keeps_clearance(Point a, Point b) const {
    for (std::uint32_t i : barriers_near(a, b)) {
        const bool jamb = i >= walls.size();
        const Segment& s = jamb ? jambs[i - walls.size()] : walls[i];
        if (segments_intersect(a, b, s.a, s.b)) return false;
        if (jamb) continue;
        const double d = std::min(std::min(distance_to_segment(a, s.a, s.b), distance_to_segment(b, s.a, s.b)),
                                  std::min(distance_to_segment(s.a, a, b), distance_to_segment(s.b, a, b)));
        if (d < options.clearance) return false;
    }
    return true;
}

int WalkGrid::snap(Point p, const std::vector<std::uint8_t>* blocked, bool straight_line) const {
    const int reach = static_cast<int>(std::ceil(kSnapRadius / options.cell));
    const int hc = static_cast<int>(std::floor((p.x - origin.x) / options.cell));
    const int hr = static_cast<int>(std::floor((p.y - origin.y) / options.cell));
    std::vector<std::pair<double, int>> candidates;
    for (int r = std::max(0, hr - reach); r <= std::min(rows - 1, hr + reach); ++r)
        for (int c = std::max(0, hc - reach); c <= std::min(cols - 1, hc + reach); ++c) {
            const int cell = r * cols + c;
            if (!free(cell) || (blocked && (*blocked)[static_cast<std::size_t>(cell)])) continue;
            const double d = distance(p, centre(cell));
            if (d <= kSnapRadius) candidates.emplace_back(d, cell);
        }
    std::sort(candidates.begin(), candidates.end());
    for (const auto& [d, cell] : candidates)
        if (!straight_line || !crosses_barrier(p, centre(cell))) return cell;
    return -1;
}

double WalkGrid::clearance_threshold() const {
    const double half_diagonal = options.cell * std::sqrt(0.5);
    return std::sqrt(options.clearance * options.clearance + half_diagonal * half_diagonal);
}

double WalkGrid::door_clear_radius() const { return clearance_threshold() + 0.75 * options.cell; }

namespace {
// Cells across a side of the plan's box.
double grid_span(double metres, const GridOptions& options) { return std::ceil(metres / options.cell); }
}  // namespace

double walk_grid_cells(const Plan& plan, const GridOptions& options) {
    const Bounds all = plan_bounds(plan);
    return std::max(1.0, grid_span(all.xmax - all.xmin, options)) * std::max(1.0, grid_span(all.ymax - all.ymin, options));
}

WalkGrid build_walk_grid(const Plan& plan, const GridOptions& options) {
    WalkGrid g;
    g.options = options;
    const Bounds all = plan_bounds(plan);
    g.origin = {all.xmin, all.ymin};
    // check_plan bounds a stored plan's area; a grid past it (or past int) is a caller's bug.
    const double cols = grid_span(all.xmax - all.xmin, options), rows = grid_span(all.ymax - all.ymin, options);
    if (!(cols * rows <= 4.0 * kMaxPlanArea / (options.cell * options.cell) + 1e6))
        throw std::length_error("a walk grid of " + std::to_string(cols * rows) + " cells: the plan is too large");
    g.cols = std::max(1, static_cast<int>(cols));
    g.rows = std::max(1, static_cast<int>(rows));
    const auto n = static_cast<std::size_t>(g.cell_count());
    g.flags.assign(n, 0);
    g.moves.assign(n, 0);
    g.space.assign(n, -1);
    rasterize(plan, g);

    // Walls, cut twice: at the real door gaps (what may not be crossed) and at the widened
    // gaps (what clearance is measured from); the difference is the jambs.
    std::vector<Segment>& clearance_barriers = g.walls;
    const std::vector<DoorGap> gaps = door_gaps(plan);
    const double widened = g.door_clear_radius();
    for (std::size_t w = 0; w < plan.walls.size(); ++w) {
        const auto& line = plan.walls[w].line;
        for (std::size_t i = 0; i + 1 < line.size(); ++i) {
            const Point a = line[i], b = line[i + 1];
            std::vector<Interval> real, wide;
            for (const DoorGap& gap : gaps) {
                if (gap.wall != w) continue;
                Interval t;
                if (disc_interval(a, b, gap.centre, gap.radius, t)) real.push_back(t);
                if (disc_interval(a, b, gap.centre, std::max(gap.radius, widened), t)) wide.push_back(t);
            }
            for (const Interval& t : remaining(wide)) clearance_barriers.push_back({lerp(a, b, t.t0), lerp(a, b, t.t1)});
            for (const Interval& widened_gap : remaining(remaining(wide)))
                for (const Interval& t : remaining(real, widened_gap)) g.jambs.push_back({lerp(a, b, t.t0), lerp(a, b, t.t1)});
        }
    }
    const SpaceIndex index(plan, all);
    add_outline(plan, index, options.cell, clearance_barriers);

    g.bucket_m = std::max(2.0, 4.0 * options.clearance);
    g.bucket_cols = static_cast<int>(std::ceil(g.cols * options.cell / g.bucket_m)) + 1;
    g.bucket_rows = static_cast<int>(std::ceil(g.rows * options.cell / g.bucket_m)) + 1;
    g.buckets.resize(static_cast<std::size_t>(g.bucket_cols) * static_cast<std::size_t>(g.bucket_rows));
    for (std::size_t i = 0; i < g.walls.size() + g.jambs.size(); ++i) {
        const Segment& s = i < g.walls.size() ? g.walls[i] : g.jambs[i - g.walls.size()];
        const auto bucket = [&](double v, double o, int count) { return std::clamp(static_cast<int>(std::floor((v - o) / g.bucket_m)), 0, count - 1); };
        for (int r = bucket(std::min(s.a.y, s.b.y), g.origin.y, g.bucket_rows); r <= bucket(std::max(s.a.y, s.b.y), g.origin.y, g.bucket_rows); ++r)
            for (int c = bucket(std::min(s.a.x, s.b.x), g.origin.x, g.bucket_cols); c <= bucket(std::max(s.a.x, s.b.x), g.origin.x, g.bucket_cols); ++c)
                g.buckets[static_cast<std::size_t>(r * g.bucket_cols + c)].push_back(static_cast<std::uint32_t>(i));
    }

    // Distance from each centre to the nearest wall, only needed up to the threshold.
    const double threshold = g.clearance_threshold();
    const double cap = threshold + options.cell;
    std::vector<float> clearance(n, static_cast<float>(cap));
    for (const Segment& s : clearance_barriers)
        cells_near(g, s, cap, [&](int c) {
            auto& d = clearance[static_cast<std::size_t>(c)];
            d = std::min(d, static_cast<float>(distance_to_segment(g.centre(c), s.a, s.b)));
        });
    for (std::size_t c = 0; c < n; ++c)
        if (g.space[c] >= 0 && clearance[c] >= threshold) g.flags[c] |= WalkGrid::kFree;
    for (const Segment& j : g.jambs) cells_near(g, j, options.cell, [&](int c) { g.flags[static_cast<std::size_t>(c)] |= WalkGrid::kNearJamb; });

    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.cols; ++c) {
            const int from = r * g.cols + c;
            if (!g.free(from)) continue;
            for (int d = 0; d < 8; ++d) {
                const int nc = c + kDirCol[d], nr = r + kDirRow[d];
                if (nc < 0 || nr < 0 || nc >= g.cols || nr >= g.rows) continue;
                const int to = nr * g.cols + nc;
                if (!g.free(to)) continue;
                if ((g.flags[static_cast<std::size_t>(from)] | g.flags[static_cast<std::size_t>(to)]) & WalkGrid::kNearJamb) {
                    const Point p = g.centre(from), q = g.centre(to);
                    if (std::any_of(g.jambs.begin(), g.jambs.end(), [&](const Segment& j) { return segments_intersect(p, q, j.a, j.b); }))
                        continue;
                }
                g.moves[static_cast<std::size_t>(from)] |= static_cast<std::uint8_t>(1u << d);
            }
        }

    // A connector joins the grid at the nearest free cell it can reach in a straight line.
    for (const Connector& con : plan.connectors) {
        const int cell = g.snap(con.at, nullptr, true);
        g.connector_cell.push_back(cell);
        if (cell >= 0) g.flags[static_cast<std::size_t>(cell)] |= WalkGrid::kConnector;
    }
    return g;
}

}  // namespace locus::plan
