#pragma once
// Temporary files removed when the process is interrupted (SIGINT, SIGTERM, SIGHUP): a writer that renames its
// temporary file into place only when it finished (`chcrt prepare`'s F.chs.tmp) removes it itself on errors, but a
// signal skips destructors. While a RemoveOnSignal is alive, the handler unlinks its path and then ends the
// process with the signal's default action, so the exit status still says which signal it was.
#include <filesystem>

namespace chcrt {

class RemoveOnSignal {
public:
    explicit RemoveOnSignal(const std::filesystem::path& file); // installs the handlers on first use
    ~RemoveOnSignal();
    RemoveOnSignal(const RemoveOnSignal&) = delete;
    RemoveOnSignal& operator=(const RemoveOnSignal&) = delete;

private:
    int slot_ = -1; // -1: all slots taken (the file is then only removed by its owner)
};

} // namespace chcrt
