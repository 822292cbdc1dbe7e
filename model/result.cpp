#include "model/result.hpp"

namespace geoslice {

const char* errorCodeName(ErrorCode code) {
    switch (code) {
        case ErrorCode::InvalidArgument:
            return "invalid_argument";
        case ErrorCode::ParseError:
            return "parse_error";
        case ErrorCode::IoError:
            return "io_error";
        case ErrorCode::NotFound:
            return "not_found";
        case ErrorCode::Unsupported:
            return "unsupported";
        case ErrorCode::OutOfRange:
            return "out_of_range";
        case ErrorCode::Internal:
            return "internal";
        case ErrorCode::Unavailable:
            return "unavailable";
        case ErrorCode::DeadlineExceeded:
            return "deadline_exceeded";
    }
    return "internal";
}

void assertionFailed(const char* expr, const char* file, int line, const char* msg) {
    std::fprintf(stderr, "geoslice: invariant broken at %s:%d: %s (%s)\n", file, line, msg, expr);
    std::abort();
}

}  // namespace geoslice
