// The walking survey's small CSV readers (datasets/walk_files.*): the landmarks file and the
// IPIN 2023 beacons file, both run on every input.
//
// Checks: they throw nothing but std::runtime_error, whose message names the file and, when
// it names a line, one the input has; landmarks are finite, in time order, on whole floors
// within ±1000; beacons are on the globe with distinct numbers 1..255 and whole floors.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>

#include "datasets/walk_files.hpp"

namespace {

[[noreturn]] void fail(const char* what, std::string_view text) {
    std::fprintf(stderr, "fuzz_walk_files: %s\ninput (%zu bytes): %.*s\n", what, text.size(), static_cast<int>(text.size()),
                 text.data());
    std::abort();
}

void check_error(const std::runtime_error& e, std::string_view text) {
    const std::string m = e.what();
    if (m.rfind("fuzz.csv:", 0) != 0) fail("an error not naming the file", text);
    long lines = 0;
    for (char c : text) lines += c == '\n';
    if (!text.empty() && text.back() != '\n') ++lines;
    const char* p = m.c_str() + 9;
    if (*p >= '0' && *p <= '9') {
        const long line = std::strtol(p, nullptr, 10);
        if (line < 1 || line > lines) fail("an error on a line the input does not have", text);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const auto landmarks = locus::datasets::parse_landmarks_csv(text, "fuzz.csv");
        if (landmarks.empty()) fail("no landmark and no error", text);
        for (std::size_t i = 0; i < landmarks.size(); ++i) {
            const auto& l = landmarks[i];
            if (!std::isfinite(l.t) || !std::isfinite(l.at.x) || !std::isfinite(l.at.y)) fail("a non-finite landmark", text);
            if (std::abs(l.floor) > 1000) fail("a floor beyond ±1000", text);
            if (i > 0 && l.t < landmarks[i - 1].t) fail("landmarks out of time order", text);
        }
        // What the reader accepts the core takes (it refuses only out-of-order landmarks).
        locus::survey::place_scans(landmarks, {landmarks.front().t, landmarks.back().t});
    } catch (const std::runtime_error& e) {
        check_error(e, text);
    } catch (const std::invalid_argument&) {
        fail("the core refused what the reader accepted", text);
    }
    try {
        std::set<int> numbers;
        for (const auto& b : locus::datasets::parse_ipin_beacons(text, "fuzz.csv")) {
            if (!(std::abs(b.lat) <= 90 && std::abs(b.lon) <= 180)) fail("a beacon off the globe", text);
            if (b.number < 1 || b.number > 255 || !numbers.insert(b.number).second) fail("a bad or repeated beacon number", text);
            if (std::abs(b.floor) > 1000) fail("a floor beyond ±1000", text);
        }
    } catch (const std::runtime_error& e) {
        check_error(e, text);
    }
    return 0;
}
