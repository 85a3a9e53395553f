// hipfai — radial mapping names as users write them (scene `options.mapping`, `--mapping`),
// parsed once into contact::RadialMapping. The names are contact::to_string's, so there is one
// table of them.
#pragma once

#include "contact/radial_mapping.h"

#include <optional>
#include <string_view>

namespace hipfai::studies {

// The mapping named `name` ("spherical", "cartesian" or "cube"); nullopt for any other name.
inline std::optional<contact::RadialMapping> radial_mapping_from_name(std::string_view name) {
  for (const contact::RadialMapping mapping :
       {contact::RadialMapping::kSpherical, contact::RadialMapping::kCartesian, contact::RadialMapping::kCube}) {
    if (name == contact::to_string(mapping)) return mapping;
  }
  return std::nullopt;
}

}  // namespace hipfai::studies
