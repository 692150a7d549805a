// SPDX-License-Identifier: Apache-2.0
#pragma once
// One job at a time on a thread kept for the renderer's life: CPU work of a frame that runs
// beside the render thread (OutlinePass::markCells after RoadPass::cull) without starting a thread per frame.

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace navmap::render::gl {

class SideTask {
public:
    SideTask() = default;
    SideTask(const SideTask&) = delete;
    SideTask& operator=(const SideTask&) = delete;
    ~SideTask() {
        if (!m_thread.joinable()) return;
        {
            std::lock_guard lock(m_mutex);
            m_stop = true;
        }
        m_wake.notify_all();
        m_thread.join();
    }

    /// Starts `job` on the side thread (started on first use). The previous job must have been
    /// waited for.
    void start(std::function<void()> job) {
        if (!m_thread.joinable()) m_thread = std::thread([this] { run(); });
        {
            std::lock_guard lock(m_mutex);
            m_job = std::move(job);
            m_busy = true;
        }
        m_wake.notify_all();
    }

    /// Blocks until the job has finished; rethrows what it threw. Returns at once when idle.
    void wait() {
        if (auto error = waitIdle()) std::rethrow_exception(error);
    }

    /// Waits for the job when it leaves scope, also when the caller throws: a job must not
    /// outlive what it reads.
    class [[nodiscard]] Scope {
    public:
        explicit Scope(SideTask& task) : m_task(task) {}
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;
        ~Scope() { (void)m_task.waitIdle(); }  // unwinding already, or reported by wait()

    private:
        SideTask& m_task;
    };

private:
    // Waits until no job runs; returns (and clears) what the last one threw.
    std::exception_ptr waitIdle() {
        std::unique_lock lock(m_mutex);
        m_done.wait(lock, [this] { return !m_busy; });
        return std::exchange(m_error, nullptr);
    }

    void run() {
        std::unique_lock lock(m_mutex);
        for (;;) {
            m_wake.wait(lock, [this] { return m_stop || m_job; });
            if (m_stop) return;
            auto job = std::exchange(m_job, nullptr);
            lock.unlock();
            std::exception_ptr error;
            try {
                job();
            } catch (...) {
                error = std::current_exception();
            }
            lock.lock();
            m_error = error;
            m_busy = false;
            m_done.notify_all();
        }
    }

    std::thread m_thread;
    std::mutex m_mutex;
    std::condition_variable m_wake, m_done;
    std::function<void()> m_job;
    std::exception_ptr m_error;
    bool m_busy = false, m_stop = false;
};

}  // namespace navmap::render::gl
