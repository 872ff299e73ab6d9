// The web viewer's static files over HTTP against the real server: the page at /, its files
// under /web/ and Leaflet under /vendor/leaflet/, each with its content type and caching
// headers, a 304 for a known ETag; every path that could leave a root (.., encoded ..,
// absolute, hidden files) is refused as raw bytes on the wire, whatever a client library
// would have normalised, and a secret beside the root never comes back.
#include <httplib.h>
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_web_test {
namespace {

using locus::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

void write_file(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
}

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

struct RawAnswer {
    int status = 0;
    std::string head, body;
};

// One request exactly as written (no client normalises its path), read to the close.
RawAnswer raw_get(int port, const std::string& target) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        ::close(fd);
        return {};
    }
    const std::string req = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
    (void)!::send(fd, req.data(), req.size(), 0);
    std::string all;
    char buf[65536];
    for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;) all.append(buf, static_cast<std::size_t>(n));
    ::close(fd);
    RawAnswer a;
    const auto split = all.find("\r\n\r\n");
    if (all.size() < 12 || split == std::string::npos) return a;
    a.status = std::stoi(all.substr(9, 3));
    a.head = all.substr(0, split);
    a.body = all.substr(split + 4);
    return a;
}

class WebTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new fs::path(locus::testing::make_temp_dir());
        write_file(*dir_ / "web" / "index.html", "<!doctype html><title>viewer</title>");
        write_file(*dir_ / "web" / "app.js", "export const x = 1;\n");
        write_file(*dir_ / "web" / "style" / "main.css", "body{margin:0}");
        write_file(*dir_ / "web" / ".hidden.js", "HIDDEN-CONTENT");
        write_file(*dir_ / "web" / "notes.txt", "not a viewer file type");
        write_file(*dir_ / "secret.js", "SECRET");
        write_file(*dir_ / "leaflet" / "leaflet.js", "/* leaflet */");
        write_file(*dir_ / "leaflet" / "images" / "marker-icon.png", "\x89PNG");
        server_ = new ServerProcess({"--web-root", (*dir_ / "web").string(), "--leaflet-root", (*dir_ / "leaflet").string()});
    }
    static void TearDownTestSuite() {
        delete server_;
        fs::remove_all(*dir_);
        delete dir_;
    }
    static RawAnswer get(const std::string& target) { return raw_get(server_->port(), target); }
    static std::string header(const RawAnswer& a, const std::string& name) {
        std::istringstream lines(a.head);
        for (std::string line; std::getline(lines, line);) {
            if (line.size() > name.size() + 1 && strncasecmp(line.c_str(), (name + ":").c_str(), name.size() + 1) == 0) {
                std::string v = line.substr(name.size() + 1);
                while (!v.empty() && (v.front() == ' ')) v.erase(0, 1);
                while (!v.empty() && (v.back() == '\r')) v.pop_back();
                return v;
            }
        }
        return "";
    }
    static inline fs::path* dir_ = nullptr;
    static inline ServerProcess* server_ = nullptr;
};

TEST_F(WebTest, ServesThePageAndItsFilesWithTypesAndCaching) {
    const auto page = get("/");
    ASSERT_EQ(page.status, 200) << page.head;
    EXPECT_EQ(page.body, "<!doctype html><title>viewer</title>");
    EXPECT_EQ(header(page, "Content-Type"), "text/html; charset=utf-8");
    EXPECT_EQ(header(page, "Cache-Control"), "no-cache");
    EXPECT_NE(header(page, "Content-Security-Policy").find("default-src 'self'"), std::string::npos);
    EXPECT_EQ(header(page, "X-Content-Type-Options"), "nosniff");

    const auto js = get("/web/app.js");
    ASSERT_EQ(js.status, 200);
    EXPECT_EQ(js.body, "export const x = 1;\n");
    EXPECT_EQ(header(js, "Content-Type"), "text/javascript; charset=utf-8");
    const auto css = get("/web/style/main.css");
    ASSERT_EQ(css.status, 200);
    EXPECT_EQ(header(css, "Content-Type"), "text/css; charset=utf-8");

    const auto leaflet = get("/vendor/leaflet/leaflet.js");
    ASSERT_EQ(leaflet.status, 200);
    EXPECT_EQ(leaflet.body, "/* leaflet */");
    EXPECT_EQ(header(leaflet, "Cache-Control"), "public, max-age=86400");
    const auto png = get("/vendor/leaflet/images/marker-icon.png");
    ASSERT_EQ(png.status, 200);
    EXPECT_EQ(header(png, "Content-Type"), "image/png");
}

TEST_F(WebTest, AKnownETagAnswers304AndAChangedFileANewTag) {
    const auto first = get("/web/app.js");
    const std::string etag = header(first, "ETag");
    ASSERT_FALSE(etag.empty());
    httplib::Client c("127.0.0.1", server_->port());
    auto again = c.Get("/web/app.js", {{"If-None-Match", etag}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304);
    EXPECT_TRUE(again->body.empty());

    write_file(*dir_ / "web" / "app.js", "export const x = 22;\n");
    auto changed = c.Get("/web/app.js", {{"If-None-Match", etag}});
    ASSERT_TRUE(changed);
    EXPECT_EQ(changed->status, 200);
    EXPECT_EQ(changed->body, "export const x = 22;\n");
    EXPECT_NE(changed->get_header_value("ETag"), etag);
}

TEST_F(WebTest, PathsThatCouldLeaveTheRootAreRefused) {
    for (const std::string target :
         {"/web/../secret.js", "/web/%2e%2e/secret.js", "/web/%2E%2E%2Fsecret.js", "/web/style/../../secret.js",
          "/web/..%2fsecret.js", "/web//etc/passwd", "/web/%2fetc%2fpasswd", "/vendor/leaflet/../../secret.js",
          "/vendor/leaflet/%2e%2e/%2e%2e/secret.js", "/web/.hidden.js", "/web/./app.js", "/web/a%00.js",
          "/web/app.js%00.html", "/web/", "/web/style/", "/web/a\\..\\secret.js"}) {
        SCOPED_TRACE(target);
        const auto a = get(target);
        EXPECT_TRUE(a.status == 400 || a.status == 404) << a.status;
        EXPECT_EQ(a.body.find("SECRET"), std::string::npos);
        EXPECT_EQ(a.body.find("HIDDEN-CONTENT"), std::string::npos);
        const auto body = json::parse(a.body, nullptr, false);
        ASSERT_FALSE(body.is_discarded()) << a.body;
        EXPECT_TRUE(body["error"]["code"].is_string());
        EXPECT_FALSE(body["error"]["message"].get<std::string>().empty());
    }
    const auto dotdot = json::parse(get("/web/%2e%2e/secret.js").body);
    EXPECT_EQ(dotdot["error"]["code"], "invalid_path");
    EXPECT_EQ(get("/web/../secret.js").status, 400);
}

TEST_F(WebTest, UnknownFilesAndTypesAre404) {
    EXPECT_EQ(get("/web/missing.js").status, 404);
    EXPECT_EQ(get("/web/notes.txt").status, 404);  // not a type the viewer serves
    EXPECT_EQ(get("/web/style").status, 404);      // a directory
    EXPECT_EQ(get("/vendor/leaflet/leaflet.css").status, 404);
    // The API's own 404s are untouched.
    const auto api = get("/v1/nothing");
    EXPECT_EQ(api.status, 404);
    EXPECT_EQ(json::parse(api.body)["error"]["code"], "not_found");
}

// Without --web-root the server finds share/locus/web beside its binary: the build tree
// holds a copy of the repository's web/ there, as the install tree does.
TEST(WebDefaultRoot, TheBuiltServerServesTheRepositorysViewer) {
    ServerProcess server;
    const auto page = raw_get(server.port(), "/");
    ASSERT_EQ(page.status, 200) << page.head;
    EXPECT_EQ(page.body, read_file(fs::path(LOCUS_SOURCE_DIR) / "web" / "index.html"));
}

TEST(WebDefaultRoot, AnEmptyWebRootServesNoViewer) {
    ServerProcess server({"--web-root", ""});
    const auto page = raw_get(server.port(), "/");
    EXPECT_EQ(page.status, 404);
    EXPECT_NE(page.body.find("no web root"), std::string::npos);
    EXPECT_EQ(raw_get(server.port(), "/health").status, 200);
}

}  // namespace
}  // namespace server_web_test
