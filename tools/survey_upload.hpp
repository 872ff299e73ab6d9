#pragma once
// Uploads the scans of many reference points to the server in parallel, one request per RP
// (per chunk, for very large RPs), creating missing RPs by name. An RP is created only with
// scans to send, and an RP this run created is deleted again when its first upload fails, so a
// failing upload never leaves an RP created but empty. Every request carries the
// job's upload_id, which the server records per RP: re-running the same jobs, after a clean
// run or an interrupted one, merges nothing twice.
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "locus/api/client.hpp"
#include "locus/geometry.hpp"
#include "locus/radio_map.hpp"

namespace locus::tools {

struct RpJob {
    std::int64_t radiomap_id = 0;
    std::string name;
    std::optional<Point> at;  // needed only when the RP does not exist yet
    std::vector<Scan> scans;
    std::string upload_id;
    std::string source;  // file the scans came from, for messages
};

struct UploadOptions {
    int concurrency = 4;
    std::optional<std::size_t> stop_after;  // test hook: upload at most this many RPs, then stop
    bool progress = false;                  // draw a progress bar on stderr
};

struct UploadSummary {
    std::size_t rps = 0;      // jobs given
    std::size_t created = 0;  // RPs that did not exist
    std::size_t applied = 0;  // RPs whose upload merged
    std::size_t already = 0;  // RPs that had this upload id already: nothing changed
    std::size_t failed = 0;
    std::size_t scans = 0;     // scans sent (applied or not)
    std::size_t readings = 0;  // readings sent
    std::int64_t retries = 0;
    double seconds = 0.0;
    bool interrupted = false;  // stopped by stop_after before every job ran
    std::vector<std::string> failures;
    nlohmann::json to_json() const;
};

// Readings per request above which an RP's scans go in several requests ("<id>#<k>").
inline constexpr std::size_t kMaxReadingsPerRequest = 50'000;

UploadSummary upload_rps(const api::ClientOptions& client, const std::vector<RpJob>& jobs, const UploadOptions& options);

}  // namespace locus::tools
