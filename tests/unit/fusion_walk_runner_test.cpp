// The walk runner (locus/motion/fusion/walk_runner.hpp): the order it takes a walk's events in, its tie
// rules, empty streams, a stream out of time order, the handlers, and the push form against the
// batch form. Every expected sequence is written out by hand from the streams above it.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "locus/motion/fusion/walk_runner.hpp"

namespace fusion_walk_runner_test {
namespace {

using namespace locus::fusion;

WalkEvent ev(EventKind kind, double t, std::size_t index) { return {t, kind, index}; }

constexpr EventKind P = EventKind::pressure, S = EventKind::step, F = EventKind::fix, T = EventKind::tick;

// Every kind, with a tie of all four at t = 2 (two steps there).
const std::vector<double> kPressure = {2.0}, kSteps = {1.0, 2.0, 2.0, 4.0}, kFixes = {0.5, 2.0, 3.0}, kTicks = {2.0, 5.0};

WalkStreams all_kinds() { return {.pressure = kPressure, .step = kSteps, .fix = kFixes, .tick = kTicks}; }

const std::vector<WalkEvent> kStepsFirstOrder = {ev(F, 0.5, 0), ev(S, 1.0, 0), ev(P, 2.0, 0), ev(S, 2.0, 1), ev(S, 2.0, 2),
                                                 ev(F, 2.0, 1), ev(T, 2.0, 0), ev(F, 3.0, 2), ev(S, 4.0, 3), ev(T, 5.0, 1)};

// Handlers that write down what reached them, as "s1" for the step of index 1.
struct Log {
    std::vector<std::string> seen;
    void record(char kind, std::size_t i) {
        std::string name(1, kind);
        name += std::to_string(i);
        seen.push_back(name);
    }
    WalkHandlers handlers(bool with_pressure = true, bool with_tick = true) {
        WalkHandlers h;
        if (with_pressure) h.pressure = [this](std::size_t i) { record('p', i); };
        h.step = [this](std::size_t i) { record('s', i); };
        h.fix = [this](std::size_t i) { record('f', i); };
        if (with_tick) h.tick = [this](std::size_t i) { record('t', i); };
        return h;
    }
};

using Names = std::vector<std::string>;

TEST(WalkRunner, StepsFirstTakesPressureThenStepsThenFixesThenTicksAtEqualTimes) {
    EXPECT_EQ(time_order(all_kinds()), kStepsFirstOrder);
    EXPECT_EQ(time_order(all_kinds(), kStepsFirst), kStepsFirstOrder);  // the default
}

TEST(WalkRunner, FixesFirstTakesAFixBeforeAStepOfItsInstant) {
    const std::vector<WalkEvent> expected = {ev(F, 0.5, 0), ev(S, 1.0, 0), ev(P, 2.0, 0), ev(F, 2.0, 1), ev(S, 2.0, 1),
                                             ev(S, 2.0, 2), ev(T, 2.0, 0), ev(F, 3.0, 2), ev(S, 4.0, 3), ev(T, 5.0, 1)};
    EXPECT_EQ(time_order(all_kinds(), kFixesFirst), expected);
}

TEST(WalkRunner, EmptyStreams) {
    EXPECT_TRUE(time_order({}).empty());
    Log log;
    run_walk({}, log.handlers());
    run_walk({}, WalkHandlers{});  // no events need no handler
    EXPECT_TRUE(log.seen.empty());
    // One stream alone is walked as it is.
    const std::vector<double> fixes = {1.0, 1.0, 7.0};
    EXPECT_EQ(time_order({.fix = fixes}), (std::vector<WalkEvent>{ev(F, 1.0, 0), ev(F, 1.0, 1), ev(F, 7.0, 2)}));
}

TEST(WalkRunner, AStreamOutOfTimeOrderIsMergedAsItStandsNotSorted) {
    // A two-way merge of heads: step 1 (1 ≤ 3), then fix 3 (5 > 3), then step 5 and step 2.
    const std::vector<double> steps = {1.0, 5.0, 2.0}, fixes = {3.0};
    EXPECT_EQ(time_order({.step = steps, .fix = fixes}),
              (std::vector<WalkEvent>{ev(S, 1.0, 0), ev(F, 3.0, 0), ev(S, 5.0, 1), ev(S, 2.0, 2)}));
}

TEST(WalkRunner, RunWalkCallsEachKindsHandlerWithTheIndexInItsStream) {
    Log log;
    run_walk(all_kinds(), log.handlers());
    EXPECT_EQ(log.seen, (Names{"f0", "s0", "p0", "s1", "s2", "f1", "t0", "f2", "s3", "t1"}));

    log.seen.clear();
    run_walk(all_kinds(), log.handlers(), kFixesFirst);
    EXPECT_EQ(log.seen, (Names{"f0", "s0", "p0", "f1", "s1", "s2", "t0", "f2", "s3", "t1"}));
}

TEST(WalkRunner, EventsWithNoHandlerAreRefusedBeforeAnyHandlerRuns) {
    Log log;
    EXPECT_THROW(run_walk(all_kinds(), log.handlers(true, false)), std::invalid_argument);  // ticks, no tick handler
    EXPECT_TRUE(log.seen.empty());
    // Without ticks the same handlers are enough.
    run_walk({.pressure = kPressure, .step = kSteps, .fix = kFixes}, log.handlers(true, false));
    EXPECT_EQ(log.seen, (Names{"f0", "s0", "p0", "s1", "s2", "f1", "f2", "s3"}));
}

TEST(WalkRunner, AHandlersExceptionStopsTheWalk) {
    std::vector<std::size_t> steps_seen;
    WalkHandlers h;
    h.step = [&](std::size_t i) { steps_seen.push_back(i); };
    h.fix = [](std::size_t) { throw std::runtime_error("bad fix"); };
    const std::vector<double> steps = {1.0, 2.0, 3.0}, fixes = {2.0};
    EXPECT_THROW(run_walk({.step = steps, .fix = fixes}, h), std::runtime_error);
    EXPECT_EQ(steps_seen, (std::vector<std::size_t>{0, 1}));  // the steps at 1 and 2, then the fix at 2
}

TEST(WalkRunner, PushedInAnyInterleavingGivesTheBatchSequence) {
    const Names batch = {"f0", "s0", "p0", "s1", "s2", "f1", "t0", "f2", "s3", "t1"};
    // Stream by stream: nothing is settled until every stream has shown an event.
    {
        Log log;
        WalkRunner runner(log.handlers());
        for (double t : kFixes) runner.push(F, t);
        for (double t : kTicks) runner.push(T, t);
        for (double t : kSteps) runner.push(S, t);
        EXPECT_TRUE(log.seen.empty());
        EXPECT_EQ(runner.held(), 9u);
        for (double t : kPressure) runner.push(P, t);
        // Pressure 2 settles fix 0.5 and step 1 (both earlier) and itself; then the pressure
        // stream is empty and open again, so step 2 waits.
        EXPECT_EQ(log.seen, (Names{"f0", "s0", "p0"}));
        runner.finish();
        EXPECT_EQ(log.seen, batch);
        EXPECT_EQ(runner.held(), 0u);
    }
    // As a live phone would send them: in time order, a pressure stream closed once it ended.
    {
        Log log;
        WalkRunner runner(log.handlers());
        runner.push(F, 0.5);
        runner.push(S, 1.0);
        runner.push(P, 2.0);
        runner.close(P);
        runner.push(T, 2.0);
        runner.push(S, 2.0);
        runner.push(S, 2.0);
        runner.push(F, 2.0);
        runner.push(F, 3.0);
        runner.push(S, 4.0);
        runner.push(T, 5.0);
        // Step 4 waits: a fix might yet come before it.
        EXPECT_EQ(log.seen, (Names{"f0", "s0", "p0", "s1", "s2", "f1", "t0", "f2"}));
        EXPECT_EQ(runner.held(), 2u);
        runner.finish();
        EXPECT_EQ(log.seen, batch);
    }
}

TEST(WalkRunner, PushHoldsAnEventUntilEveryOpenStreamHasOne) {
    Log log;
    WalkRunner runner(log.handlers(false, false));  // steps and fixes only
    runner.push(S, 1.0);
    EXPECT_TRUE(log.seen.empty());  // a fix before t = 1 may yet come
    EXPECT_EQ(runner.held(), 1u);
    runner.push(F, 0.5);
    EXPECT_EQ(log.seen, (Names{"f0"}));  // the fix was earlier; the step waits for the next fix
    runner.push(F, 1.0);
    EXPECT_EQ(log.seen, (Names{"f0", "s0"}));  // a step before a fix of its instant
    runner.close(F);
    EXPECT_EQ(log.seen, (Names{"f0", "s0"}));  // the fix at 1 waits: a step at 1 would go first
    runner.close(S);
    EXPECT_EQ(log.seen, (Names{"f0", "s0", "f1"}));
    EXPECT_THROW(runner.push(F, 2.0), std::invalid_argument);  // closed
    EXPECT_THROW(runner.push(P, 2.0), std::invalid_argument);  // no handler
    EXPECT_EQ(runner.held(), 0u);
}

TEST(WalkRunner, PushWithFixesFirst) {
    Log log;
    WalkRunner runner(log.handlers(false, false), kFixesFirst);
    runner.push(S, 2.0);
    runner.push(F, 2.0);
    EXPECT_EQ(log.seen, (Names{"f0"}));  // the fix goes first; the step waits for the next fix
    runner.finish();
    EXPECT_EQ(log.seen, (Names{"f0", "s0"}));
}

// merge_sources: three sources of fixes, written out by hand. Radio at 1, 3, 3; GNSS at 0, 3;
// beacons at 3, 5. At t = 3 the radio fixes first (in their order), then GNSS, then the beacon.
TEST(WalkRunner, MergedSourcesTakeTheEarlierSourceFirstAtEqualTimes) {
    const std::vector<double> radio = {1, 3, 3}, gnss = {0, 3}, ble = {3, 5};
    const MergedStream m = merge_sources({radio, gnss, ble});
    EXPECT_EQ(m.t, (std::vector<double>{0, 1, 3, 3, 3, 3, 5}));
    EXPECT_EQ(m.source, (std::vector<std::size_t>{1, 0, 0, 0, 1, 2, 2}));
    EXPECT_EQ(m.index, (std::vector<std::size_t>{0, 0, 1, 2, 1, 0, 1}));
    const MergedStream none = merge_sources({{}, {}});
    EXPECT_TRUE(none.t.empty());
    // A source out of time order is walked as it stands, as time_order walks a stream.
    const std::vector<double> late = {4, 2};
    const MergedStream as_is = merge_sources({late, std::vector<double>{3}});
    EXPECT_EQ(as_is.t, (std::vector<double>{3, 4, 2}));
    EXPECT_EQ(as_is.source, (std::vector<std::size_t>{1, 0, 0}));
}

}  // namespace
}  // namespace fusion_walk_runner_test
