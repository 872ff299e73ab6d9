#pragma once
// One walk's events taken in time order and fed to a filter: the loop every evaluation, the
// replay and the server's thin-client path share (docs/fusion.md, "One walk runner"). A walk is
// a few streams, each already in the order its events are to be taken: PDR steps, radio fixes,
// barometer pressure samples, and ticks (instants an estimate is wanted at, as the IPIN scoring's
// 2 Hz). The runner knows only each event's kind, time and place in its stream; what an event
// holds stays with the caller, whose handlers look it up by that place. So any filter (the
// Kalman, particle and walk filters, the ranging EKF, the fusion rules, the barometric floor)
// takes its events through one small interface, a handler per kind.
//
// Order. The next event is the head of one stream: the earliest, and at equal times the one whose
// kind comes first in the TieOrder. The heads are compared as a two-way merge compares them (a
// stream later in the tie order goes first only when its head is strictly earlier), so a stream
// that is not in time order is walked as it stands, never sorted. Events of one stream keep their
// order. The rule is deterministic: the same streams give the same sequence.
//  - kStepsFirst (evaluations, `locus sim`, `locus replay`, `locus eval walks`, `locus eval ipin`):
//    pressure, then step, then fix, then tick. A fix at a step's instant is taken after the step
//    (the scan saw the walker where the step put them); a pressure sample before both; a tick last,
//    so an estimate at t has everything stamped t.
//  - kFixesFirst (the server's thin clients, server/tracks/fusion.hpp): a radio fix before a step
//    of equal time, as that API has always documented.
// A new kind of event (a floor change, say) is a new EventKind, a place in both orders and a
// handler slot: the merge itself does not change.
//
// Two forms. Batch: time_order (the sequence) and run_walk (the sequence fed to the handlers),
// for a whole recording. Push: WalkRunner, for events that arrive one at a time (a live track):
// it holds an event until every stream still open has one waiting, so whatever the arrival
// interleaving it delivers exactly the batch form's sequence; close() a stream that has ended.
//
// Cost, n events over k kinds (k = 4): time_order and run_walk O(n·k) time, time_order one
// 24-byte WalkEvent per event, run_walk no memory of its own. WalkRunner O(k) per event pushed,
// holding the events that wait for the slowest open stream (a deque of times per kind). Pure:
// no I/O, no threads.
#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <initializer_list>
#include <span>
#include <vector>

namespace locus::fusion {

enum class EventKind : std::uint8_t { pressure, step, fix, tick };
inline constexpr std::size_t kEventKinds = 4;

// The kinds in the order they are taken at equal times: order[0] first. Each kind once.
using TieOrder = std::array<EventKind, kEventKinds>;
inline constexpr TieOrder kStepsFirst = {EventKind::pressure, EventKind::step, EventKind::fix, EventKind::tick};
inline constexpr TieOrder kFixesFirst = {EventKind::pressure, EventKind::fix, EventKind::step, EventKind::tick};

struct WalkEvent {
    double t_s = 0.0;
    EventKind kind = EventKind::step;
    std::size_t index = 0;  // its place in its own stream (0 for the stream's first event)
    bool operator==(const WalkEvent&) const = default;
};

// Each stream's event times, in the order its events are to be taken. An empty span: no
// events of that kind.
struct WalkStreams {
    std::span<const double> pressure = {}, step = {}, fix = {}, tick = {};
    std::span<const double> of(EventKind kind) const;
};

// The filter's side: a handler per kind, called with the event's index in its stream. A kind
// with no handler takes no events.
struct WalkHandlers {
    std::function<void(std::size_t)> pressure, step, fix, tick;
    const std::function<void(std::size_t)>& of(EventKind kind) const;
};

// The times of a stream's items, for WalkStreams: times_of(steps, &PdrStep::t_s).
template <typename Range, typename Time>
std::vector<double> times_of(const Range& items, Time time) {
    std::vector<double> out;
    out.reserve(items.size());
    for (const auto& item : items) out.push_back(static_cast<double>(item.*time));
    return out;
}

// Several sources of one kind merged into one stream (a tracker's radio answers, GNSS fixes and
// beacon fixes are all `fix` events): each source's times in its own order, heads compared as
// time_order compares them (a later source goes first only when strictly earlier), so at equal
// times the earlier source's event comes first. `t` is the merged stream's times, for
// WalkStreams; `source[k]` and `index[k]` say where its k-th event came from. O(n·sources).
struct MergedStream {
    std::vector<double> t;
    std::vector<std::size_t> source, index;
};
MergedStream merge_sources(std::initializer_list<std::span<const double>> sources);

// Batch: every event of the streams, in order.
std::vector<WalkEvent> time_order(const WalkStreams& streams, const TieOrder& ties = kStepsFirst);

// Batch, fed: each event in order to its kind's handler. A stream with events and no handler
// throws std::invalid_argument before any handler runs; an exception from a handler stops the walk.
void run_walk(const WalkStreams& streams, const WalkHandlers& handlers, const TieOrder& ties = kStepsFirst);

// Push: events given one at a time, delivered to the handlers in the batch form's order. The
// streams open are those with a handler.
class WalkRunner {
public:
    explicit WalkRunner(WalkHandlers handlers, const TieOrder& ties = kStepsFirst);

    // The next event of its kind's stream (its index: how many of that kind came before); then
    // every event whose place is settled is delivered. std::invalid_argument for a kind with no
    // handler or one closed.
    void push(EventKind kind, double t_s);
    // No more events of this kind; what waited on it may now be delivered.
    void close(EventKind kind);
    // Closes every stream: everything held is delivered.
    void finish();
    // Events pushed and not yet delivered.
    std::size_t held() const;

private:
    struct Stream {
        std::deque<double> waiting;
        std::size_t next_index = 0;  // index of waiting.front()
        bool open = false;
    };
    void deliver();

    WalkHandlers handlers_;
    TieOrder ties_;
    std::array<Stream, kEventKinds> streams_;
};

}  // namespace locus::fusion
