#include "cli/Diagnostics.h"

#include "pipeline/SettingNames.h"

#include <unistd.h>

#include <algorithm>
#include <string>

namespace gvr {

namespace {

/// An ostream buffer over a C stream, so that gvr's C++ and C output share one
/// unbuffered descriptor and stay in order.
class FileBuffer : public std::streambuf {
public:
    void attach(std::FILE* file) { mFile = file; }

protected:
    int overflow(int c) override { return c == EOF ? 0 : std::fputc(c, mFile); }
    std::streamsize xsputn(const char* text, std::streamsize n) override {
        return std::streamsize(std::fwrite(text, 1, std::size_t(n), mFile));
    }
    int sync() override { return std::fflush(mFile); }

private:
    std::FILE* mFile = stderr;
};

FileBuffer gBuffer;
std::ostream gStream(&gBuffer);
std::FILE* gFile = stderr;
std::FILE* gCaptured = nullptr;  // where descriptor 2 points after the diversion

}  // namespace

void divertLibraryOutput() {
    if (gCaptured) return;
    std::FILE* scratch = std::tmpfile();
    if (!scratch) return;  // no scratch space: library lines stay on stderr
    const int saved = dup(STDERR_FILENO);
    std::FILE* own = saved < 0 ? nullptr : fdopen(saved, "w");
    if (!own || dup2(fileno(scratch), STDERR_FILENO) < 0) {
        if (own) std::fclose(own);
        std::fclose(scratch);
        return;
    }
    std::setvbuf(own, nullptr, _IONBF, 0);
    gFile = own;
    gBuffer.attach(own);
    gCaptured = scratch;
}

std::ostream& diagnostics() { return gStream; }

std::FILE* diagnosticsFile() { return gFile; }

int diagnosticsFd() { return fileno(gFile); }

std::string inCommandLineTerms(const std::string& message) {
    return respellSettings(message, [](std::string key, const std::string& value) {
        std::replace(key.begin(), key.end(), '_', '-');
        return "--" + key + (value.empty() ? "" : " " + value);
    });
}

void showLibraryOutput() {
    if (!gCaptured) return;
    std::fflush(stderr);
    std::rewind(gCaptured);
    std::string line;
    for (int c = std::fgetc(gCaptured); c != EOF; c = std::fgetc(gCaptured)) {
        if (c != '\n') {
            line += char(c);
            continue;
        }
        if (!line.empty()) diagnostics() << "gvr: library: " << line << "\n";
        line.clear();
    }
    if (!line.empty()) diagnostics() << "gvr: library: " << line << "\n";
}

}  // namespace gvr
