#include "renderer/core/output_path.h"

#include "renderer/core/error.h"

#include <unistd.h>

namespace chcrt {
namespace fs = std::filesystem;

void checkOutputPath(const fs::path& file) {
    std::error_code error;
    if (fs::is_directory(file, error)) throw InputError(file.string() + ": is a directory, not a file to write");
    const fs::path directory = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    if (!fs::exists(directory, error)) {
        throw InputError(file.string() + ": directory \"" + directory.string() + "\" does not exist");
    }
    if (!fs::is_directory(directory, error)) {
        throw InputError(file.string() + ": \"" + directory.string() + "\" is a file, not a directory");
    }
    if (::access(directory.c_str(), W_OK | X_OK) != 0) {
        throw InputError(file.string() + ": directory \"" + directory.string() + "\" is not writable");
    }
}

} // namespace chcrt
