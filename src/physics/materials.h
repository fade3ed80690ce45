// Fabric presets for struct Material: cotton, linen and silk, the three fabrics of the
// paper's figures 7-9. Every value, its source and whether it is measured, derived or
// estimated is tabled in docs/materials.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "physics/model.h"

namespace tissu {

// The preset named `name` ("cotton", "linen", "silk"; exact, lower case), every field of
// Material filled in SI units; std::nullopt for any other name.
std::optional<Material> material_preset(const std::string& name);

// The preset names, in the paper's order: cotton, linen, silk.
std::vector<std::string> material_preset_names();

}  // namespace tissu
