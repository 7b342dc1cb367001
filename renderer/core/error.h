#pragma once
// Error policy: bugs assert; bad input, shader and GL failures throw one of these and are
// caught once in app/ (one-line message, non-zero exit); expected failures are return values.
#include <stdexcept>
#include <string>

namespace chcrt {

// Bad user input: missing or malformed files, empty scenes, invalid flags or values. Exit code 2.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// GL context, shader compile/link or missing-feature failures. Exit code 3.
class GlError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A correctness check (verify) found differences. Exit code 4. Thrown only by app/ commands.
class VerifyFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

} // namespace chcrt
