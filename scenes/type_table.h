// A scene concept's types as a table, one row per type: the `type` name a scene file uses, the
// keys that type accepts, and the reader that builds its runtime value. The table is the only
// list of a concept's types in the loader: the names in messages, the key check (an unknown key
// is an error naming the accepted ones) and the dispatch all come from it.
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "scenes/json_reader.h"

namespace penumbra {

template <typename Reader>
struct TypeRow {
    std::string_view name;
    std::vector<std::string_view> keys;  // every key the type accepts, "type" included
    Reader read;
};

// The row that `value`'s "type" names, once `value` is known to hold only that row's keys.
template <typename Reader>
const TypeRow<Reader>& findTypeRow(const JsonValue& value, std::span<const TypeRow<Reader>> table) {
    std::vector<std::string_view> names;
    for (const TypeRow<Reader>& row : table) names.push_back(row.name);
    const TypeRow<Reader>& row = table[value.requiredMember("type").choice(names)];
    const JsonObject checked(value, row.keys);
    return row;
}

}  // namespace penumbra
