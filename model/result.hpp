// Expected failures as values: a code plus a message that names the input and what was
// wrong. Broken invariants are GS_ASSERT, which stays on in release builds.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <variant>

namespace geoslice {

enum class ErrorCode {
    InvalidArgument,   // a bad value from a caller (CLI flag, request field)
    ParseError,        // a malformed file: the message names file, line or byte offset
    IoError,           // cannot open, read or write a file
    NotFound,          // a named thing (file, model, record) does not exist
    Unsupported,       // a valid input that geoslice does not handle (yet)
    OutOfRange,        // a number outside what the operation accepts
    Internal,          // a dependency failed in a way we cannot attribute to the input
    Unavailable,       // no capacity now (queue full, memory budget spent): retry later
    DeadlineExceeded,  // the work did not finish in time, or its caller is gone (cancelled)
};

const char* errorCodeName(ErrorCode code);

struct Error {
    ErrorCode code = ErrorCode::Internal;
    std::string message;
};

inline Error makeError(ErrorCode code, std::string message) { return Error{code, std::move(message)}; }

// Result<T>: either a T or an Error. Accessing the wrong alternative is an invariant break.
template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error error) : v_(std::move(error)) {}

    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T* operator->() { return &std::get<0>(v_); }
    const T* operator->() const { return &std::get<0>(v_); }
    T& operator*() & { return std::get<0>(v_); }

    const Error& error() const { return std::get<1>(v_); }

private:
    std::variant<T, Error> v_;
};

// Result<void> equivalent.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : error_(std::move(error)), ok_(false) {}
    bool ok() const { return ok_; }
    explicit operator bool() const { return ok_; }
    const Error& error() const { return error_; }

private:
    Error error_;
    bool ok_ = true;
};

[[noreturn]] void assertionFailed(const char* expr, const char* file, int line, const char* msg);

}  // namespace geoslice

// An invariant that must hold in every build type.
#define GS_ASSERT(expr, msg)                                                        \
    do {                                                                            \
        if (!(expr)) ::geoslice::assertionFailed(#expr, __FILE__, __LINE__, (msg)); \
    } while (0)
