#pragma once
// The workers behind the HTTP front. cpp-httplib hands each accepted connection to a
// TaskQueue and serves it on one worker until the connection closes; its own ThreadPool has a
// fixed size, so with --threads 8, eight idle keep-alive connections stalled every other
// client. This pool keeps `min_threads` workers and starts another whenever a connection
// arrives and no worker is free, up to `max_threads`; a worker idle for `idle_exit` ends
// (down to min_threads).
//
// Cost: one thread per open connection: 8 MiB of stack reserved (a few pages touched) and a
// sleeping thread in poll(). The connection cap (Front) bounds the count; for fan-in beyond a
// few thousand connections, put nginx in front (docker/nginx.conf).
#include <httplib.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>

namespace locus::http {

class ConnectionPool final : public httplib::TaskQueue {
public:
    ConnectionPool(std::size_t min_threads, std::size_t max_threads,
                   std::chrono::milliseconds idle_exit = std::chrono::seconds(30));
    ~ConnectionPool() override;
    ConnectionPool(const ConnectionPool&) = delete;
    ConnectionPool& operator=(const ConnectionPool&) = delete;

    void enqueue(std::function<void()> fn) override;
    // Runs every queued job, then waits until every worker has ended.
    void shutdown() override;

    struct Stats {
        std::size_t threads = 0, idle = 0, queued = 0;
    };
    Stats stats() const;

private:
    bool spawn_locked();  // false when the system refuses a thread
    void work();

    const std::size_t min_threads_, max_threads_;
    const std::chrono::milliseconds idle_exit_;
    mutable std::mutex mutex_;
    std::condition_variable work_ready_, worker_ended_;
    std::deque<std::function<void()>> jobs_;
    std::size_t threads_ = 0;   // started and not yet ended
    std::size_t idle_ = 0;      // waiting for a job
    std::size_t starting_ = 0;  // started, not yet looking for a job
    bool stopping_ = false;
};

}  // namespace locus::http
