#include "http/front/static_files.hpp"

#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>
#include <system_error>

#include "http/app.hpp"

namespace locus::http {

namespace fs = std::filesystem;

namespace {

// A path segment the viewer's files can have: letters, digits, '-', '_' and dots, not
// starting with a dot (so neither "." nor ".." nor hidden files).
bool plain_segment(std::string_view s) {
    if (s.empty() || s.front() == '.' || s.size() > 128) return false;
    for (const char c : s) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                        c == '_' || c == '.';
        if (!ok) return false;
    }
    return true;
}

// Why `rel` (the part of the URL after the route's prefix) is refused, or "" when it is a
// plain relative name. The check is on the decoded path and refuses '%' as well, so an
// encoded "%2e%2e" is refused whether or not the HTTP library decoded it.
std::string path_problem(const std::string& rel) {
    if (rel.empty()) return "empty file name";
    if (rel.front() == '/') return "absolute path";
    std::size_t depth = 0, start = 0;
    while (start <= rel.size()) {
        const std::size_t end = rel.find('/', start);
        const std::string_view seg =
            std::string_view(rel).substr(start, end == std::string::npos ? std::string::npos : end - start);
        if (seg == "..") return "'..' in the path";
        if (!plain_segment(seg)) return "path segment '" + std::string(seg.substr(0, 64)) + "' is not a plain file name";
        if (++depth > 4) return "path too deep";
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return "";
}

// A weak validator from what changes when the file is replaced.
std::string etag_of(const fs::path& file, std::uintmax_t size) {
    std::error_code ec;
    const auto mtime = fs::last_write_time(file, ec);
    const auto ticks = ec ? 0 : static_cast<long long>(mtime.time_since_epoch().count());
    std::ostringstream out;
    out << "W/\"" << std::hex << size << '-' << ticks << '"';
    return out.str();
}

void serve_file(const httplib::Request& req, httplib::Response& res, const std::string& root, const std::string& rel,
                const char* cache_control) {
    if (root.empty()) {
        write_error(res, 404, "not_found", "this server does not serve the web viewer (no web root)");
        return;
    }
    if (const auto problem = path_problem(rel); !problem.empty()) {
        write_error(res, 400, "invalid_path", problem);
        return;
    }
    const auto type = content_type_of(rel);
    const fs::path file = fs::path(root) / rel;
    std::error_code ec;
    if (!type || !fs::is_regular_file(file, ec)) {
        write_error(res, 404, "not_found", "no file '" + rel + "'");
        return;
    }
    const auto size = fs::file_size(file, ec);
    if (ec) {
        write_error(res, 404, "not_found", "no file '" + rel + "'");
        return;
    }
    const std::string etag = etag_of(file, size);
    res.set_header("Cache-Control", cache_control);
    res.set_header("ETag", etag);
    res.set_header("X-Content-Type-Options", "nosniff");
    if (req.get_header_value("If-None-Match") == etag) {
        res.status = 304;
        return;
    }
    std::ifstream in(file, std::ios::binary);
    std::string body(static_cast<std::size_t>(size), '\0');
    if (!in.read(body.data(), static_cast<std::streamsize>(body.size()))) {
        write_error(res, 404, "not_found", "file '" + rel + "' could not be read");
        return;
    }
    res.status = 200;
    res.set_content(std::move(body), *type);
}

// The viewer talks only to this server and loads nothing from elsewhere; Leaflet sets element
// styles, which CSP counts as inline style.
constexpr const char* viewer_csp =
    "default-src 'self'; img-src 'self' data: blob:; style-src 'self' 'unsafe-inline'; connect-src 'self'; "
    "object-src 'none'; base-uri 'none'; frame-ancestors 'none'";

}  // namespace

std::string default_web_root() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "";
    return (exe.parent_path().parent_path() / "share" / "locus" / "web").string();
}

std::optional<std::string> content_type_of(const std::string& name) {
    static const std::array<std::pair<std::string_view, std::string_view>, 9> types{{
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".png", "image/png"},
        {".svg", "image/svg+xml"},
        {".json", "application/json"},
        {".ico", "image/x-icon"},
        {".webmanifest", "application/manifest+json"},
    }};
    for (const auto& [ext, type] : types)
        if (name.size() > ext.size() && name.ends_with(ext)) return std::string(type);
    return std::nullopt;
}

void install_static_routes(httplib::Server& server, const StaticRoots& roots) {
    // The page changes with the server; each load asks (a 304 when unchanged).
    server.Get("/", [web = roots.web](const httplib::Request& req, httplib::Response& res) {
        serve_file(req, res, web, "index.html", "no-cache");
        res.set_header("Content-Security-Policy", viewer_csp);
    });
    server.Get(R"(/web/(.*))", [web = roots.web](const httplib::Request& req, httplib::Response& res) {
        serve_file(req, res, web, req.matches[1].str(), "no-cache");
    });
    // Leaflet changes only with the Debian package: a day of caching is safe.
    server.Get(R"(/vendor/leaflet/(.*))", [leaflet = roots.leaflet](const httplib::Request& req, httplib::Response& res) {
        serve_file(req, res, leaflet, req.matches[1].str(), "public, max-age=86400");
    });
}

}  // namespace locus::http
