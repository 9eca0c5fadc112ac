#include "pipeline/LabelTable.h"

#include "pipeline/Error.h"
#include "pipeline/LowerCase.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

namespace gvr {

namespace {

std::string trimmed(const std::string& text) {
    const auto first = text.find_first_not_of(" \t");
    if (first == std::string::npos) return "";
    return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

/// "17 Hippocampus_L, 53 Thalamus_L, ..." for error messages; long tables are cut.
std::string validLabels(const LabelTable& table) {
    std::string list;
    std::size_t shown = 0;
    for (const auto& [id, name] : table.names) {
        if (shown++ == 40) return list + ", ... (" + std::to_string(table.names.size()) + " in all)";
        list += (list.empty() ? "" : ", ") + std::to_string(id) + " " + name;
    }
    return list.empty() ? "none: the volume has no labels" : list;
}

int findLabel(const LabelTable& table, const std::string& item, const std::string& culprit) {
    char* end = nullptr;
    const long id = std::strtol(item.c_str(), &end, 10);
    if (!item.empty() && *end == '\0') {
        if (table.contains(int(id))) return int(id);
        throw InputError(culprit, "no structure has label " + item + "; valid: " + validLabels(table));
    }
    for (const auto& [candidate, name] : table.names) {
        if (name == item) return candidate;
    }
    for (const auto& [candidate, name] : table.names) {
        if (lowerCase(name) == lowerCase(item)) return candidate;
    }
    throw InputError(culprit, "no structure is named '" + item + "'; valid: " + validLabels(table));
}

}  // namespace

std::string LabelTable::nameOf(int id) const {
    const auto it = names.find(id);
    return it == names.end() ? "label_" + std::to_string(id) : it->second;
}

std::vector<int> selectLabels(const LabelTable& table, const std::string& spec, const std::string& culprit) {
    if (trimmed(spec) == "all") {
        std::vector<int> all;
        for (const auto& [id, name] : table.names) all.push_back(id);
        return all;
    }
    std::set<int> chosen;
    std::istringstream in(spec);
    for (std::string item; std::getline(in, item, ',');) {
        item = trimmed(item);
        if (!item.empty()) chosen.insert(findLabel(table, item, culprit));
    }
    if (chosen.empty()) throw InputError(culprit, "names no structure; valid: all, or " + validLabels(table));
    return {chosen.begin(), chosen.end()};
}

std::vector<int> shownLabels(const LabelTable& table, const std::string& show, const std::string& hide) {
    const std::vector<int> shown = selectLabels(table, show.empty() ? "all" : show, "`show`");
    if (hide.empty()) return shown;
    const std::vector<int> hidden = selectLabels(table, hide, "`hide`");
    std::vector<int> result;
    std::set_difference(shown.begin(), shown.end(), hidden.begin(), hidden.end(), std::back_inserter(result));
    return result;
}

}  // namespace gvr
