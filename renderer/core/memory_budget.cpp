#include "renderer/core/memory_budget.h"

#include "renderer/core/error.h"

#include <atomic>
#include <unistd.h>

namespace chcrt {
namespace {

std::atomic<uint64_t> gBudget{0}; // 0: not set, the default applies

std::string thousands(uint64_t value) {
    const std::string digits = std::to_string(value);
    std::string grouped;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) grouped += ',';
        grouped += digits[i];
    }
    return grouped;
}

} // namespace

uint64_t physicalMemoryBytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES);
    const long pageSize = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return uint64_t(4) << 30; // unknown: assume a small machine
    return uint64_t(pages) * uint64_t(pageSize);
}

uint64_t defaultMemoryBudgetBytes() { return physicalMemoryBytes() / 5 * 4; }

uint64_t memoryBudgetBytes() {
    const uint64_t set = gBudget.load(std::memory_order_relaxed);
    return set != 0 ? set : defaultMemoryBudgetBytes();
}

void setMemoryBudgetBytes(uint64_t bytes) { gBudget.store(bytes, std::memory_order_relaxed); }

std::string formatMegabytes(uint64_t bytes) { return thousands((bytes + (uint64_t(1) << 20) - 1) >> 20) + " MiB"; }

void checkMemoryBudget(const MemoryParts& parts) {
    uint64_t total = 0;
    for (const auto& [what, bytes] : parts) {
        total = bytes > UINT64_MAX - total ? UINT64_MAX : total + bytes;
    }
    const uint64_t budget = memoryBudgetBytes();
    if (total <= budget) return;
    std::string list;
    for (const auto& [what, bytes] : parts) {
        if (bytes == 0) continue;
        list += (list.empty() ? "" : ", ") + what + ": " + formatMegabytes(bytes);
    }
    const bool isDefault = gBudget.load(std::memory_order_relaxed) == 0;
    throw InputError("this run needs at least " + formatMegabytes(total) + " (" + list + "), more than the " +
                     formatMegabytes(budget) + " --max-memory-mb allows" +
                     (isDefault ? " (default: 4/5 of this machine's " + formatMegabytes(physicalMemoryBytes()) + ")"
                                : std::string()));
}

void checkMemoryBudget(uint64_t bytes, const std::string& what) { checkMemoryBudget(MemoryParts{{what, bytes}}); }

} // namespace chcrt
