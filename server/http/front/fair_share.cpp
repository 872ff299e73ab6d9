#include "http/front/fair_share.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "http/api_error.hpp"
#include "http/app.hpp"
#include "tracks/token.hpp"

namespace locus::http {

namespace {

// "/v1/<collection>/<digits>/<tail>" exactly.
bool is_item_path(std::string_view path, std::string_view collection, std::string_view tail) {
    if (!path.starts_with("/v1/")) return false;
    path.remove_prefix(4);
    if (!path.starts_with(collection) || path.size() <= collection.size() || path[collection.size()] != '/') return false;
    path.remove_prefix(collection.size() + 1);
    std::size_t digits = 0;
    while (digits < path.size() && path[digits] >= '0' && path[digits] <= '9') ++digits;
    if (digits == 0 || digits >= path.size() || path[digits] != '/') return false;
    return path.substr(digits + 1) == tail;
}

enum class Limited { none, track_open, expensive };

Limited limited(const httplib::Request& req) {
    const bool get = req.method == "GET" || req.method == "HEAD";
    if (req.method == "POST") {
        if (req.path == "/v1/tracks") return Limited::track_open;
        if (is_item_path(req.path, "maps", "route") || is_item_path(req.path, "maps", "localize")) return Limited::expensive;
    }
    if (get && (is_item_path(req.path, "maps", "search") || is_item_path(req.path, "radiomaps", "quality"))) return Limited::expensive;
    return Limited::none;
}

std::string number_text(double v) {
    if (v == std::floor(v) && std::fabs(v) < 1e15) return std::to_string(static_cast<long long>(v));
    std::string s = std::to_string(v);
    while (!s.empty() && s.back() == '0') s.pop_back();
    return s;
}

}  // namespace

FairShare::FairShare(FairShareOptions options, std::string api_key)
    : options_(std::move(options)),
      api_key_(std::move(api_key)),
      opens_(options_.track_open_rate, options_.track_open_burst, options_.table_capacity),
      routes_(options_.route_rate, options_.route_burst, options_.table_capacity),
      track_writes_(options_.track_write_rate, options_.track_write_burst, options_.table_capacity) {}

double FairShare::now() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - epoch_).count(); }

bool FairShare::exempt(const httplib::Request& req) const {
    if (api_key_.empty()) return false;
    const std::string auth = req.get_header_value("Authorization");
    return auth.starts_with("Bearer ") && tracks::same_hash(std::string_view(auth).substr(7), api_key_);
}

std::vector<std::string> FairShare::forwarded(const httplib::Request& req) const {
    std::vector<std::string> out;
    if (!options_.trusted_proxies.empty()) {
        const auto n = req.get_header_value_count("X-Forwarded-For");
        for (std::size_t i = 0; i < n; ++i) out.push_back(req.get_header_value("X-Forwarded-For", i));
    }
    return out;
}

std::optional<std::string> FairShare::client(const httplib::Request& req) const {
    if (exempt(req)) return std::nullopt;
    return client_of(req.remote_addr, forwarded(req), options_.trusted_proxies);
}

bool FairShare::local(const httplib::Request& req) const {
    const auto peer = parse_address(req.remote_addr);
    if (!peer) return false;
    const bool trusted_peer = std::any_of(options_.trusted_proxies.begin(), options_.trusted_proxies.end(),
                                          [&](const AddressRange& r) { return r.contains(*peer); });
    if (!trusted_peer)
        for (const char* header : {"X-Forwarded-For", "Forwarded", "X-Real-IP"})
            if (req.has_header(header)) return false;
    const auto client = client_address(req.remote_addr, forwarded(req), options_.trusted_proxies);
    return client && is_loopback(*client);
}

ClientBuckets::Verdict FairShare::take(ClientBuckets& bucket, const std::string& who, double cost) {
    std::lock_guard lock(mu_);
    return bucket.take(who, now(), cost);
}

bool FairShare::refuse(const httplib::Request& req, httplib::Response& res) {
    const Limited what = limited(req);
    if (what == Limited::none) return false;
    const auto who = client(req);
    if (!who) return false;
    const ClientBuckets::Verdict v = take(what == Limited::track_open ? opens_ : routes_, *who, 1);
    if (v.allowed) return false;
    // Whole seconds, rounded up: a retry at Retry-After finds a token.
    const long long retry = retry_seconds(v.wait_s);
    res.set_header("Retry-After", std::to_string(retry));
    const std::string message =
        what == Limited::track_open
            ? "this client opened tracks faster than --client-track-opens (" + number_text(options_.track_open_rate) +
                  " a second, bursts of --client-track-open-burst " + number_text(options_.track_open_burst) + ")"
            : "this client sent route, search, map localize and quality requests faster than --client-rate (" +
                  number_text(options_.route_rate) + " a second, bursts of --client-burst " + number_text(options_.route_burst) + ")";
    write_error(res, 429, "rate_limited", message + "; retry after " + std::to_string(retry) + " s");
    return true;
}

void FairShare::charge_track_bytes(const httplib::Request& req) {
    const auto who = client(req);
    if (!who) return;
    const ClientBuckets::Verdict bytes = take(track_writes_, *who, static_cast<double>(req.body.size()));
    if (!bytes.allowed)
        throw ApiError(429, "rate_limited",
                       "this client posted fixes and steps faster than --client-track-bytes (" + number_text(options_.track_write_rate) +
                           " bytes a second, bursts of --client-track-bytes-burst " + number_text(options_.track_write_burst) +
                           "): what it posts is stored; retry after " + std::to_string(retry_seconds(bytes.wait_s)) + " s",
                       bytes.wait_s);
}

void FairShare::charge_localizations(const httplib::Request& req, std::size_t localizations) {
    if (localizations == 0) return;
    const auto who = client(req);
    if (!who) return;
    const ClientBuckets::Verdict scans = take(routes_, *who, static_cast<double>(localizations));
    if (!scans.allowed)
        throw ApiError(429, "rate_limited",
                       "this client's scans to localize (" + std::to_string(localizations) + " in this request) come faster than --client-rate (" +
                           number_text(options_.route_rate) + " localizations a second with map localize, route and search, bursts of --client-burst " +
                           number_text(options_.route_burst) + "); retry after " + std::to_string(retry_seconds(scans.wait_s)) + " s",
                       scans.wait_s);
}

}  // namespace locus::http
