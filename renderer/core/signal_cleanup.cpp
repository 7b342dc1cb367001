#include "renderer/core/signal_cleanup.h"

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>
#include <mutex>
#include <unistd.h>

namespace chcrt {
namespace {

// Fixed storage: the handler may only touch what is already allocated (unlink is async-signal-safe, the heap is
// not). A slot's path is complete before `used` is set, and cleared only after `used` is reset.
constexpr size_t kSlots = 16;
constexpr size_t kPathBytes = 4096;
struct Slot {
    std::atomic<bool> used{false};
    char path[kPathBytes] = {};
};
std::array<Slot, kSlots> slots;
std::mutex slotsMutex;
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void removeFilesAndRaise(int signal) {
    for (Slot& s : slots) {
        if (s.used.load()) ::unlink(s.path);
    }
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

void installHandlersOnce() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (int signal : kSignals) {
            struct sigaction action = {};
            action.sa_handler = removeFilesAndRaise;
            sigemptyset(&action.sa_mask);
            struct sigaction previous = {};
            // A signal the caller chose to ignore (nohup) stays ignored.
            if (::sigaction(signal, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN) continue;
            ::sigaction(signal, &action, nullptr);
        }
    });
}

} // namespace

RemoveOnSignal::RemoveOnSignal(const std::filesystem::path& file) {
    const std::string path = std::filesystem::absolute(file).string(); // the handler must not depend on the cwd
    if (path.size() >= kPathBytes) return;
    installHandlersOnce();
    std::lock_guard<std::mutex> lock(slotsMutex);
    for (size_t i = 0; i < kSlots; ++i) {
        if (slots[i].used.load()) continue;
        std::memcpy(slots[i].path, path.c_str(), path.size() + 1);
        slots[i].used.store(true);
        slot_ = int(i);
        return;
    }
}

RemoveOnSignal::~RemoveOnSignal() {
    if (slot_ < 0) return;
    std::lock_guard<std::mutex> lock(slotsMutex);
    slots[size_t(slot_)].used.store(false);
}

} // namespace chcrt
