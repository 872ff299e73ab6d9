#pragma once
// Many servers, one PostgreSQL database: how a committed write on one server reaches the
// indexes and caches of the others. The writing transaction adds one to change_counter.version
// and sends NOTIFY locus_changes with the changes and that version (payload_of), so the
// notification leaves only on commit; every server's ChangeWatcher LISTENs on its own
// connection and hands other servers' changes to the same feed local writes use
// (Store::subscribe). Versions are consecutive (writes take one lock), so a missed
// notification shows as a gap; and the counter, read twice a second, catches one that never
// came (a dropped listener connection). Either way the watcher hands on "everything changed".
// Live tracks' writes come on a second channel, uncounted (announce_tracks).
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "store/documents.hpp"

namespace locus::store {

// The NOTIFY payload: origin (the writing server), version and the changes; past PostgreSQL's
// payload limit, the changes are left out and the payload means "everything changed".
std::string payload_of(const std::string& origin, std::int64_t version, const std::vector<Change>& changes);
// The payload up to its version: payload_of(…) is payload_head(…) + the version + "}", so the
// writing transaction can add the version it takes from change_counter in the same statement.
std::string payload_head(const std::string& origin, const std::vector<Change>& changes);
struct Notification {
    std::string origin;
    std::int64_t version = 0;
    bool everything = false;
    std::vector<Change> changes;
};
// The statement a write transaction on `db` (PostgreSQL) ends with, sent with its COMMIT
// (Transaction::commit): it adds one to change_counter and sends the notification with that
// version, so other servers see `changes` once it commits.
class Db;
std::string announcement(Db& db, const std::string& origin, const std::vector<Change>& changes);
// Live tracks' writes (tracks::Service, on its own connection) are announced on a channel of
// their own, locus_tracks, without the counter: bumping its one row would make every fix post
// wait on the row lock of the one before it. (Their commits are serialized all the same:
// PostgreSQL commits NOTIFY-sending transactions one at a time cluster-wide, a lock taken in
// PreCommit_Notify; measured in docs/deploy.md "Live tracks".) Nothing is invalidated by them, only
// event streams woken, so a notification lost with its connection is made good by the
// "everything changed" the watcher hands on when it reconnects.
void announce_tracks(Db& db, const std::string& origin, const std::vector<Change>& changes);
// Throws on a payload payload_of did not write.
Notification parse_payload(const std::string& payload);
// The change that makes every subscriber drop everything it holds (a deleted map, id 0).
Change everything_changed();

class ChangeWatcher {
public:
    using Apply = std::function<void(const std::vector<Change>&)>;
    // Connects on its own thread (retrying every second while PostgreSQL is away) and calls
    // `apply` there with the changes of servers other than `origin`, tracks' included.
    ChangeWatcher(std::string url, std::string origin, Apply apply);
    ~ChangeWatcher();
    ChangeWatcher(const ChangeWatcher&) = delete;
    ChangeWatcher& operator=(const ChangeWatcher&) = delete;

private:
    void run();

    std::string url_, origin_;
    Apply apply_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace locus::store
