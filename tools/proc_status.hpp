#pragma once
// What Linux says of a running process in /proc/PID/status: its resident memory now (VmRSS)
// and at its peak (VmHWM), for the memory benchmarks and the tests that bound a server's
// memory; and in /proc/PID/stat the CPU time it has used, for the load benchmarks. One small
// file read per call.
#include <string>

namespace locus::tools {

// The value of one `Field:` line of /proc/PID/status in kB (e.g. "VmHWM:"); -1 when the
// process or the field is not there.
long long proc_status_kb(int pid, const std::string& field);

// The CPU time process `pid` has used so far, user and system (utime + stime, fields 14 and
// 15 of /proc/PID/stat), in seconds; -1 when the process is not there.
double proc_cpu_seconds(int pid);

}  // namespace locus::tools
