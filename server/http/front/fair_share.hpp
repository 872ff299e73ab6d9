#pragma once
// Per-client fair shares (docs/deploy.md "Per-client limits"): what one client (one address,
// client_address.hpp) may take of what every client shares, so one of them cannot fill a
// server-wide cap and leave everyone else 503.
//
// Rates are kept here, checked before routing (App's pre-routing handler): anonymous track
// opens (POST /v1/tracks, --client-track-opens/--client-track-open-burst) and the expensive
// anonymous reads (POST /v1/maps/{id}/route, GET /v1/maps/{id}/search, POST /v1/maps/{id}/localize,
// GET /v1/radiomaps/{id}/quality; one bucket for the four, --client-rate/--client-burst).
// What a track's writer stores is charged by the routes once the body is read, before it is
// parsed (charge_track_bytes), and the scans a thin client has the server localize once it is
// parsed (charge_localizations). What a client holds (live
// tracks, event streams) is counted where it is held, by the tracks service (tracks::Options;
// live tracks in the database, as a keyed hash); the routes ask client() for the key it
// counts under.
//
// A request carrying the server's API key is the operator's and is exempt from all of these.
//
// Costs: client() parses the peer and X-Forwarded-For (client_address.hpp); refuse() adds a
// regex-free path check and, for a limited route, one ClientBuckets::take under a mutex;
// charge_track_bytes() and charge_localizations() one each.
// Memory: at most `table_capacity` buckets per table (three tables), whatever the clients.
#include <httplib.h>

#include <chrono>
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "http/front/client_address.hpp"
#include "http/front/client_buckets.hpp"

namespace locus::http {

struct FairShareOptions {
    // A phone opens a track per walk; a burst covers a building's worth of tests or restarts.
    double track_open_rate = 0.5;  // per second
    double track_open_burst = 30;
    // A phone localizes about once a second and routes or searches now and then.
    double route_rate = 10;  // per second
    double route_burst = 60;
    // What a track's writer posts (fixes, a thin client's steps and scans) is stored for the
    // retention period: its bytes are metered so one client cannot fill the disk. An hour of a
    // phone's fixes uploaded at once is some 300 KB; a live phone posts about 1 KB a second.
    double track_write_rate = 16 * 1024;  // bytes per second
    double track_write_burst = 1024 * 1024;
    std::vector<AddressRange> trusted_proxies;  // --trusted-proxy; empty: X-Forwarded-For is ignored
    std::size_t table_capacity = 65'536;        // buckets held per table (client_buckets.hpp)
};

class FairShare {
public:
    FairShare(FairShareOptions options, std::string api_key);

    // The key the client of `req` is counted under, or nullopt when it carries the server's
    // API key ('Authorization: Bearer KEY'; never with no key configured): exempt.
    std::optional<std::string> client(const httplib::Request& req) const;
    // Whether the client of `req` is on this machine: its address, as client() resolves it
    // through the trusted proxies, is a loopback address, and no proxy the server does not
    // trust forwarded it (a proxy on this machine that is not named makes every client look
    // local, so a forwarding header from a peer that is not a trusted proxy says "not local").
    bool local(const httplib::Request& req) const;
    // Before routing: true, with `res` holding the 429 (Retry-After, rate_limited), when the
    // request is on a rate-limited route and its client has no token left.
    bool refuse(const httplib::Request& req, httplib::Response& res);

    // Once a track write's body is read (POST /v1/tracks/{id}/fixes and /steps), before it is
    // parsed: its bytes against --client-track-bytes, so a client past its budget is refused
    // without costing the parse (a body refused later, as invalid or for its scans, has spent
    // its bytes: it was received). Throws ApiError 429 rate_limited with retry_after_s.
    void charge_track_bytes(const httplib::Request& req);
    // Once a /steps body is parsed: the scans it asks the server to localize against the
    // bucket map localize takes from (--client-rate), one token each, a batch of more than the
    // burst admitted on a full bucket and paid for after. Throws ApiError 429 rate_limited.
    void charge_localizations(const httplib::Request& req, std::size_t localizations);

    const FairShareOptions& options() const { return options_; }

private:
    bool exempt(const httplib::Request& req) const;
    std::vector<std::string> forwarded(const httplib::Request& req) const;  // X-Forwarded-For values, when a proxy is trusted
    double now() const;  // seconds since the tables began, the buckets' clock
    // `cost` of `who`'s tokens from one of the tables, now, under the tables' mutex.
    ClientBuckets::Verdict take(ClientBuckets& bucket, const std::string& who, double cost);

    FairShareOptions options_;
    std::string api_key_;
    std::mutex mu_;  // every table
    ClientBuckets opens_, routes_, track_writes_;
    std::chrono::steady_clock::time_point epoch_ = std::chrono::steady_clock::now();
};

}  // namespace locus::http
