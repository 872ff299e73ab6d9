#pragma once
// Starts the real locus-server binary on 127.0.0.1 with an OS-chosen port and a temp SQLite
// file (or, under scripts/with_postgres.sh, a fresh PostgreSQL database: test_database.hpp),
// and talks HTTP to it. The db survives stop()/start() so restarts can be tested.
#include <sys/types.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_database.hpp"

// By reference and as a declared return type only: a test that talks HTTP itself includes
// <httplib.h> (some 100,000 lines, most integration tests never need them).
namespace httplib {
class Client;
class Result;
}  // namespace httplib

namespace locus::testing {

// RLIMIT_FSIZE for the server process: no file it writes grows past this many bytes (writes
// fail with EFBIG, as on a full disk).
struct FileSizeLimit {
    long long bytes = 0;
};

// A second server on the database of a first one (PostgreSQL: replicas).
struct SameDatabase {
    std::string db;  // the first server's db()
};

struct Response {
    int status = 0;  // 0 = no answer (connection failed)
    nlohmann::json body;
    std::string raw;
};
Response to_response(const httplib::Result& r);
// A client of the server on `port` (127.0.0.1) with timeouts generous enough for a loaded CI machine.
httplib::Client client(int port);

class ServerProcess {
public:
    explicit ServerProcess(std::vector<std::string> extra_args = {});
    ServerProcess(std::vector<std::string> extra_args, FileSizeLimit limit);
    ServerProcess(std::vector<std::string> extra_args, SameDatabase same);
    ~ServerProcess();
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;

    void start();
    int stop(int signal_number = 15);  // returns the exit status (or 128+signal)
    void kill9();

    int port() const { return port_; }
    std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
    // The SQLite file; on PostgreSQL there is none (tests that open the file skip there).
    const std::string& db_path() const { return db_path_; }
    pid_t pid() const { return pid_; }  // the locus-server process itself (execv'd, no shell)
    // What --db says: the SQLite file or the PostgreSQL URL.
    const std::string& db() const { return db_; }
    const std::string& dir() const { return dir_; }
    std::string log() const;  // everything the server printed so far
    void set_api_key(std::string key) { api_key_ = std::move(key); }
    // Applies from the next start(); 0 lifts the limit.
    void set_file_size_limit(long long bytes) { file_size_limit_ = bytes; }

    Response get(const std::string& path) const;
    Response post(const std::string& path, const nlohmann::json& body) const;
    Response post_raw(const std::string& path, const std::string& body,
                      const std::string& content_type = "application/json") const;
    Response patch(const std::string& path, const nlohmann::json& body) const;
    Response put(const std::string& path, const nlohmann::json& body) const;
    Response del(const std::string& path) const;

private:
    void init_db();
    std::vector<std::string> extra_args_;
    std::unique_ptr<TestDatabase> database_;  // PostgreSQL: owned by the server that created it
    std::string dir_, db_path_, db_, log_path_, api_key_;
    pid_t pid_ = -1;
    int port_ = 0;
    long long file_size_limit_ = 0;
};

// The body of an answer with `status`; otherwise throws, failing the test with the status and
// what came back. A request that timed out has status 0 and a null body: read unchecked, it
// failed later as a type_error on null that hid the cause.
nlohmann::json body_of(const Response& r, int status = 200);

// Runs the locus CLI, returning exit status and captured stdout (stderr goes to a file).
struct CommandResult {
    int status = -1;
    std::string out;
    std::string err;
};
CommandResult run_command(const std::vector<std::string>& argv, const std::vector<std::string>& env = {});

std::string make_temp_dir();

}  // namespace locus::testing
