// A request body with a Content-Encoding (server/http/body_coding.*), then the localize
// request parser on what it decodes to: the compressed path a client can take into the server.
//
// The first byte chooses the coding (gzip, deflate, identity), the rest is the body as sent.
// Checks: decoding never yields more than the limit; a refused body leaves nothing behind; an
// accepted one is handed to parse_localize_request, which refuses only with an ApiError.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "http/api_error.hpp"
#include "http/front/body_coding.hpp"
#include "http/localize/localize_request.hpp"

using namespace locus::http;

namespace {

constexpr std::uint64_t kLimit = 256 * 1024;  // small, so that bombs reach it quickly

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz_body_coding: %s\n", what);
        std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const BodyCoding coding = data[0] % 3 == 0 ? BodyCoding::gzip : data[0] % 3 == 1 ? BodyCoding::deflate : BodyCoding::identity;
    const std::string_view sent(reinterpret_cast<const char*>(data + 1), size - 1);
    const DecodedBody decoded = decode_body(sent, coding, kLimit);
    check(decoded.body.size() <= kLimit, "decoded past the limit");
    if (decoded.status != DecodedBody::Status::ok) {
        check(decoded.body.empty(), "a refused body left bytes behind");
        check(decoded.status == DecodedBody::Status::too_large || !decoded.problem.empty(), "a corrupt body without a reason");
        return 0;
    }
    if (coding == BodyCoding::identity) check(decoded.body == sent, "identity changed the body");
    try {
        (void)parse_localize_request(decoded.body);
    } catch (const ApiError& e) {
        check(e.status == 400 || e.status == 422, "an ApiError with a status other than 400/422");
    }
    return 0;
}
