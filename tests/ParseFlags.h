#pragma once
// Shared by the tests of the command-line flag groups (cli/*Flags, cli/*Options).

#include <CLI/CLI.hpp>

#include <vector>

namespace gvr::test {

/// Parses @a args as if typed after "gvr"; throws what CLI11 throws.
inline void parseFlags(CLI::App& app, std::vector<const char*> args) {
    args.insert(args.begin(), "gvr");
    app.parse(int(args.size()), args.data());
}

}  // namespace gvr::test
