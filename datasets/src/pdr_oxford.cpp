#include "datasets/pdr_oxford.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace locus::datasets {

namespace fs = std::filesystem;

namespace {

std::string trim(std::string s) {
    const auto b = s.find_first_not_of(" \t\r");
    const auto e = s.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::string canonical_placement(const std::string& p) {
    static const char* known[] = {"InHand", "FrontPocket", "BackPocket", "Armband", "NeckPouch", "Purse", "SwingingArm"};
    auto lower = [](std::string s) {
        for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return s;
    };
    for (const char* k : known)
        if (lower(k) == lower(p)) return k;
    return p;
}

// stepcounter.csv: timestamp_ns,foot1,foot2; a step is a 0→1 transition of either foot.
long debounced_foot_switch_steps(const std::string& path) {
    std::ifstream in(path);
    if (!in) return 0;
    std::string line;
    long n = 0;
    int p1 = -1, p2 = -1;
    double last = -1e300;
    while (std::getline(in, line)) {
        long long ns = 0;
        int f1 = 0, f2 = 0;
        if (std::sscanf(line.c_str(), "%lld,%d,%d", &ns, &f1, &f2) != 3) continue;
        const double t = static_cast<double>(ns) * 1e-9;
        const bool rise = (p1 == 0 && f1 == 1) || (p2 == 0 && f2 == 1);
        if (rise && t - last >= 0.35) ++n, last = t;
        p1 = f1, p2 = f2;
    }
    return n;
}

long alternating_foot_switch_steps(const std::string& path) {
    std::ifstream in(path);
    if (!in) return 0;
    std::string line;
    long n = 0;
    int p1 = -1, p2 = -1, last_foot = 0;
    while (std::getline(in, line)) {
        long long ns = 0;
        int f1 = 0, f2 = 0;
        if (std::sscanf(line.c_str(), "%lld,%d,%d", &ns, &f1, &f2) != 3) continue;
        for (int foot : {1, 2}) {
            const bool rise = foot == 1 ? (p1 == 0 && f1 == 1) : (p2 == 0 && f2 == 1);
            if (rise && foot != last_foot) ++n, last_foot = foot;
        }
        p1 = f1, p2 = f2;
    }
    return n;
}

}  // namespace

std::vector<OxfordTrace> load_oxford(const std::string& dir_in) {
    fs::path dir(dir_in);
    if (!fs::exists(dir / "stats.csv") && fs::exists(dir / "optimisation" / "stats.csv")) dir /= "optimisation";
    std::ifstream stats(dir / "stats.csv");
    if (!stats) throw std::runtime_error("no stats.csv in " + dir_in + " (expected the Oxford optimisation folder)");
    std::vector<OxfordTrace> out;
    std::string line;
    while (std::getline(stats, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> f;
        std::istringstream in(line);
        std::string cell;
        while (std::getline(in, cell, ',')) f.push_back(trim(cell));
        if (f.size() < 7) continue;
        OxfordTrace t;
        t.name = f[0];
        t.user = f[1];
        t.phone = f[2];
        t.placement = canonical_placement(f[3]);
        t.true_steps = std::stol(f[6]);
        t.samples = read_accel_log((dir / "data" / t.name / "accelerometer.csv").string());
        t.debounced_steps = debounced_foot_switch_steps((dir / "data" / t.name / "stepcounter.csv").string());
        t.alternating_steps = alternating_foot_switch_steps((dir / "data" / t.name / "stepcounter.csv").string());
        out.push_back(std::move(t));
    }
    if (out.empty()) throw std::runtime_error("no traces listed in " + (dir / "stats.csv").string());
    return out;
}

long count_steps(const std::vector<AccelSample>& samples, const pdr::StepDetectorConfig& config) {
    pdr::StepDetector d(config);
    for (const auto& s : samples) d.push(s.t_s, s.ax, s.ay, s.az);
    return static_cast<long>(d.steps());
}

EvalSummary summarise(std::vector<TraceResult> results) {
    EvalSummary s;
    s.traces = std::move(results);
    std::map<std::string, std::pair<double, int>> acc;
    for (const auto& r : s.traces) {
        s.mean_abs_error_pct += r.abs_error_pct;
        auto& a = acc[r.trace->placement];
        a.first += r.abs_error_pct;
        ++a.second;
    }
    if (!s.traces.empty()) s.mean_abs_error_pct /= static_cast<double>(s.traces.size());
    for (const auto& [p, a] : acc) {
        s.placement_mean_pct[p] = a.first / a.second;
        s.worst_placement_pct = std::max(s.worst_placement_pct, a.first / a.second);
    }
    return s;
}

static TraceResult score(const OxfordTrace& t, long detected) {
    return {&t, detected, 100.0 * std::abs(static_cast<double>(detected - t.true_steps)) / static_cast<double>(t.true_steps)};
}

EvalSummary evaluate(const std::vector<const OxfordTrace*>& traces, const pdr::StepDetectorConfig& config) {
    std::vector<TraceResult> r;
    for (const auto* t : traces) r.push_back(score(*t, count_steps(t->samples, config)));
    return summarise(std::move(r));
}

double objective(const EvalSummary& s) { return s.mean_abs_error_pct; }

// The grid of the final search (docs/pdr.md). Its ranges were widened once, after a first
// search put the best bout length and threshold floor on the edge of a narrower grid.
std::vector<pdr::StepDetectorConfig> tuning_grid() {
    std::vector<pdr::StepDetectorConfig> grid;
    for (auto signal : {pdr::StepSignal::vertical, pdr::StepSignal::magnitude})
        for (double smooth : {0.06, 0.08, 0.1, 0.12})
            for (double tmin : {0.3, 0.4, 0.6})
                for (double factor : {0.2, 0.3, 0.4})
                    for (double hyst : {0.25, 0.5})
                        for (int bout : {1, 4, 6, 8, 10, 12})
                            for (double cmin : {0.5, 0.6, 0.7})
                                for (double cmax : {1.3, 1.5, 1.7}) {
                                    if (bout == 1 && (cmin != 0.6 || cmax != 1.3)) continue;  // unused when off
                                    pdr::StepDetectorConfig c;
                                    c.signal = signal;
                                    c.smoothing_s = smooth;
                                    c.min_threshold = tmin;
                                    c.threshold_factor = factor;
                                    c.hysteresis = hyst;
                                    c.bout_steps = bout;
                                    c.cadence_min_ratio = cmin;
                                    c.cadence_max_ratio = cmax;
                                    grid.push_back(c);
                                }
    return grid;
}

CvResult tune_leave_one_user_out(const std::vector<OxfordTrace>& traces, const std::vector<pdr::StepDetectorConfig>& grid,
                                 unsigned threads, const std::function<void(std::size_t, std::size_t)>& progress) {
    // counts[g][t]: steps detected on trace t with grid config g.
    std::vector<std::vector<long>> counts(grid.size(), std::vector<long>(traces.size()));
    std::atomic<std::size_t> next{0}, done{0};
    std::mutex progress_mutex;
    auto worker = [&] {
        for (std::size_t g; (g = next++) < grid.size();) {
            for (std::size_t t = 0; t < traces.size(); ++t) counts[g][t] = count_steps(traces[t].samples, grid[g]);
            const auto d = ++done;
            std::lock_guard lock(progress_mutex);
            if (progress) progress(d, grid.size());
        }
    };
    std::vector<std::thread> pool;
    for (unsigned i = 0; i < std::max(1u, threads); ++i) pool.emplace_back(worker);
    for (auto& th : pool) th.join();

    auto summary_of = [&](std::size_t g, const std::function<bool(const OxfordTrace&)>& keep) {
        std::vector<TraceResult> r;
        for (std::size_t t = 0; t < traces.size(); ++t)
            if (keep(traces[t])) r.push_back(score(traces[t], counts[g][t]));
        return summarise(std::move(r));
    };
    auto best_of = [&](const std::function<bool(const OxfordTrace&)>& keep) {
        std::size_t best = 0;
        double best_obj = 1e300;
        for (std::size_t g = 0; g < grid.size(); ++g) {
            const double o = objective(summary_of(g, keep));
            if (o < best_obj) best_obj = o, best = g;
        }
        return best;
    };

    CvResult cv;
    std::set<std::string> users;
    for (const auto& t : traces) users.insert(t.user);
    std::vector<TraceResult> held;
    for (const auto& u : users) {
        const auto g = best_of([&](const OxfordTrace& t) { return t.user != u; });
        cv.chosen[u] = grid[g];
        for (std::size_t t = 0; t < traces.size(); ++t)
            if (traces[t].user == u) held.push_back(score(traces[t], counts[g][t]));
    }
    cv.held_out = summarise(std::move(held));
    const auto all = best_of([](const OxfordTrace&) { return true; });
    cv.all_traces_best = grid[all];
    cv.all_traces_fit = summary_of(all, [](const OxfordTrace&) { return true; });
    return cv;
}

}  // namespace locus::datasets
