#pragma once
// Text as the directory compares it: folded (case, accents and compatibility forms gone, so
// "Müller", "MULLER" and "muller" are one word), cut into words, and compared with a one-edit
// tolerance for typing mistakes.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace locus::directory {

// Unicode case fold, compatibility decomposition and accent stripping (utf8proc), recomposed:
// "Café" → "cafe", "Straße" → "strasse", "ﬁ" → "fi". Bytes that are not UTF-8 are dropped.
std::string fold(std::string_view text);

// Whether `text` is well-formed UTF-8 (what a query must be to be echoed back as typed).
bool is_utf8(std::string_view text);

// Characters (code points) of UTF-8 text: how names and queries are measured.
std::size_t code_points(std::string_view text);

// The words of `text`, folded, as code points: runs of letters and digits; a '.' or ',' between
// two digits stays inside its word, so a room number "3.21" is one word. Everything else
// (spaces, punctuation, symbols) separates.
std::vector<std::u32string> words(std::string_view text);

// True when at most one substitution, insertion, deletion or swap of two neighbours turns
// `query` into `word` or, when `prefix`, into the start of `word`. Linear time.
bool within_one_edit(std::u32string_view query, std::u32string_view word, bool prefix);

}  // namespace locus::directory
