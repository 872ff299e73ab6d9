#include "locus/motion/fusion/walk_runner.hpp"

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace locus::fusion {

namespace {

constexpr std::size_t slot(EventKind kind) { return static_cast<std::size_t>(kind); }

std::string name_of(EventKind kind) {
    switch (kind) {
        case EventKind::pressure: return "pressure";
        case EventKind::step: return "step";
        case EventKind::fix: return "fix";
        case EventKind::tick: return "tick";
    }
    return "event";
}

// Of the heads given (nullopt: that stream has nothing to offer), the one taken next: the
// kinds in tie order, a later one winning only when strictly earlier than the best so far,
// exactly as `a.t <= b.t ? a : b` picks between two streams. nullopt when every head is.
template <typename HeadOf>
std::optional<EventKind> next_kind(const TieOrder& ties, HeadOf&& head_of) {
    std::optional<EventKind> best;
    double best_t = 0.0;
    for (const EventKind kind : ties) {
        const std::optional<double> t = head_of(kind);
        if (!t) continue;
        if (!best || !(best_t <= *t)) best = kind, best_t = *t;
    }
    return best;
}

// Visits every event of the streams in order.
template <typename Visit>
void merge(const WalkStreams& streams, const TieOrder& ties, Visit&& visit) {
    std::array<std::size_t, kEventKinds> at{};
    const auto head_of = [&](EventKind kind) -> std::optional<double> {
        const auto s = streams.of(kind);
        return at[slot(kind)] < s.size() ? std::optional<double>(s[at[slot(kind)]]) : std::nullopt;
    };
    while (const auto kind = next_kind(ties, head_of)) {
        const std::size_t i = at[slot(*kind)]++;
        visit(WalkEvent{streams.of(*kind)[i], *kind, i});
    }
}

}  // namespace

std::span<const double> WalkStreams::of(EventKind kind) const {
    switch (kind) {
        case EventKind::pressure: return pressure;
        case EventKind::step: return step;
        case EventKind::fix: return fix;
        case EventKind::tick: return tick;
    }
    return {};
}

const std::function<void(std::size_t)>& WalkHandlers::of(EventKind kind) const {
    switch (kind) {
        case EventKind::pressure: return pressure;
        case EventKind::step: return step;
        case EventKind::fix: return fix;
        case EventKind::tick: return tick;
    }
    return tick;
}

MergedStream merge_sources(std::initializer_list<std::span<const double>> sources) {
    const std::vector<std::span<const double>> src(sources);
    std::vector<std::size_t> next(src.size(), 0);
    std::size_t total = 0;
    for (const auto& s : src) total += s.size();
    MergedStream out;
    out.t.reserve(total);
    out.source.reserve(total);
    out.index.reserve(total);
    for (std::size_t n = 0; n < total; ++n) {
        std::size_t best = src.size();
        for (std::size_t k = 0; k < src.size(); ++k)
            if (next[k] < src[k].size() && (best == src.size() || src[k][next[k]] < src[best][next[best]])) best = k;
        out.t.push_back(src[best][next[best]]);
        out.source.push_back(best);
        out.index.push_back(next[best]++);
    }
    return out;
}

std::vector<WalkEvent> time_order(const WalkStreams& streams, const TieOrder& ties) {
    std::vector<WalkEvent> out;
    out.reserve(streams.pressure.size() + streams.step.size() + streams.fix.size() + streams.tick.size());
    merge(streams, ties, [&](const WalkEvent& e) { out.push_back(e); });
    return out;
}

void run_walk(const WalkStreams& streams, const WalkHandlers& handlers, const TieOrder& ties) {
    for (const EventKind kind : ties)
        if (!streams.of(kind).empty() && !handlers.of(kind))
            throw std::invalid_argument("run_walk: " + std::to_string(streams.of(kind).size()) + " " + name_of(kind) +
                                        " events and no handler for them");
    merge(streams, ties, [&](const WalkEvent& e) { handlers.of(e.kind)(e.index); });
}

WalkRunner::WalkRunner(WalkHandlers handlers, const TieOrder& ties) : handlers_(std::move(handlers)), ties_(ties) {
    for (const EventKind kind : ties_) streams_[slot(kind)].open = static_cast<bool>(handlers_.of(kind));
}

void WalkRunner::push(EventKind kind, double t_s) {
    Stream& s = streams_[slot(kind)];
    if (!s.open)
        throw std::invalid_argument("WalkRunner: a " + name_of(kind) + " event, and that stream " +
                                    (handlers_.of(kind) ? "was closed" : "has no handler"));
    s.waiting.push_back(t_s);
    deliver();
}

void WalkRunner::close(EventKind kind) {
    streams_[slot(kind)].open = false;
    deliver();
}

void WalkRunner::finish() {
    for (Stream& s : streams_) s.open = false;
    deliver();
}

std::size_t WalkRunner::held() const {
    std::size_t n = 0;
    for (const Stream& s : streams_) n += s.waiting.size();
    return n;
}

void WalkRunner::deliver() {
    const auto head_of = [this](EventKind kind) -> std::optional<double> {
        const Stream& s = streams_[slot(kind)];
        return s.waiting.empty() ? std::nullopt : std::optional<double>(s.waiting.front());
    };
    for (;;) {
        // An open stream with nothing waiting may yet bring an event that goes first.
        for (const Stream& s : streams_)
            if (s.open && s.waiting.empty()) return;
        const auto kind = next_kind(ties_, head_of);
        if (!kind) return;
        Stream& s = streams_[slot(*kind)];
        s.waiting.pop_front();
        handlers_.of(*kind)(s.next_index++);  // counted as delivered even if the handler throws
    }
}

}  // namespace locus::fusion
