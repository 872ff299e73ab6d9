// The survey file reader (datasets/survey_format.*): every input is read as JSON lines and as CSV.
//
// Checks: parse() never throws; nothing half-parsed reaches the result (every RP has a name
// and at least one scan, every scan at least one reading, no AP twice in a scan, every
// reading a valid type, a normalised 1..64-character bssid and an rss in [-120, 0]); the
// scan and reading totals match the RPs; every error names a line of the input.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>
#include <utility>

#include "datasets/survey_format.hpp"

using namespace locus;
namespace survey = locus::datasets::survey;

namespace {

[[noreturn]] void fail(const char* what, survey::Format format, std::string_view text) {
    std::fprintf(stderr, "fuzz_survey_format (%s): %s\ninput (%zu bytes): %.*s\n",
                 format == survey::Format::Csv ? "csv" : "json lines", what, text.size(), static_cast<int>(text.size()),
                 text.data());
    std::abort();
}

void check(std::string_view text, survey::Format format) {
    const survey::SurveyFile file = survey::parse(text, format);
    const std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    std::size_t scans = 0, readings = 0;
    std::set<std::string> names;
    for (const auto& rp : file.rps) {
        if (rp.name.empty()) fail("an RP without a name", format, text);
        if (!names.insert(rp.name).second) fail("an RP twice", format, text);
        if (rp.scans.empty()) fail("an RP without scans", format, text);
        if (rp.at && !(std::isfinite(rp.at->x) && std::isfinite(rp.at->y) && std::fabs(rp.at->x) <= 1e7 &&
                       std::fabs(rp.at->y) <= 1e7))
            fail("an RP outside [-1e7, 1e7]", format, text);
        for (const auto& scan : rp.scans) {
            if (scan.empty()) fail("an empty scan", format, text);
            std::set<std::pair<std::string, std::string>> aps;
            for (const auto& r : scan) {
                if (r.type != "wifi" && r.type != "ble") fail("a type other than wifi/ble", format, text);
                if (r.bssid.empty() || r.bssid.str().size() > 64) fail("a bssid outside 1..64 characters", format, text);
                if (Bssid(r.bssid.str()) != r.bssid) fail("a bssid not normalised", format, text);
                if (!valid_rss(r.rss)) fail("an rss outside [-120, 0]", format, text);
                if (!aps.emplace(r.type, r.bssid).second) fail("an AP twice in one scan", format, text);
            }
            ++scans;
            readings += scan.size();
        }
    }
    if (scans != file.scans || readings != file.readings) fail("totals that do not match the RPs", format, text);
    for (const auto& e : file.errors) {
        // Line 0 only for an input without a line ("no header line" of an empty CSV).
        if (e.line < (text.empty() ? 0 : 1) || e.line > lines) fail("an error on a line the input does not have", format, text);
        if (e.message.empty()) fail("an error without a message", format, text);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    check(text, survey::Format::JsonLines);
    check(text, survey::Format::Csv);
    return 0;
}
