// kinscene shim conventions, shared by every backend's C ABI.
//
// Every fallible shim function returns an int status and takes (char* err, size_t err_len)
// last. No C++ exception ever crosses the boundary: ks::guard catches everything and writes
// the message into err. The Rust side (crate kinscene-shim) turns a non-zero status into a
// typed error.
#pragma once

#include <cstddef>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>

#define KS_API extern "C" __attribute__((visibility("default")))

enum ks_status : int {
    KS_OK = 0,
    KS_EXCEPTION = 1,        // a C++ exception from the library (std::exception::what() in err)
    KS_INVALID_ARGUMENT = 2, // the shim rejected its input (message in err)
};

namespace ks {

// Thrown by shim code for bad input detected on the C++ side.
struct InvalidArgument : std::runtime_error {
    using std::runtime_error::runtime_error;
};

inline void set_error(char* err, std::size_t err_len, const char* msg) {
    if (err == nullptr || err_len == 0) return;
    std::strncpy(err, msg, err_len - 1);
    err[err_len - 1] = '\0';
}

// Runs f(), mapping every exception to a status code and message.
template <class F>
int guard(char* err, std::size_t err_len, F&& f) noexcept {
    try {
        f();
        return KS_OK;
    } catch (const InvalidArgument& e) {
        set_error(err, err_len, e.what());
        return KS_INVALID_ARGUMENT;
    } catch (const std::exception& e) {
        set_error(err, err_len, e.what());
        return KS_EXCEPTION;
    } catch (...) {
        set_error(err, err_len, "unknown C++ exception");
        return KS_EXCEPTION;
    }
}

}  // namespace ks
