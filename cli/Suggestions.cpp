#include "cli/Suggestions.h"

#include <algorithm>
#include <cctype>
#include <numeric>

namespace gvr {

namespace {

std::size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    std::iota(row.begin(), row.end(), 0);
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::vector<std::string> commandNames(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
        names.push_back(command->get_name());
    }
    return names;
}

/// Every "-x" and "--name" that @a command (and, for flags such as --verbose, @a app) takes.
std::vector<std::string> flagNames(const CLI::App& app, const CLI::App& command) {
    std::vector<std::string> names;
    for (const CLI::App* owner : {&command, &app}) {
        for (const CLI::Option* option : owner->get_options()) {
            for (const std::string& name : option->get_snames()) names.push_back("-" + name);
            for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
        }
    }
    return names;
}

/// "--time=5" and "--time" both name "--time".
std::string flagOf(const std::string& argument) { return argument.substr(0, argument.find('=')); }

bool looksLikeAFlag(const std::string& argument) {
    return argument.size() > 1 && argument[0] == '-' && !std::isdigit(static_cast<unsigned char>(argument[1])) &&
           argument[1] != '.';
}

}  // namespace

std::string closestName(const std::string& typed, const std::vector<std::string>& names) {
    std::string best;
    std::size_t bestDistance = std::max<std::size_t>(2, typed.size() / 3) + 1;
    for (const std::string& name : names) {
        const std::size_t distance = editDistance(typed, name);
        if (distance < bestDistance) {
            best = name;
            bestDistance = distance;
        }
    }
    if (!best.empty()) return best;
    std::vector<std::string> starting;
    for (const std::string& name : names) {
        if (typed.size() >= 3 && name.compare(0, typed.size(), typed) == 0) starting.push_back(name);
    }
    return starting.size() == 1 ? starting.front() : "";
}

std::string unknownCommandMessage(const CLI::App& app, int argc, const char* const* argv) {
    for (int n = 1; n < argc; ++n) {
        const std::string argument = argv[n];
        if (looksLikeAFlag(argument)) continue;
        const std::vector<std::string> names = commandNames(app);
        if (std::find(names.begin(), names.end(), argument) != names.end()) return "";
        const std::string near = closestName(argument, names);
        return "unknown command '" + argument + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?") +
               " (gvr help lists the commands)";
    }
    return "";
}

std::string unknownFlagMessage(const CLI::App& app, int argc, const char* const* argv) {
    const std::vector<CLI::App*> parsed = app.get_subcommands();
    if (parsed.empty()) return "";
    const CLI::App& command = *parsed.front();
    const std::vector<std::string> names = flagNames(app, command);
    for (int n = 1; n < argc; ++n) {
        const std::string argument = argv[n];
        if (!looksLikeAFlag(argument) || argument == "--") continue;
        const std::string flag = flagOf(argument);
        if (std::find(names.begin(), names.end(), flag) != names.end()) continue;
        if (flag.size() > 2 && flag[1] != '-') continue;  // bundled short flags such as -qj
        const std::string near = closestName(flag, names);
        return command.get_name() + ": unknown option " + flag + (near.empty() ? "" : "; did you mean " + near + "?") +
               " (gvr help " + command.get_name() + " lists the options)";
    }
    return "";
}

}  // namespace gvr
