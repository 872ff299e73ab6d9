// The kept texts of GET /v1/floors/{id}/plan (http/plans/plan_answers.hpp): built once per floor
// and form, shared by the requests that ask during the build, emptied by any change, a failed
// build kept by no one, and texts past the memory bound answered but not kept.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "http/plans/plan_answers.hpp"
#include "store/sql_store.hpp"
#include "temp_dir.hpp"

namespace plan_answers_test {
namespace {

using locus::http::PlanAnswers;
using locus::store::kind;
using locus::store::SqlStore;
using locus::testing::TempDir;

TEST(PlanAnswers, OneBuildServesEveryoneUntilAnythingChanges) {
    TempDir t{"plananswers"};
    SqlStore s(t.path());
    PlanAnswers answers(s);
    std::atomic<int> builds{0};
    const auto build = [&] {
        ++builds;
        std::this_thread::sleep_for(std::chrono::milliseconds(200));  // long enough for the others to arrive
        return std::string("plan v") + std::to_string(builds.load());
    };
    std::vector<std::thread> readers;
    std::vector<std::string> got(8);
    for (std::size_t i = 0; i < got.size(); ++i) readers.emplace_back([&, i] { got[i] = *answers.get(7, false, build); });
    for (auto& r : readers) r.join();
    EXPECT_EQ(builds.load(), 1);
    for (const auto& g : got) EXPECT_EQ(g, "plan v1");
    EXPECT_EQ(*answers.get(7, true, build), "plan v2");  // the other form is its own
    EXPECT_EQ(*answers.get(7, false, build), "plan v1");
    s.create(kind("maps"), std::nullopt, {{"name", "M"}});  // any change
    EXPECT_EQ(*answers.get(7, false, build), "plan v3");
}

TEST(PlanAnswers, AFailedBuildReachesItsWaitersAndIsNotKept) {
    TempDir t{"plananswers"};
    SqlStore s(t.path());
    PlanAnswers answers(s);
    EXPECT_THROW(answers.get(1, false, [] () -> std::string { throw std::runtime_error("no plan"); }), std::runtime_error);
    EXPECT_EQ(*answers.get(1, false, [] { return std::string("now there is"); }), "now there is");
}

TEST(PlanAnswers, TextsPastTheBoundAreAnsweredNotKept) {
    TempDir t{"plananswers"};
    SqlStore s(t.path());
    PlanAnswers answers(s, 10);
    int builds = 0;
    const auto big = [&] {
        ++builds;
        return std::string(8, 'x');
    };
    EXPECT_EQ(answers.get(1, false, big)->size(), 8u);
    EXPECT_EQ(answers.get(1, false, big)->size(), 8u);
    EXPECT_EQ(builds, 1);  // kept: 8 of 10 bytes
    EXPECT_EQ(answers.get(2, false, big)->size(), 8u);
    EXPECT_EQ(answers.get(2, false, big)->size(), 8u);
    EXPECT_EQ(builds, 3);  // 16 would pass the bound: built each time
}

}  // namespace
}  // namespace plan_answers_test
