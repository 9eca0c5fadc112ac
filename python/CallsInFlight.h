/// @file CallsInFlight.h
/// @brief The module's work without the GIL, counted, so that interpreter exit stops it first.
///
/// At exit, Python ends a daemon thread that asks for the GIL back with
/// pthread_exit, and its forced unwind through gil_scoped_release's destructor
/// (noexcept) calls std::terminate: a fit, export, evaluate or render in a daemon
/// thread aborted the interpreter (signal 6) when the program ended or a Ctrl-C
/// ended it. An atexit handler runs after the non-daemon threads are joined and
/// before daemon threads are cut off: it asks the calls to stop (a fit stops at
/// its next iteration; other calls finish), waits until each has the GIL back,
/// and from then on refuses new ones.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <stdexcept>

namespace gvr {

/// Raised in a call that the interpreter's exit stopped, or that started after it:
/// SystemExit in Python, on which a thread ends without a traceback.
class InterpreterExiting : public std::runtime_error {
public:
    InterpreterExiting() : std::runtime_error("gvr: stopped, since the Python interpreter is exiting") {}
};

class CallsInFlight {
public:
    static CallsInFlight& instance() {
        static CallsInFlight calls;
        return calls;
    }

    /// Whether exit has asked the calls to stop: long work checks it as it goes.
    bool stopping() const { return mStopping.load(); }

    /// @throw InterpreterExiting once exit has begun.
    void enter() {
        std::lock_guard<std::mutex> lock(mMutex);
        if (mStopping) throw InterpreterExiting();
        ++mActive;
    }

    void leave() {
        std::lock_guard<std::mutex> lock(mMutex);
        if (--mActive == 0) mIdle.notify_all();
    }

    /// For atexit, holding the GIL: releases it until no call is left in C++.
    void stopAndWait() {
        mStopping = true;
        pybind11::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(mMutex);
        mIdle.wait(lock, [this] { return mActive == 0; });
    }

private:
    std::atomic<bool> mStopping{false};
    std::mutex mMutex;
    std::condition_variable mIdle;
    std::size_t mActive = 0;
};

/// The GIL released for the module's C++ work, for as long as the object lives.
/// The call counts as in flight until the GIL is back, so that exit, which waits
/// for none to be in flight, never sees a thread still asking for it.
class WithoutGil {
public:
    WithoutGil() = default;
    WithoutGil(const WithoutGil&) = delete;
    WithoutGil& operator=(const WithoutGil&) = delete;

private:
    struct InFlight {
        InFlight() { CallsInFlight::instance().enter(); }
        ~InFlight() { CallsInFlight::instance().leave(); }
    };
    InFlight mInFlight;  // made first, so left last: after the GIL is back
    pybind11::gil_scoped_release mRelease;
};

}  // namespace gvr
