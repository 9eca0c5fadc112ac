/// @file ScopedEnvironment.h
/// @brief An environment variable set (or unset) for one test, as it was again after
/// it, even when the test fails midway.
#pragma once

#include <cstdlib>
#include <optional>
#include <string>

namespace gvr::test {

class ScopedEnvironment {
public:
    /// Sets @a name to @a value, or unsets it when @a value is std::nullopt.
    ScopedEnvironment(std::string name, const std::optional<std::string>& value) : mName(std::move(name)) {
        if (const char* before = std::getenv(mName.c_str())) mBefore = before;
        assign(value);
    }
    ~ScopedEnvironment() { assign(mBefore); }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    void assign(const std::optional<std::string>& value) const {
        if (value) {
            ::setenv(mName.c_str(), value->c_str(), 1);
        } else {
            ::unsetenv(mName.c_str());
        }
    }

    std::string mName;
    std::optional<std::string> mBefore;
};

}  // namespace gvr::test
