#include "http/front/connection_pool.hpp"

#include <system_error>
#include <thread>

namespace locus::http {

ConnectionPool::ConnectionPool(std::size_t min_threads, std::size_t max_threads, std::chrono::milliseconds idle_exit)
    : min_threads_(min_threads), max_threads_(std::max(max_threads, min_threads)), idle_exit_(idle_exit) {
    std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < min_threads_; ++i) spawn_locked();  // fewer if the system refuses
}

ConnectionPool::~ConnectionPool() { shutdown(); }

void ConnectionPool::enqueue(std::function<void()> fn) {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(fn));
    // A queued job stays in jobs_ until a worker takes it, so jobs_ > idle + starting means
    // some job has no worker coming for it.
    if (jobs_.size() > idle_ + starting_ && threads_ < max_threads_ && spawn_locked()) return;
    // No new worker (at the cap, or the system refused one): the job waits for a busy one.
    work_ready_.notify_one();
}

bool ConnectionPool::spawn_locked() {
    // The thread is created before it is counted: when the system refuses a thread (a pids
    // or process limit), the counts stay true and shutdown does not wait for a ghost. The new
    // thread takes the lock first thing, so it cannot see the counts before they are raised.
    try {
        std::thread([this] { work(); }).detach();
    } catch (const std::system_error&) {
        return false;
    }
    ++threads_;
    ++starting_;
    return true;
}

void ConnectionPool::work() {
    std::unique_lock lock(mutex_);
    --starting_;
    for (;;) {
        if (!jobs_.empty()) {
            auto job = std::move(jobs_.front());
            jobs_.pop_front();
            lock.unlock();
            job();
            job = nullptr;  // the connection's captures go before the lock is taken again
            lock.lock();
            continue;
        }
        if (stopping_) break;
        ++idle_;
        const bool woken = work_ready_.wait_for(lock, idle_exit_, [this] { return !jobs_.empty() || stopping_; });
        --idle_;
        if (!woken && threads_ > min_threads_) break;
    }
    --threads_;
    worker_ended_.notify_all();
}

void ConnectionPool::shutdown() {
    std::unique_lock lock(mutex_);
    stopping_ = true;
    work_ready_.notify_all();
    worker_ended_.wait(lock, [this] { return threads_ == 0; });
}

ConnectionPool::Stats ConnectionPool::stats() const {
    std::lock_guard lock(mutex_);
    return {threads_, idle_, jobs_.size()};
}

}  // namespace locus::http
