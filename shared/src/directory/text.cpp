#include "locus/directory/text.hpp"

#include <utf8proc.h>

#include <algorithm>
#include <cstdlib>
#include <memory>

namespace locus::directory {

namespace {

// utf8proc refuses a whole string for one bad byte; a name is better searched without it.
std::string valid_utf8(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    const auto* p = reinterpret_cast<const utf8proc_uint8_t*>(text.data());
    auto left = static_cast<utf8proc_ssize_t>(text.size());
    while (left > 0) {
        utf8proc_int32_t cp = 0;
        const utf8proc_ssize_t n = utf8proc_iterate(p, left, &cp);
        if (n <= 0) {
            ++p;
            --left;
            continue;
        }
        out.append(reinterpret_cast<const char*>(p), static_cast<std::size_t>(n));
        p += n;
        left -= n;
    }
    return out;
}

bool is_word_char(utf8proc_int32_t cp) {
    switch (utf8proc_category(cp)) {
        case UTF8PROC_CATEGORY_LU:
        case UTF8PROC_CATEGORY_LL:
        case UTF8PROC_CATEGORY_LT:
        case UTF8PROC_CATEGORY_LM:
        case UTF8PROC_CATEGORY_LO:
        case UTF8PROC_CATEGORY_MN:  // marks that survive folding belong to their letter
        case UTF8PROC_CATEGORY_MC:
        case UTF8PROC_CATEGORY_ME:
        case UTF8PROC_CATEGORY_ND:
        case UTF8PROC_CATEGORY_NL:
        case UTF8PROC_CATEGORY_NO:
            return true;
        default:
            return false;
    }
}

bool is_digit(char32_t c) { return utf8proc_category(static_cast<utf8proc_int32_t>(c)) == UTF8PROC_CATEGORY_ND; }

// What is left after the edit: equal, or (typing a prefix) the start of the word's rest.
bool rest_matches(std::u32string_view query, std::u32string_view word, bool prefix) {
    return prefix ? word.starts_with(query) : word == query;
}

}  // namespace

bool is_utf8(std::string_view text) {
    const auto* p = reinterpret_cast<const utf8proc_uint8_t*>(text.data());
    auto left = static_cast<utf8proc_ssize_t>(text.size());
    while (left > 0) {
        utf8proc_int32_t cp = 0;
        const utf8proc_ssize_t n = utf8proc_iterate(p, left, &cp);
        if (n <= 0) return false;
        p += n;
        left -= n;
    }
    return true;
}

std::size_t code_points(std::string_view text) {
    std::size_t n = 0;  // bytes that do not continue a code point
    for (const char c : text) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    return n;
}

std::string fold(std::string_view text) {
    const std::string clean = valid_utf8(text);
    if (clean.empty()) return {};
    utf8proc_uint8_t* mapped = nullptr;
    const auto options = static_cast<utf8proc_option_t>(UTF8PROC_STABLE | UTF8PROC_COMPAT | UTF8PROC_COMPOSE |
                                                        UTF8PROC_CASEFOLD | UTF8PROC_STRIPMARK | UTF8PROC_IGNORE);
    const utf8proc_ssize_t n = utf8proc_map(reinterpret_cast<const utf8proc_uint8_t*>(clean.data()),
                                            static_cast<utf8proc_ssize_t>(clean.size()), &mapped, options);
    const std::unique_ptr<utf8proc_uint8_t, decltype(&std::free)> owned(mapped, &std::free);
    if (n < 0) return {};  // only on allocation failure: the input is valid UTF-8 by now
    return {reinterpret_cast<const char*>(mapped), static_cast<std::size_t>(n)};
}

std::vector<std::u32string> words(std::string_view text) {
    const std::string folded = fold(text);
    std::u32string cps;
    cps.reserve(folded.size());
    const auto* p = reinterpret_cast<const utf8proc_uint8_t*>(folded.data());
    auto left = static_cast<utf8proc_ssize_t>(folded.size());
    while (left > 0) {
        utf8proc_int32_t cp = 0;
        const utf8proc_ssize_t n = utf8proc_iterate(p, left, &cp);
        if (n <= 0) break;  // fold wrote valid UTF-8
        cps.push_back(static_cast<char32_t>(cp));
        p += n;
        left -= n;
    }
    std::vector<std::u32string> out;
    std::u32string word;
    for (std::size_t i = 0; i < cps.size(); ++i) {
        const char32_t c = cps[i];
        const bool joins_number = (c == U'.' || c == U',') && !word.empty() && is_digit(word.back()) &&
                                  i + 1 < cps.size() && is_digit(cps[i + 1]);
        if (joins_number || is_word_char(static_cast<utf8proc_int32_t>(c))) {
            word.push_back(c);
        } else if (!word.empty()) {
            out.push_back(std::move(word));
            word.clear();
        }
    }
    if (!word.empty()) out.push_back(std::move(word));
    return out;
}

bool within_one_edit(std::u32string_view q, std::u32string_view w, bool prefix) {
    std::size_t i = 0;
    const std::size_t common = std::min(q.size(), w.size());
    while (i < common && q[i] == w[i]) ++i;
    if (i == common) {
        // One is the start of the other: the query's one extra letter goes, or the word's
        // missing letter comes (nothing to add when a prefix is enough).
        if (q.size() > w.size()) return q.size() - w.size() <= 1;
        return prefix || w.size() - q.size() <= 1;
    }
    const auto qs = q.substr(i), ws = w.substr(i);
    if (rest_matches(qs.substr(1), ws.substr(1), prefix)) return true;  // substituted
    if (rest_matches(qs.substr(1), ws, prefix)) return true;            // a letter too many
    if (rest_matches(qs, ws.substr(1), prefix)) return true;            // a letter left out
    return qs.size() >= 2 && ws.size() >= 2 && qs[0] == ws[1] && qs[1] == ws[0] &&
           rest_matches(qs.substr(2), ws.substr(2), prefix);  // two neighbours swapped
}

}  // namespace locus::directory
