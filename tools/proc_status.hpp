#pragma once
// What Linux says of a running process in /proc/PID/status: its resident memory now (VmRSS)
// and at its peak (VmHWM), for the memory benchmarks and the tests that bound a server's
// memory. One small file read per call.
#include <string>

namespace locus::tools {

// The value of one `Field:` line of /proc/PID/status in kB (e.g. "VmHWM:"); -1 when the
// process or the field is not there.
long long proc_status_kb(int pid, const std::string& field);

}  // namespace locus::tools
