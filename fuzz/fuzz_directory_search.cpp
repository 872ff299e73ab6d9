// The directory's folding, words and ranked search (shared/src/directory) on arbitrary bytes:
// the first line is the query, each further line a document "name|category|tag|tag…".
//
// Checks: nothing throws; at most `limit` hits, each a real document, best first, a matched
// tag that exists; a document whose name is the query is found; within_one_edit is symmetric
// and a whole-word match is also a prefix match.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "locus/directory/index.hpp"
#include "locus/directory/text.hpp"

using namespace locus::directory;

namespace {

[[noreturn]] void fail(const char* what, std::string_view text) {
    std::fprintf(stderr, "fuzz_directory_search: %s\ninput (%zu bytes): %.*s\n", what, text.size(),
                 static_cast<int>(text.size()), text.data());
    std::abort();
}

std::vector<std::string_view> split(std::string_view s, char sep) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= s.size(); ++i)
        if (i == s.size() || s[i] == sep) {
            out.push_back(s.substr(start, i - start));
            start = i + 1;
        }
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const auto lines = split(text, '\n');
    const std::string_view query = lines[0];
    std::vector<Document> docs;
    for (std::size_t i = 1; i < lines.size() && docs.size() < 200; ++i) {
        const auto fields = split(lines[i], '|');
        Document d{std::string(fields[0]), fields.size() > 1 ? std::string(fields[1]) : "", {}};
        for (std::size_t f = 2; f < fields.size(); ++f) d.tags.emplace_back(fields[f]);
        docs.push_back(std::move(d));
    }
    const std::size_t limit = size == 0 ? 10 : 1 + data[size - 1] % 12;

    const Index index(docs);
    const auto hits = index.search(query, limit);
    if (hits.size() > limit) fail("more hits than the limit", text);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits[i].document >= docs.size()) fail("a hit past the documents", text);
        if (i > 0 && hits[i].score > hits[i - 1].score) fail("hits out of order", text);
        if (hits[i].matched == Field::tag && hits[i].tag >= docs[hits[i].document].tags.size()) fail("a matched tag that is not there", text);
    }
    if (!words(query).empty())
        for (std::size_t d = 0; d < docs.size(); ++d)
            if (docs[d].name == query) {
                bool found = false;
                for (const auto& h : index.search(query, docs.size())) found |= h.document == d;
                if (!found) fail("a document whose name is the query was not found", text);
                break;
            }

    const auto qw = words(query);
    if (qw.size() >= 2) {
        const bool ab = within_one_edit(qw[0], qw[1], false), ba = within_one_edit(qw[1], qw[0], false);
        if (ab != ba) fail("within_one_edit is not symmetric", text);
        if (ab && !within_one_edit(qw[0], qw[1], true)) fail("a whole-word edit is no prefix edit", text);
    }
    return 0;
}
