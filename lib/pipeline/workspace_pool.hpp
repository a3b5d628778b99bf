// Working buffers lent to whichever thread runs the next item and taken back after it, for a per-frame
// step called from a callback that does not say which thread it runs on (a stage's frame consumer).
// A frame-sized buffer made for every frame has fresh pages mapped and zeroed by the system (a
// diffusion's working set is 0.18 GB at 1080p); kept, they are mapped once per thread.
// The pool holds at most as many as were ever lent at once, so the caller budgets one per thread.
#pragma once
#include <memory>
#include <mutex>
#include <vector>

namespace statfilter {

template <class T>
class WorkspacePool {
public:
    // One workspace, returned to the pool (or let go, see keep) when the lease ends.
    class Lease {
    public:
        Lease(WorkspacePool& pool, std::unique_ptr<T> item) : pool_(&pool), item_(std::move(item)) {}
        Lease(Lease&& other) noexcept = default;
        Lease& operator=(Lease&&) = delete;
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        ~Lease() {
            if (item_) pool_->give_back(std::move(item_));
        }
        T& operator*() { return *item_; }
        T* operator->() { return item_.get(); }

    private:
        WorkspacePool* pool_;
        std::unique_ptr<T> item_;
    };

    Lease borrow() {
        std::unique_ptr<T> item;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!idle_.empty()) {
                item = std::move(idle_.back());
                idle_.pop_back();
            }
        }
        if (!item) item = std::make_unique<T>();
        return Lease(*this, std::move(item));
    }
    // Whether a returned workspace is kept for the next item (the default); when the budget has no room
    // for one per thread between items, each goes when its lease ends, and the idle ones go now.
    void keep(bool keep) {
        std::lock_guard<std::mutex> lock(mutex_);
        keep_ = keep;
        if (!keep_) idle_.clear();
    }
    // Lets the idle workspaces go (between phases budgeted apart).
    void release() {
        std::lock_guard<std::mutex> lock(mutex_);
        idle_.clear();
    }

private:
    void give_back(std::unique_ptr<T> item) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (keep_) idle_.push_back(std::move(item));
    }

    std::mutex mutex_;
    std::vector<std::unique_ptr<T>> idle_;
    bool keep_ = true;
};

}  // namespace statfilter
