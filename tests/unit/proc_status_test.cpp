// tools/proc_status: what /proc says of a process, read for this test's own process (whose
// CPU time grows while it works and whose memory is resident) and for one that is not there.
#include "proc_status.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>

namespace proc_status_test {
namespace {

using locus::tools::proc_cpu_seconds;
using locus::tools::proc_status_kb;

TEST(ProcStatus, CpuTimeGrowsWhileTheProcessWorks) {
    const double before = proc_cpu_seconds(getpid());
    ASSERT_GE(before, 0.0);
    // Work until the clock's tick (1/100 s on Linux) has surely moved the count: 0.2 s of CPU.
    volatile double sink = 0.0;
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
    while (std::chrono::steady_clock::now() < until)
        for (int i = 0; i < 1000; ++i) sink = sink + std::sqrt(static_cast<double>(i));
    const double after = proc_cpu_seconds(getpid());
    EXPECT_GT(after - before, 0.05);
    EXPECT_LT(after - before, 5.0);
}

TEST(ProcStatus, ResidentMemoryOfARunningProcess) {
    const long long rss = proc_status_kb(getpid(), "VmRSS:");
    EXPECT_GT(rss, 0);
    EXPECT_GE(proc_status_kb(getpid(), "VmHWM:"), rss);  // the peak, read after, is at least the RSS then
    EXPECT_EQ(proc_status_kb(getpid(), "NoSuchField:"), -1);
}

TEST(ProcStatus, AProcessThatIsNotThere) {
    EXPECT_EQ(proc_cpu_seconds(999'999'999), -1.0);
    EXPECT_EQ(proc_status_kb(999'999'999, "VmRSS:"), -1);
}

}  // namespace
}  // namespace proc_status_test
