// tracks::FusionSessions' locking: a thin client's filter run holds its own track's lock, so
// another track's run goes on while it waits (here inside its scans, as a run does while it
// localizes), one track's runs take turns, and a track forgotten during a run keeps no filter.
// Ordering only, with latches and flags; no timing is asserted (a broken lock shows as a
// wait that never ends, cut short by a generous bound, or as a step out of turn).
// Eigen first (tracks/fusion.hpp): see tracks/fusion_sessions.hpp.
#include "tracks/fusion.hpp"
#include "tracks/fusion_sessions.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "store/sql_store.hpp"
#include "temp_dir.hpp"
#include "tracks/run_sources.hpp"

namespace fusion_sessions_test {
namespace {

namespace tracks = locus::tracks;

// A flag one thread raises and another waits for, at most `bound` (then false).
class Flag {
public:
    void raise() {
        std::lock_guard lock(mu_);
        up_ = true;
        cv_.notify_all();
    }
    bool wait(std::chrono::seconds bound = std::chrono::seconds(20)) {
        std::unique_lock lock(mu_);
        return cv_.wait_for(lock, bound, [this] { return up_; });
    }
    bool up() {
        std::lock_guard lock(mu_);
        return up_;
    }

private:
    std::mutex mu_;
    std::condition_variable cv_;
    bool up_ = false;
};

// Sources whose scans, asked during the run, say so and then wait for `release`.
class WaitingSources : public tracks::RunSources {
public:
    Flag inside, release;
    bool released = false;
    std::shared_ptr<const locus::geo::FloorToEarth> georeference(std::int64_t) override { return nullptr; }
    std::vector<tracks::Fix> scans(tracks::ScanMemory&, std::optional<double>, const std::optional<tracks::Fix>&) override {
        inside.raise();
        released = release.wait();
        return {};
    }
};

// The one floor of the test's store: it has no plan, so walk_pf walks freely.
constexpr std::int64_t kFloor = 1;

tracks::RadioFix fix_at(double t, double x) {
    tracks::RadioFix f;
    f.t = t;
    f.floor_id = kFloor;
    f.x = x;
    f.y = 5.0;
    f.accuracy_m = 2.0;
    return f;
}

// One run of track `id` to its end (kept): a fix at t, then a step.
void run_to_end(tracks::FusionSessions& sessions, std::int64_t id, double t, tracks::RunSources* sources = nullptr) {
    auto run = sessions.begin(id);
    run.run(tracks::FusionMethod::walk_pf, {}, std::nullopt, {{t + 1, 0.7, 90.0}}, {fix_at(t, 10.0)}, {}, {}, nullptr, sources);
    run.keep();
}

struct Sessions : ::testing::Test {
    locus::testing::TempDir dir{"fusion-sessions"};
    locus::store::SqlStore store{dir.path()};
    tracks::FusionSessions sessions{store};
    void SetUp() override {
        using locus::store::kind;
        const auto map = store.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
        const auto building = store.create(kind("buildings"), map, {{"name", "B"}}).id;
        ASSERT_EQ(store.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 50.0}, {"height", 10.0}}).id, kFloor);
    }
};

TEST_F(Sessions, AnotherTracksRunGoesOnWhileOneWaitsInsideItsRun) {
    WaitingSources waiting;
    auto first = std::async(std::launch::async, [&] { run_to_end(sessions, 1, 100.0, &waiting); });
    ASSERT_TRUE(waiting.inside.wait());
    // Track 1's run is inside its scans until released: track 2's runs to its end meanwhile.
    auto second = std::async(std::launch::async, [&] { run_to_end(sessions, 2, 100.0); });
    const bool second_done = second.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
    waiting.release.raise();
    first.get();
    EXPECT_TRUE(second_done) << "track 2's run waited for track 1's";
    EXPECT_TRUE(waiting.released);
}

TEST_F(Sessions, OneTracksRunsTakeTurns) {
    WaitingSources waiting;
    auto first = std::async(std::launch::async, [&] { run_to_end(sessions, 1, 100.0, &waiting); });
    ASSERT_TRUE(waiting.inside.wait());
    std::atomic<bool> second_began{false};
    auto second = std::async(std::launch::async, [&] {
        auto run = sessions.begin(1);
        second_began = true;
        // It continues the filter the first run kept: steps alone, no fix, are fused.
        const auto fixes = run.run(tracks::FusionMethod::walk_pf, {}, std::nullopt, {{102.0, 0.7, 90.0}}, {}, {}, {}, nullptr, nullptr);
        run.keep();
        return fixes.size();
    });
    // While the first run waits, the second has not begun (it would fuse a step with no filter).
    EXPECT_EQ(second.wait_for(std::chrono::milliseconds(200)), std::future_status::timeout);
    EXPECT_FALSE(second_began);
    waiting.release.raise();
    first.get();
    EXPECT_EQ(second.get(), 1u);
}

TEST_F(Sessions, ATrackForgottenDuringItsRunKeepsNoFilter) {
    WaitingSources waiting;
    auto first = std::async(std::launch::async, [&] { run_to_end(sessions, 1, 100.0, &waiting); });
    ASSERT_TRUE(waiting.inside.wait());
    auto forgetting = std::async(std::launch::async, [&] { sessions.forget({1}); });
    const bool forgot = forgetting.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
    waiting.release.raise();
    first.get();
    EXPECT_TRUE(forgot) << "forget waited for the track's run";
    // No filter held: steps without a fix cannot be fused.
    auto run = sessions.begin(1);
    EXPECT_THROW(run.run(tracks::FusionMethod::walk_pf, {}, std::nullopt, {{102.0, 0.7, 90.0}}, {}, {}, {}, nullptr, nullptr),
                 std::invalid_argument);
    // A track not forgotten keeps its filter: steps alone are fused.
    run_to_end(sessions, 2, 100.0);
    auto again = sessions.begin(2);
    EXPECT_EQ(again.run(tracks::FusionMethod::walk_pf, {}, std::nullopt, {{102.0, 0.7, 90.0}}, {}, {}, {}, nullptr, nullptr).size(), 1u);
}

}  // namespace
}  // namespace fusion_sessions_test
