#include "server_process.hpp"

#include <httplib.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include "text_file.hpp"
#include "build_paths.hpp"


namespace locus::testing {

Response to_response(const httplib::Result& r) {
    Response out;
    if (!r) return out;
    out.status = r->status;
    out.raw = r->body;
    out.body = nlohmann::json::parse(r->body, nullptr, false);
    return out;
}

// Generous timeouts: on a loaded CI machine a large export can take longer than
// cpp-httplib's default 5 s read timeout, and a test then read the body of no answer.
httplib::Client client(int port) {
    httplib::Client c("127.0.0.1", port);
    c.set_connection_timeout(10, 0);
    c.set_read_timeout(30, 0);
    c.set_write_timeout(30, 0);
    return c;
}

namespace {

int wait_status(pid_t pid) {
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return -1;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return -1;
}
}  // namespace

std::string make_temp_dir() {
    std::string tmpl = (std::getenv("TMPDIR") ? std::string(std::getenv("TMPDIR")) : std::string("/tmp")) +
                       "/locus-test-XXXXXX";
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    return tmpl;
}

ServerProcess::ServerProcess(std::vector<std::string> extra_args) : extra_args_(std::move(extra_args)) {
    // A server may refuse a body and close while a test is still sending it: that must fail
    // the request, not kill the test process.
    std::signal(SIGPIPE, SIG_IGN);
    init_db();
    start();
}

ServerProcess::ServerProcess(std::vector<std::string> extra_args, FileSizeLimit limit)
    : extra_args_(std::move(extra_args)), file_size_limit_(limit.bytes) {
    init_db();
    start();
}

ServerProcess::ServerProcess(std::vector<std::string> extra_args, SameDatabase same) : extra_args_(std::move(extra_args)) {
    std::signal(SIGPIPE, SIG_IGN);
    dir_ = make_temp_dir();
    log_path_ = dir_ + "/server.log";
    db_ = same.db;
    if (!on_postgres()) db_path_ = db_;
    start();
}

void ServerProcess::init_db() {
    dir_ = make_temp_dir();
    log_path_ = dir_ + "/server.log";
    if (on_postgres()) {
        database_ = std::make_unique<TestDatabase>();
        db_ = database_->url();
    } else {
        db_path_ = dir_ + "/locus.db";
        db_ = db_path_;
    }
}

ServerProcess::~ServerProcess() {
    if (pid_ > 0) stop();
    std::error_code ec;
    std::string cmd = "rm -rf '" + dir_ + "'";
    [[maybe_unused]] int rc = std::system(cmd.c_str());
}

void ServerProcess::start() {
    std::vector<std::string> args{LOCUS_SERVER_BIN, "--db", db_, "--host", "127.0.0.1", "--port", "0"};
    args.insert(args.end(), extra_args_.begin(), extra_args_.end());
    const auto offset = static_cast<std::size_t>(slurp(log_path_).size());
    pid_ = fork();
    if (pid_ == 0) {
        FILE* f = std::fopen(log_path_.c_str(), "a");
        if (f) {
            dup2(fileno(f), 1);
            dup2(fileno(f), 2);
        }
        if (file_size_limit_ > 0) {
            const rlimit limit{static_cast<rlim_t>(file_size_limit_), static_cast<rlim_t>(file_size_limit_)};
            setrlimit(RLIMIT_FSIZE, &limit);
        }
        std::vector<char*> cargs;
        for (auto& a : args) cargs.push_back(a.data());
        cargs.push_back(nullptr);
        execv(cargs[0], cargs.data());
        _exit(127);
    }
    // The server prints {"event":"listening",...,"port":N} once it accepts connections.
    const std::regex listening(R"re("event":"listening".*"port":(\d+))re");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
        const std::string log = slurp(log_path_).substr(offset);
        std::smatch m;
        if (std::regex_search(log, m, listening)) {
            port_ = std::stoi(m[1].str());
            return;
        }
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            throw std::runtime_error("locus-server exited during start-up:\n" + log);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    throw std::runtime_error("locus-server did not start listening within 20 s:\n" + slurp(log_path_));
}

int ServerProcess::stop(int signal_number) {
    if (pid_ <= 0) return -1;
    kill(pid_, signal_number);
    const int status = wait_status(pid_);
    pid_ = -1;
    return status;
}

void ServerProcess::kill9() { stop(SIGKILL); }

std::string ServerProcess::log() const { return slurp(log_path_); }

namespace {
// What every request of a ServerProcess carries: its API key, when it has one.
httplib::Headers key_headers(const std::string& api_key) {
    httplib::Headers h;
    if (!api_key.empty()) h.emplace("Authorization", "Bearer " + api_key);
    return h;
}
}  // namespace

Response ServerProcess::get(const std::string& path) const {
    auto c = client(port_);
    return to_response(c.Get(path.c_str(), key_headers(api_key_)));
}

Response ServerProcess::post(const std::string& path, const nlohmann::json& body) const {
    return post_raw(path, body.dump());
}

Response ServerProcess::post_raw(const std::string& path, const std::string& body,
                                 const std::string& content_type) const {
    auto c = client(port_);
    return to_response(c.Post(path.c_str(), key_headers(api_key_), body, content_type.c_str()));
}

Response ServerProcess::patch(const std::string& path, const nlohmann::json& body) const {
    auto c = client(port_);
    return to_response(c.Patch(path.c_str(), key_headers(api_key_), body.dump(), "application/json"));
}

Response ServerProcess::put(const std::string& path, const nlohmann::json& body) const {
    auto c = client(port_);
    return to_response(c.Put(path.c_str(), key_headers(api_key_), body.dump(), "application/json"));
}

Response ServerProcess::del(const std::string& path) const {
    auto c = client(port_);
    return to_response(c.Delete(path.c_str(), key_headers(api_key_)));
}

nlohmann::json body_of(const Response& r, int status) {
    if (r.status != status)
        throw std::runtime_error("expected status " + std::to_string(status) + ", got " + std::to_string(r.status) +
                                 (r.status == 0 ? " (no answer: connection failed or timed out)" : "") + ": " + r.raw);
    return r.body;
}

CommandResult run_command(const std::vector<std::string>& argv, const std::vector<std::string>& env) {
    const std::string dir = make_temp_dir();
    const std::string out_path = dir + "/out", err_path = dir + "/err";
    const pid_t pid = fork();
    if (pid == 0) {
        FILE* out = std::fopen(out_path.c_str(), "w");
        FILE* err = std::fopen(err_path.c_str(), "w");
        if (out) dup2(fileno(out), 1);
        if (err) dup2(fileno(err), 2);
        for (const auto& kv : env) putenv(const_cast<char*>(kv.c_str()));
        std::vector<char*> cargs;
        for (const auto& a : argv) cargs.push_back(const_cast<char*>(a.c_str()));
        cargs.push_back(nullptr);
        execv(cargs[0], cargs.data());
        _exit(127);
    }
    CommandResult r;
    r.status = wait_status(pid);
    r.out = slurp(out_path);
    r.err = slurp(err_path);
    std::string cmd = "rm -rf '" + dir + "'";
    [[maybe_unused]] int rc = std::system(cmd.c_str());
    return r;
}

}  // namespace locus::testing
