/// @file LabelTable.h
/// @brief Integer structure labels (an atlas or a segmentation) and their names,
/// and the user's choice of structures: "all", IDs, names, or a mix.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace gvr {

/// Label 0 is background and never a structure.
struct LabelTable {
    std::map<int, std::string> names;  ///< every structure present, id -> name

    /// The name, or "label_<id>" for an id the table does not name.
    std::string nameOf(int id) const;
    bool contains(int id) const { return names.count(id) > 0; }
};

/// The ids that @a spec chooses from @a table, ascending: "all", or a comma-separated
/// mix of ids and names (names match exactly, or ignoring case).
/// @throw InputError naming @a culprit for an unknown id or name, listing the valid ones.
std::vector<int> selectLabels(const LabelTable& table, const std::string& spec, const std::string& culprit);

/// The ids of @a table shown by --show @a show (empty: all) and --hide @a hide (empty: none).
std::vector<int> shownLabels(const LabelTable& table, const std::string& show, const std::string& hide);

}  // namespace gvr
