#pragma once
// The scene schema: every key a scene file may hold, with type, unit, default and
// allowed range. The loader validates against it and docs/scenes.md is generated
// from it (`dvisph schema`), so the two cannot drift.
#include <string>
#include <vector>

namespace dvisph {

enum class FieldType { number, integer, boolean, choice, vector, map, list };

struct Field {
  std::string name;
  FieldType type;
  std::string unit;  // "" for dimensionless
  std::string help;
  bool required = false;
  std::string default_value;  // YAML text; "" = no default (required or optional block)
  double min = -1e300, max = 1e300;
  bool min_exclusive = false;
  std::vector<std::string> choices;  // for FieldType::choice
  std::vector<Field> children;       // for map, and the items of list
};

// The root map of a scene file.
const Field& scene_schema();

// Markdown reference of every key (docs/scenes.md).
std::string schema_markdown();

}  // namespace dvisph
