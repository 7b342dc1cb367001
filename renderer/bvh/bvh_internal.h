#pragma once
// Helpers shared by the BVH builder, its statistics and the CPU tracer; not part of the public interface.
#include "renderer/bvh/bvh.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace chcrt::detail {

// 0 = hardware concurrency; never less than one.
inline uint32_t resolveThreadCount(uint32_t requested) {
    if (requested != 0) {
        return requested;
    }
    return std::max(1u, std::thread::hardware_concurrency());
}

// Minimal fork-join loop: calls fn(workerIndex, item) for every item in [0, itemCount) on up to `threads`
// threads (the caller is worker 0). Items are handed out through one atomic counter, so uneven items balance.
// workerIndex < threads lets callers keep per-worker accumulators without locks. The first exception thrown
// by any item is rethrown in the caller after all workers stopped.
//
// What it is not: a task system. No nesting, no work stealing; the BVH builder only needs flat loops.
template <class Fn>
void parallelFor(uint32_t threads, uint32_t itemCount, Fn&& fn) {
    threads = std::min(threads, itemCount);
    if (threads <= 1) {
        for (uint32_t item = 0; item < itemCount; ++item) {
            fn(0u, item);
        }
        return;
    }
    std::atomic<uint32_t> next{0};
    std::exception_ptr failure;
    std::mutex failureMutex;
    auto work = [&](uint32_t worker) {
        try {
            for (uint32_t item = next.fetch_add(1); item < itemCount; item = next.fetch_add(1)) {
                fn(worker, item);
            }
        } catch (...) {
            const std::lock_guard lock(failureMutex);
            if (!failure) {
                failure = std::current_exception();
            }
            next.store(itemCount); // let the other workers run out of items
        }
    };
    {
        std::vector<std::jthread> helpers;
        helpers.reserve(threads - 1);
        for (uint32_t worker = 1; worker < threads; ++worker) {
            helpers.emplace_back(work, worker);
        }
        work(0u);
    } // jthreads join here
    if (failure) {
        std::rethrow_exception(failure);
    }
}

// Fills everything in bvh.stats except buildSeconds (tree walk: counts, depth, SAH cost, bytes).
void measureBvh(Bvh& bvh, float traversalCost, float intersectionCost);

} // namespace chcrt::detail
