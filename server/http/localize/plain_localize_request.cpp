#include "http/localize/plain_localize_request.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>
#include <vector>

#include "http/validation.hpp"

namespace locus::http {

namespace {

// A cursor over the body. Every reader returns false when the text is not what the fast
// path takes, and the caller gives up (the full parser then reads the body).
class Reader {
public:
    explicit Reader(std::string_view text) : s_(text) {}

    void skip_space() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
    }
    bool at_end() {
        skip_space();
        return i_ == s_.size();
    }
    // Consumes `c` (after white space) if it is next.
    bool take(char c) {
        skip_space();
        if (i_ < s_.size() && s_[i_] == c) {
            ++i_;
            return true;
        }
        return false;
    }
    // A string of printable ASCII without escapes.
    bool string(std::string_view& out) {
        if (!take('"')) return false;
        const std::size_t start = i_;
        for (; i_ < s_.size(); ++i_) {
            const auto c = static_cast<unsigned char>(s_[i_]);
            if (c == '"') {
                out = s_.substr(start, i_ - start);
                ++i_;
                return true;
            }
            if (c == '\\' || c < 0x20 || c >= 0x80) return false;
        }
        return false;
    }
    // A JSON number (RFC 8259 grammar). An integer of up to 15 characters fits the int64 that
    // nlohmann reads it as; a fraction or exponent goes through from_chars, which rounds
    // correctly like nlohmann's strtod. The 24-character cap only bounds the work.
    bool number(double& out) {
        skip_space();
        const std::size_t start = i_;
        auto digits = [&] {
            const std::size_t from = i_;
            while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') ++i_;
            return i_ - from;
        };
        if (i_ < s_.size() && s_[i_] == '-') ++i_;
        if (i_ < s_.size() && s_[i_] == '0') ++i_;
        else if (digits() == 0) return false;
        bool integral = true;
        if (i_ < s_.size() && s_[i_] == '.') {
            ++i_;
            integral = false;
            if (digits() == 0) return false;
        }
        if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
            ++i_;
            integral = false;
            if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) ++i_;
            if (digits() == 0) return false;
        }
        if (i_ - start > 24 || (integral && i_ - start > 15)) return false;
        const char* first = s_.data() + start;
        const char* last = s_.data() + i_;
        if (integral) {  // as nlohmann: an int64, then a double (so "-0" is +0.0)
            long long n = 0;
            const auto r = std::from_chars(first, last, n);
            out = static_cast<double>(n);
            return r.ec == std::errc() && r.ptr == last;
        }
        const auto r = std::from_chars(first, last, out);
        return r.ec == std::errc() && r.ptr == last;
    }

private:
    std::string_view s_;
    std::size_t i_ = 0;
};

// {"bssid": .., "rss": .., "type": ..}, each key at most once, bssid and rss required. The
// reading's text stays in the body: the query copies it once, normalised.
bool reading(Reader& in, match::ReadingView& out) {
    if (!in.take('{')) return false;
    bool has_bssid = false, has_rss = false, has_type = false;
    do {
        std::string_view key;
        if (!in.string(key) || !in.take(':')) return false;
        if (key == "bssid" && !has_bssid) {
            if (!in.string(out.bssid)) return false;
            has_bssid = true;
        } else if (key == "type" && !has_type) {
            if (!in.string(out.type)) return false;
            has_type = true;
        } else if (key == "rss" && !has_rss) {
            if (!in.number(out.rss)) return false;
            has_rss = true;
        } else {
            return false;  // an unknown or repeated key
        }
    } while (in.take(','));
    if (!in.take('}') || !has_bssid || !has_rss) return false;
    if (bssid_problem(out.bssid) || (has_type && type_problem(out.type))) return false;
    return std::isfinite(out.rss) && valid_rss(out.rss);
}

// [[reading, ..], ..]: at least one scan, none empty. The readings of all scans go into one
// list in order, which is what Query::from_scans averages over as well.
bool scans(Reader& in, std::vector<match::ReadingView>& out) {
    if (!in.take('[')) return false;
    std::size_t n = 0;
    do {
        // Past a count limit the full parser words the refusal.
        if (++n > kMaxScans || !in.take('[')) return false;
        const std::size_t first = out.size();
        do {
            if (out.size() - first >= kMaxReadings || !reading(in, out.emplace_back())) return false;
        } while (in.take(','));
        if (!in.take(']')) return false;
    } while (in.take(','));
    return in.take(']');
}

// Each worker thread keeps its reading list between requests, so a request does not grow one
// reading by reading; after a huge body the list gives its memory back at once.
class ScratchReadings {
public:
    ScratchReadings() { list().clear(); }
    ~ScratchReadings() {
        list().clear();
        if (list().capacity() > 4096) std::vector<match::ReadingView>().swap(list());
    }
    ScratchReadings(const ScratchReadings&) = delete;
    ScratchReadings& operator=(const ScratchReadings&) = delete;
    static std::vector<match::ReadingView>& list() {
        thread_local std::vector<match::ReadingView> readings;
        return readings;
    }
};

}  // namespace

std::optional<LocalizeRequest> parse_plain_localize_request(std::string_view body) {
    Reader in(body);
    if (!in.take('{')) return std::nullopt;
    const ScratchReadings scratch;
    std::vector<match::ReadingView>& readings = ScratchReadings::list();
    std::optional<std::string_view> algorithm;
    bool has_scans = false;
    do {
        std::string_view key;
        if (!in.string(key) || !in.take(':')) return std::nullopt;
        if (key == "scans" && !has_scans) {
            has_scans = true;
            if (!scans(in, readings)) return std::nullopt;
        } else if (key == "algorithm" && !algorithm) {
            std::string_view name;
            if (!in.string(name)) return std::nullopt;
            algorithm = name;
        } else {
            return std::nullopt;
        }
    } while (in.take(','));
    if (!in.take('}') || !in.at_end() || !has_scans) return std::nullopt;
    LocalizeRequest r;
    if (algorithm) {
        const auto a = match::parse_algorithm(*algorithm);
        if (!a) return std::nullopt;
        r.algorithm = *a;
        r.algorithm_given = true;
    }
    r.query = match::Query::from_means(readings);  // the same average as from_scans over the scans
    if (r.query.aps.empty()) return std::nullopt;
    return r;
}

}  // namespace locus::http
