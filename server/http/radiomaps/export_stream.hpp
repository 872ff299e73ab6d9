#pragma once
// GET /v1/radiomaps/{id}/export written out as it is read (store::RadioMapReader): the same
// bytes as json_text(export_json(...)) of the whole document, with one batch of RPs in memory
// at a time instead of the document (a 100,000-RP map's was about 3 GB as a JSON value).
#include <cstddef>
#include <memory>
#include <string>

#include "store/documents.hpp"

namespace locus::http {

class ExportStream {
public:
    explicit ExportStream(std::unique_ptr<store::RadioMapReader> reader, std::size_t rps_per_piece = 256);
    // The document's next piece; empty once all of it was given. The reader (its connection
    // and read transaction) is let go as soon as the last RP was read.
    std::string next();

private:
    std::unique_ptr<store::RadioMapReader> reader_;
    std::size_t rps_per_piece_;
    std::string head_, tail_;  // the document before its first RP, and from the end of "rps" on
    enum class Part { head, rps, done } part_ = Part::head;
    bool first_rp_ = true;
};

}  // namespace locus::http
