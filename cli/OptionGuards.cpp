#include "cli/OptionGuards.h"

#include <string>

namespace gvr {

namespace {

bool isUnsigned(const CLI::Option& option) { return option.get_type_name().rfind("UINT", 0) == 0; }

const CLI::Validator kNotNegative(
    [](std::string& value) -> std::string {
        const std::size_t first = value.find_first_not_of(" \t");
        if (first != std::string::npos && value[first] == '-') return "must not be negative, got " + value;
        return "";
    },
    "", "not negative");

}  // namespace

void refuseNegativeUnsignedValues(CLI::App& app) {
    for (CLI::Option* option : app.get_options()) {
        if (isUnsigned(*option)) option->check(kNotNegative);
    }
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
        refuseNegativeUnsignedValues(*command);
}

void useOneLineUsageErrors(CLI::App& app) {
    app.failure_message(
        [](const CLI::App*, const CLI::Error& error) { return "gvr: error: " + std::string(error.what()) + "\n"; });
}

}  // namespace gvr
