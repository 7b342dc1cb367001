// The memory budget (--max-memory-mb): its default from the machine, and the one-line error naming the flag and
// the parts of the estimate.
#include "renderer/core/error.h"
#include "renderer/core/memory_budget.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

struct BudgetScope {
    explicit BudgetScope(uint64_t bytes) { setMemoryBudgetBytes(bytes); }
    ~BudgetScope() { setMemoryBudgetBytes(0); }
};

std::string budgetError(const MemoryParts& parts) {
    try {
        checkMemoryBudget(parts);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(MemoryBudget, DefaultsToFourFifthsOfThePhysicalMemory) {
    EXPECT_GT(physicalMemoryBytes(), uint64_t(64) << 20);
    EXPECT_EQ(defaultMemoryBudgetBytes(), physicalMemoryBytes() / 5 * 4);
    EXPECT_EQ(memoryBudgetBytes(), defaultMemoryBudgetBytes());
    {
        const BudgetScope scope(uint64_t(100) << 20);
        EXPECT_EQ(memoryBudgetBytes(), uint64_t(100) << 20);
    }
    EXPECT_EQ(memoryBudgetBytes(), defaultMemoryBudgetBytes());
}

TEST(MemoryBudget, AnEstimateOverTheBudgetNamesTheFlagAndItsParts) {
    const BudgetScope scope(uint64_t(100) << 20);
    EXPECT_EQ(budgetError({{"render targets 512x512", uint64_t(60) << 20}, {"scene", uint64_t(40) << 20}}), "")
        << "exactly the budget fits";
    EXPECT_EQ(budgetError({{"render targets 16384x16384", uint64_t(73728) << 20}, {"unused", 0}, {"scene", 1}}),
              "this run needs at least 73,729 MiB (render targets 16384x16384: 73,728 MiB, scene: 1 MiB), more than "
              "the 100 MiB --max-memory-mb allows");
    EXPECT_THROW(checkMemoryBudget((uint64_t(100) << 20) + 1, "one byte too many"), InputError);
    // Parts that add up past 2^64 (sizes from hostile headers) saturate instead of wrapping to a small total.
    EXPECT_NE(budgetError({{"a", UINT64_MAX / 2 + 2}, {"b", UINT64_MAX / 2 + 2}}), "");
}

TEST(MemoryBudget, TheDefaultIsNamedAsTheMachines) {
    const std::string message = budgetError({{"everything", UINT64_MAX}});
    EXPECT_NE(message.find("--max-memory-mb allows (default: 4/5 of this machine's "), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(MemoryBudget, MegabytesAreRoundedUpAndGrouped) {
    EXPECT_EQ(formatMegabytes(0), "0 MiB");
    EXPECT_EQ(formatMegabytes(1), "1 MiB");
    EXPECT_EQ(formatMegabytes(uint64_t(1) << 20), "1 MiB");
    EXPECT_EQ(formatMegabytes(uint64_t(1234567) << 20), "1,234,567 MiB");
}

} // namespace
} // namespace chcrt
