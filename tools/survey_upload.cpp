#include "survey_upload.hpp"

#include "survey_connect.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "datasets/survey_format.hpp"

namespace locus::tools {

using nlohmann::json;

json UploadSummary::to_json() const {
    return {{"rps", rps},           {"created", created},   {"applied", applied},
            {"already_uploaded", already}, {"failed", failed}, {"scans", scans},
            {"readings", readings}, {"retries", retries},   {"seconds", seconds},
            {"readings_per_s", seconds > 0 ? static_cast<double>(readings) / seconds : 0.0},
            {"interrupted", interrupted}, {"failures", failures}};
}

namespace {

// Splits an RP's scans into request-sized chunks; small RPs are one chunk.
std::vector<std::vector<Scan>> chunks(const std::vector<Scan>& scans) {
    std::vector<std::vector<Scan>> out(1);
    std::size_t in_chunk = 0;
    for (const auto& s : scans) {
        if (in_chunk > 0 && in_chunk + s.size() > kMaxReadingsPerRequest) {
            out.emplace_back();
            in_chunk = 0;
        }
        out.back().push_back(s);
        in_chunk += s.size();
    }
    return out;
}

// A name for messages: bytes that are not UTF-8 shown as \xNN (the summary is JSON).
std::string shown(const std::string& s) {
    if (datasets::survey::valid_utf8(s)) return s;
    std::string out;
    for (unsigned char c : s) {
        if (c < 0x80) {
            out += static_cast<char>(c);
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02X", c);
            out += buf;
        }
    }
    return out;
}

// Everything a request will carry as a JSON string must be UTF-8; checked before the RP is
// created, so that a job the JSON writer would refuse leaves nothing behind.
void check_sendable(const RpJob& job) {
    if (!datasets::survey::valid_utf8(job.name)) throw std::runtime_error("the RP name is not UTF-8");
    for (const auto& scan : job.scans)
        for (const auto& r : scan)
            if (!datasets::survey::valid_utf8(r.bssid.str()) || !datasets::survey::valid_utf8(r.type))
                throw std::runtime_error("a reading of AP '" + shown(r.bssid) + "' is not UTF-8");
}

void draw_progress(std::size_t done, std::size_t total, std::size_t readings, double seconds) {
    constexpr int width = 30;
    const int filled = total ? static_cast<int>(width * done / total) : width;
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r[%s] %zu/%zu RPs, %zu readings, %.0f readings/s ", bar.c_str(), done, total, readings,
                 seconds > 0 ? static_cast<double>(readings) / seconds : 0.0);
    std::fflush(stderr);
}

}  // namespace

UploadSummary upload_rps(const api::ClientOptions& client_options, const std::vector<RpJob>& jobs,
                         const UploadOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    UploadSummary summary;
    summary.rps = jobs.size();

    // One list per radio map up front: find-or-create without a list per RP.
    std::map<std::pair<std::int64_t, std::string>, std::int64_t> existing;
    {
        api::Client client(client_options);
        std::set<std::int64_t> radiomaps;
        for (const auto& j : jobs) radiomaps.insert(j.radiomap_id);
        for (auto rm : radiomaps)
            for (const auto& rp : client.rps(rm)) existing[{rm, rp.name}] = rp.id;
        summary.retries += client.retries();
    }

    std::atomic<std::size_t> next{0}, done{0}, created{0}, applied{0}, already{0}, failed{0}, scans{0}, readings{0};
    std::atomic<std::int64_t> retries{0};
    std::atomic<bool> interrupted{false};
    std::mutex failures_mu;
    const std::size_t limit = options.stop_after ? std::min(*options.stop_after, jobs.size()) : jobs.size();

    auto worker = [&] {
        api::Client client(client_options);
        for (;;) {
            const std::size_t i = next++;
            if (i >= jobs.size()) break;
            if (i >= limit) {
                interrupted = true;
                break;
            }
            const RpJob& job = jobs[i];
            std::int64_t rp_id = 0;
            bool created_here = false, any_sent = false;
            try {
                check_sendable(job);
                if (job.scans.empty()) {
                    // Nothing to send: an RP is only ever created together with its scans.
                    ++already;
                    ++done;
                    continue;
                }
                if (auto it = existing.find({job.radiomap_id, job.name}); it != existing.end()) {
                    rp_id = it->second;
                } else {
                    if (!job.at)
                        throw std::runtime_error("RP '" + job.name + "' does not exist and " + job.source +
                                                 " gives no coordinates for it");
                    try {
                        rp_id = client.create_rp(job.radiomap_id, job.name, job.at->x, job.at->y).id;
                        created_here = true;
                        ++created;
                    } catch (const api::ApiError& e) {
                        if (e.status() != 409) throw;
                        rp_id = client.ensure_rp(job.radiomap_id, job.name, job.at->x, job.at->y).id;
                    }
                }
                const auto parts = chunks(job.scans);
                bool any_applied = false;
                for (std::size_t k = 0; k < parts.size(); ++k) {
                    api::ScanUpload up;
                    up.upload_id = parts.size() == 1 ? job.upload_id : job.upload_id + "#" + std::to_string(k);
                    up.scans = parts[k];
                    any_applied = client.upload(rp_id, up).applied || any_applied;
                    any_sent = true;
                    std::size_t n = 0;
                    for (const auto& s : parts[k]) n += s.size();
                    readings += n;
                    scans += parts[k].size();
                }
                ++(any_applied ? applied : already);
            } catch (const std::exception& e) {
                std::string message = job.source + ": RP '" + shown(job.name) + "': " + plain_numbers(e.what());
                // The RP this run created got none of its scans: take it away again, so that no
                // RP is left created but empty (a re-run creates it with its scans).
                if (created_here && !any_sent) {
                    try {
                        client.del("/v1/rps/" + std::to_string(rp_id));
                        --created;
                    } catch (const std::exception& d) {
                        message += "; RP " + std::to_string(rp_id) + " is left without scans (deleting it failed: " +
                                   d.what() + ")";
                    }
                }
                ++failed;
                std::lock_guard lock(failures_mu);
                summary.failures.push_back(message);
            }
            ++done;
        }
        retries += client.retries();
    };

    const int n_threads = std::max(1, std::min<int>(options.concurrency, static_cast<int>(std::max<std::size_t>(limit, 1))));
    std::vector<std::thread> threads;
    for (int t = 0; t < n_threads; ++t) threads.emplace_back(worker);
    if (options.progress) {
        while (done.load() < limit) {
            draw_progress(done, jobs.size(), readings,
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    }
    for (auto& t : threads) t.join();
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (options.progress) {
        draw_progress(done, jobs.size(), readings, summary.seconds);
        std::fprintf(stderr, "\n");
    }
    summary.created = created;
    summary.applied = applied;
    summary.already = already;
    summary.failed = failed;
    summary.scans = scans;
    summary.readings = readings;
    summary.retries += retries;
    summary.interrupted = interrupted || limit < jobs.size();
    return summary;
}

}  // namespace locus::tools
