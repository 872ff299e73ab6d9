#include "locus/imaging/plan_from_image.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "locus/plan/check.hpp"

namespace locus::imaging {

namespace {

using Contour = std::vector<cv::Point>;

// A gap narrower than this does not let anyone through: the outline of a cupboard or a duct
// with such a gap still shuts it.
constexpr double kPocketGapM = 0.6;

// A round structuring element about `metres` across, at least 3 pixels (odd, so it is centred).
cv::Mat disc(double metres, double px_per_m) {
    int d = static_cast<int>(std::lround(metres * px_per_m));
    d = std::max(3, d | 1);
    return cv::getStructuringElement(cv::MORPH_ELLIPSE, {d, d});
}

// The image's pixel (u, v), its centre, in floor metres: the image's y points down, the plan's up.
struct ToMetres {
    double px_per_m;
    int height;
    Point operator()(const cv::Point& p) const {
        return {(p.x + 0.5) / px_per_m, (height - (p.y + 0.5)) / px_per_m};
    }
};

std::vector<Point> polyline(const Contour& c, const ToMetres& to_m) {
    std::vector<Point> out;
    out.reserve(c.size() + 1);
    for (const auto& p : c) out.push_back(to_m(p));
    return out;
}

plan::Ring ring(const Contour& c, const ToMetres& to_m) {
    auto r = polyline(c, to_m);
    if (!r.empty()) r.push_back(r.front());
    return r;
}

Contour simplify(const Contour& c, double epsilon_px) {
    if (epsilon_px <= 0.0) return c;
    Contour out;
    cv::approxPolyDP(c, out, epsilon_px, true);
    return out;
}

// `mask` (0/255) with each 8-connected piece kept when it passes `keep` (given the piece's
// label counts) and cleared otherwise.
cv::Mat keep_labelled(const cv::Mat& mask, const cv::Mat& labels, const std::vector<std::uint8_t>& kept) {
    cv::Mat out(mask.size(), CV_8U);
    for (int y = 0; y < mask.rows; ++y) {
        const int* l = labels.ptr<int>(y);
        auto* o = out.ptr<std::uint8_t>(y);
        for (int x = 0; x < mask.cols; ++x) o[x] = kept[static_cast<std::size_t>(l[x])];
    }
    return out;
}

// The pieces of `mask` whose bounding box passes keep(width, height).
template <typename Keep>
cv::Mat keep_components(const cv::Mat& mask, Keep keep) {
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
    std::vector<std::uint8_t> kept(static_cast<std::size_t>(n), 0);
    for (int i = 1; i < n; ++i)
        if (keep(stats.at<int>(i, cv::CC_STAT_WIDTH), stats.at<int>(i, cv::CC_STAT_HEIGHT))) kept[static_cast<std::size_t>(i)] = 255;
    return keep_labelled(mask, labels, kept);
}

// The pieces of `mask` holding at least min_pixels pixels that are also set in `counted`.
cv::Mat keep_components(const cv::Mat& mask, const cv::Mat& counted, double min_pixels) {
    cv::Mat labels;
    const int n = cv::connectedComponents(mask, labels, 8, CV_32S);
    std::vector<double> count(static_cast<std::size_t>(n), 0.0);
    for (int y = 0; y < mask.rows; ++y) {
        const int* l = labels.ptr<int>(y);
        const auto* c = counted.ptr<std::uint8_t>(y);
        for (int x = 0; x < mask.cols; ++x)
            if (c[x]) count[static_cast<std::size_t>(l[x])] += 1.0;
    }
    std::vector<std::uint8_t> kept(static_cast<std::size_t>(n), 0);
    for (int i = 1; i < n; ++i)
        if (count[static_cast<std::size_t>(i)] >= min_pixels) kept[static_cast<std::size_t>(i)] = 255;
    return keep_labelled(mask, labels, kept);
}

// The strokes' middle lines, one pixel wide (Zhang and Suen's thinning, 1984): a wall is its
// stroke's middle rather than its outline, so a point on a wall (a surveyed position, a phone's
// estimate) is beside the wall instead of shut inside its outline. OpenCV has thinning only in
// its contrib modules, which Debian does not package apart from the whole of contrib.
cv::Mat thin(const cv::Mat& mask) {
    cv::Mat img;
    cv::copyMakeBorder(mask, img, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    img /= 255;
    std::vector<cv::Point> drop;
    for (bool changed = true; changed;) {
        changed = false;
        for (int pass = 0; pass < 2; ++pass) {
            drop.clear();
            for (int y = 1; y + 1 < img.rows; ++y) {
                const auto* up = img.ptr<std::uint8_t>(y - 1);
                const auto* row = img.ptr<std::uint8_t>(y);
                const auto* down = img.ptr<std::uint8_t>(y + 1);
                for (int x = 1; x + 1 < img.cols; ++x) {
                    if (!row[x]) continue;
                    // Neighbours clockwise from north: p2 … p9.
                    const int p[8] = {up[x], up[x + 1], row[x + 1], down[x + 1], down[x], down[x - 1], row[x - 1], up[x - 1]};
                    int b = 0, a = 0;
                    for (int i = 0; i < 8; ++i) b += p[i], a += (!p[i] && p[(i + 1) % 8]);
                    if (b < 2 || b > 6 || a != 1) continue;
                    const bool ok = pass == 0 ? (!(p[0] && p[2] && p[4]) && !(p[2] && p[4] && p[6]))
                                              : (!(p[0] && p[2] && p[6]) && !(p[0] && p[4] && p[6]));
                    if (ok) drop.push_back({x, y});
                }
            }
            for (const auto& q : drop) img.at<std::uint8_t>(q) = 0;
            changed = changed || !drop.empty();
        }
    }
    return img(cv::Rect(1, 1, mask.cols, mask.rows)) * 255;
}

// Everything not reachable from the border through `open` (4-connected, as people cannot
// squeeze through a diagonal pixel gap).
cv::Mat enclosed(const cv::Mat& open) {
    cv::Mat labels;
    const int n = cv::connectedComponents(open, labels, 4, CV_32S);
    std::vector<std::uint8_t> outside(static_cast<std::size_t>(n), 0);
    const int w = open.cols, h = open.rows;
    auto mark = [&](int x, int y) {
        if (open.at<std::uint8_t>(y, x)) outside[static_cast<std::size_t>(labels.at<int>(y, x))] = 1;
    };
    for (int x = 0; x < w; ++x) mark(x, 0), mark(x, h - 1);
    for (int y = 0; y < h; ++y) mark(0, y), mark(w - 1, y);
    cv::Mat out(open.size(), CV_8U);
    for (int y = 0; y < h; ++y) {
        const int* l = labels.ptr<int>(y);
        const auto* o = open.ptr<std::uint8_t>(y);
        auto* d = out.ptr<std::uint8_t>(y);
        for (int x = 0; x < w; ++x) d[x] = (o[x] && outside[static_cast<std::size_t>(l[x])]) ? 0 : 255;
    }
    return out;
}

void check_options(const GreyImage& image, const FromImageOptions& o) {
    if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("the image is empty");
    if (image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
        throw std::invalid_argument("the image has " + std::to_string(image.pixels.size()) + " pixels, not width × height");
    auto positive = [](double v, const char* name) {
        if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string(name) + " must be a positive number");
    };
    positive(o.px_per_m, "px_per_m");
    positive(o.merge_m, "merge_m");
    positive(o.close_m, "close_m");
    positive(o.solid_m, "solid_m");
    if (!(o.simplify_m >= 0.0) || !std::isfinite(o.simplify_m)) throw std::invalid_argument("simplify_m must be 0 or more");
    if (!(o.min_wall_m >= 0.0) || !std::isfinite(o.min_wall_m)) throw std::invalid_argument("min_wall_m must be 0 or more");
    if (!(o.min_space_m2 >= 0.0) || !std::isfinite(o.min_space_m2))
        throw std::invalid_argument("min_space_m2 must be 0 or more");
    if (o.threshold < 1 || o.threshold > 255) throw std::invalid_argument("threshold must be within [1, 255]");
    // The plan's own bounds (check.hpp): refuse here with the reason rather than emit a plan the
    // server refuses.
    const double w_m = image.width / o.px_per_m, h_m = image.height / o.px_per_m;
    if (w_m * h_m > plan::kMaxPlanArea)
        throw std::invalid_argument("at " + std::to_string(o.px_per_m) + " px/m the image covers " + std::to_string(w_m) +
                                    " m × " + std::to_string(h_m) + " m, more than a plan may (" +
                                    std::to_string(plan::kMaxPlanArea) + " m²): is px_per_m right?");
}

// The space of one outer ring and its holes, simplified as much as epsilon allows while the
// rings stay simple and the holes inside: check_plan decides, and each failure halves epsilon.
std::optional<plan::Space> space_of(const Contour& outer, const std::vector<const Contour*>& holes, double epsilon_px,
                                    const ToMetres& to_m) {
    for (double eps = epsilon_px;; eps /= 2.0) {
        const bool last = eps < 0.25;
        const double e = last ? 0.0 : eps;
        plan::Plan one;
        plan::Space s;
        s.kind = "free";
        s.shape.outer = ring(simplify(outer, e), to_m);
        for (const auto* h : holes) {
            auto r = simplify(*h, e);
            if (r.size() >= 3) s.shape.holes.push_back(ring(r, to_m));
        }
        if (s.shape.outer.size() < 4) return std::nullopt;
        one.spaces.push_back(s);
        if (plan::check_plan(one).empty()) return s;
        if (last) {
            // Pixel-exact rings that still touch themselves (a one-pixel neck): keep the outline
            // without its holes if that is sound, else give the piece up.
            one.spaces.front().shape.holes.clear();
            if (plan::check_plan(one).empty()) return one.spaces.front();
            return std::nullopt;
        }
    }
}

}  // namespace

plan::Plan plan_from_image(const GreyImage& image, const FromImageOptions& o, FromImageStats* stats) {
    check_options(image, o);
    const double ppm = o.px_per_m;
    const ToMetres to_m{ppm, image.height};
    const double epsilon_px = o.simplify_m * ppm;

    cv::Mat grey(image.height, image.width, CV_8U, const_cast<std::uint8_t*>(image.pixels.data()));
    cv::Mat ink;
    cv::threshold(grey, ink, o.threshold - 1, 255, cv::THRESH_BINARY_INV);  // grey < threshold

    // Strokes: double lines and hatching merged, specks (text, dimension marks) dropped.
    cv::Mat strokes;
    cv::morphologyEx(ink, strokes, cv::MORPH_CLOSE, disc(o.merge_m, ppm));
    const double min_extent = o.min_wall_m * ppm;
    strokes = keep_components(strokes, [&](int w, int h) { return std::max(w, h) >= min_extent; });

    // The inside: whatever a disc close_m across cannot reach from the image's border without
    // touching a stroke, so a gap narrower than that (an entrance, a window left blank) does
    // not let the outside in. The disc's centres are where the dilated strokes are not; the
    // outside is the disc swept over the centres reachable from the border. The image gets a
    // blank frame first so that the border is outside even for a building drawn to the edge.
    const cv::Mat bridge = disc(o.close_m, ppm);
    const int frame = bridge.cols + 1;
    cv::Mat framed, centres, outside;
    cv::copyMakeBorder(strokes, framed, frame, frame, frame, frame, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::dilate(framed, centres, bridge);
    cv::dilate(~enclosed(~centres), outside, bridge);
    cv::Mat inside = ~outside(cv::Rect(frame, frame, strokes.cols, strokes.rows));
    const double min_area_px = o.min_space_m2 * ppm * ppm;
    cv::Mat solid;
    cv::morphologyEx(strokes, solid, cv::MORPH_OPEN, disc(o.solid_m, ppm));
    // Pockets shut in by strokes and smaller than a space (ducts, cupboards, the box around a
    // pillar) are solid too: a position snapped into one would be cut off from everything.
    // Their walls are drawn round them, not through them. Gaps in their outline narrower than
    // anyone passes (kPocketGapM; often just pixels lighter than the threshold) do not open them.
    // Found as the places a disc kPocketGapM across fits (a disc cannot pass such a gap, which
    // closing would not seal in a thin line): a pocket's region of them is smaller than a
    // square space's, (side − gap)², and its pixels are what that disc covers from there.
    const cv::Mat person = disc(kPocketGapM, ppm);
    cv::Mat reach, pockets;
    cv::dilate(strokes, reach, person);
    const cv::Mat standing = inside & ~reach;
    const double side = std::sqrt(min_area_px) - person.cols;
    cv::dilate(standing & ~keep_components(standing, standing, side > 1.0 ? side * side : 1.0), pockets, person);
    pockets &= inside & ~strokes;
    inside &= ~(solid | pockets);
    // One-pixel necks would make rings that touch themselves.
    cv::morphologyEx(inside, inside, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
    // A piece is a space when it has room to stand in: strokes alone (a wall left outside the
    // outline, a facade line) are not.
    inside = keep_components(inside, ~strokes, min_area_px);

    plan::Plan plan;
    FromImageStats st;

    std::vector<Contour> contours;
    std::vector<cv::Vec4i> tree;
    cv::findContours(inside, contours, tree, cv::RETR_CCOMP, cv::CHAIN_APPROX_NONE);
    for (std::size_t i = 0; i < contours.size(); ++i) {
        if (tree[i][3] >= 0) continue;  // a hole: taken with its outer ring
        std::vector<const Contour*> holes;
        for (int h = tree[i][2]; h >= 0; h = tree[static_cast<std::size_t>(h)][0])
            if (std::abs(cv::contourArea(contours[static_cast<std::size_t>(h)])) >= min_area_px / 4.0)
                holes.push_back(&contours[static_cast<std::size_t>(h)]);
        if (auto s = space_of(contours[i], holes, epsilon_px, to_m)) {
            st.holes += s->shape.holes.size();
            st.space_points += s->shape.outer.size();
            for (const auto& h : s->shape.holes) st.space_points += h.size();
            plan.spaces.push_back(std::move(*s));
        }
    }
    st.spaces = plan.spaces.size();

    // Walls: the middle line of every stroke, pockets filled (a line round a cupboard would
    // enclose a walkable speck). Solid blocks are holes already; their own middle lines would
    // only repeat them. Contours of one-pixel lines trace every line twice (once from each
    // side), so each contour is cut into the runs of pixels no earlier contour took, and each
    // run, simplified, is a wall.
    const cv::Mat lines = thin((strokes | pockets) & ~solid);
    contours.clear();
    cv::findContours(lines, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    cv::Mat taken = cv::Mat::zeros(lines.size(), CV_8U);
    auto add_wall = [&](const Contour& run, bool closed) {
        if (run.size() < 2) return;
        Contour simple;
        cv::approxPolyDP(run, simple, epsilon_px, closed);
        if (simple.size() < 2 || (simple.size() == 2 && simple[0] == simple[1])) return;
        if (closed) simple.push_back(simple.front());
        plan::Wall w;
        w.line = polyline(simple, to_m);
        st.wall_points += w.line.size();
        plan.walls.push_back(std::move(w));
    };
    for (const auto& c : contours) {
        Contour run;
        for (const auto& q : c) {
            auto& t = taken.at<std::uint8_t>(q);
            if (t) {
                // Keep the run joined to the pixel it meets, so walls meet without a gap.
                if (!run.empty()) run.push_back(q), add_wall(run, false), run.clear();
                continue;
            }
            if (run.empty() && &q != &c.front()) run.push_back(*(&q - 1));
            t = 1;
            run.push_back(q);
        }
        add_wall(run, run.size() == c.size() && c.size() > 2);  // a loop no other contour shares: closed
    }
    st.walls = plan.walls.size();
    if (stats) *stats = st;
    return plan;
}

}  // namespace locus::imaging
