#pragma once
// Checks of output paths before the work that fills them: a command that renders for an hour must not find at the
// end that its statistics file cannot be written (docs/cli.md, exit code 2).
#include <filesystem>

namespace chcrt {

// Throws InputError naming `file` when it could not be created: its directory is missing, is a file, or is not
// writable, or `file` itself is a directory. Writes nothing.
void checkOutputPath(const std::filesystem::path& file);

} // namespace chcrt
