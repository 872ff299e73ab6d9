#pragma once
// A building's directory: the names a visitor looks for (rooms, points of interest, the
// people and departments tagged on them) and a ranked search over them that forgives case,
// accents, an unfinished word and one typing mistake per word.
//
// Every word of the query must be found, as a whole word, the start of one or (for words of
// letters only, from kMinTypoLength letters) a word one edit away, in the document's name,
// category or tags. A document's score is the mean over the query's words of the best match
// (exact 1, prefix 0.5 to 0.9 by how much of the word was typed, typo 0.4, a typo in a prefix
// 0.3) times its field's weight (name 1, tag 0.8, category 0.6), plus 1 when the query is the
// whole name or 0.5 when it is a whole tag. Ties go to the shorter name, then the name's
// folded order, then the order the documents were given in.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace locus::directory {

// Typo tolerance starts at this many letters (a shorter word has too many neighbours), and
// a typo in a word still being typed at kMinPrefixTypoLength.
inline constexpr std::size_t kMinTypoLength = 4;
inline constexpr std::size_t kMinPrefixTypoLength = 5;

struct Document {
    std::string name;
    std::string category;           // a POI's or space's kind ("cafeteria", "toilet"); may be empty
    std::vector<std::string> tags;  // people's names, departments
};

enum class Field { name, tag, category };

struct Hit {
    std::size_t document = 0;  // its position in the documents the index was built from
    double score = 0.0;
    // Where the query was found: the name when every word was found there, otherwise the
    // field (and the tag) that held the first word that was not.
    Field matched = Field::name;
    std::size_t tag = 0;  // which of the document's tags, when matched is Field::tag
};

class Index {
public:
    Index() = default;
    explicit Index(const std::vector<Document>& documents);

    std::size_t size() const { return docs_.size(); }
    // At most `limit` hits, best first; none for a query without words.
    std::vector<Hit> search(std::string_view query, std::size_t limit) const;

private:
    // One word of a document: which distinct word, and where it stands.
    struct Occurrence {
        std::uint32_t word;    // index into words_
        std::uint32_t source;  // 0 name, 1 category, 2 + i tag i
    };
    struct Span {
        std::uint32_t begin, size;
    };
    struct DocInfo {
        std::string folded;  // the folded name, for ties
        std::size_t length;  // its code points
        std::uint32_t tags;
    };

    std::u32string_view word(std::uint32_t w) const { return {chars_.data() + spans_[w].begin, spans_[w].size}; }

    std::u32string chars_;                 // every distinct word, one after another
    std::vector<Span> spans_;              // word id → its characters
    std::vector<std::uint32_t> post_begin_;  // word id → its documents in postings_ (size + 1 entries)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> postings_;  // (document, source)
    std::vector<std::uint32_t> doc_begin_;  // document → its words in occurrences_ (size + 1 entries)
    std::vector<Occurrence> occurrences_;   // each document's words in order: name, category, tags
    std::vector<DocInfo> docs_;
};

}  // namespace locus::directory
