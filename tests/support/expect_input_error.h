// Helpers for tests that check what an InputError says.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "core/error.h"

namespace penumbra::testing {

// Runs `f`, which must throw InputError, and returns the error. When it throws nothing, the test
// fails and an empty error is returned.
inline InputError catchInputError(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e;
    }
    ADD_FAILURE() << "expected an InputError, but nothing was thrown";
    return InputError("(nothing was thrown)");
}

}  // namespace penumbra::testing

// Expects `part` to occur in `text` (both convertible to std::string).
#define EXPECT_CONTAINS(text, part)                            \
    EXPECT_NE(std::string(text).find(part), std::string::npos) \
        << "expected to find \"" << (part) << "\" in \"" << std::string(text) << "\""
