// KHR_materials_variants: a model's named material variants (a shoe's colourways), each
// primitive mapping some of them to another material than its own. Private to the glTF
// reader (docs/design.md, "glTF").
#pragma once

#include <string>
#include <vector>

#include "gltf/reader.h"

namespace softpbr::pbr::gltf {

// The names of the file's variants, in their order (empty when it has none). The schema
// check (schema.cpp) has made each an object with a string name, and every mapping's
// variants and material indices in range.
std::vector<std::string> variant_names(const tg::Model& model);

// Every primitive whose mappings list `variant` takes that mapping's material (the first
// such mapping); the others keep their own, as the specification's default. `variant` is a
// variant's name or, when no variant has that name, its index ("1"). Throws LoadError
// "file: /extensions/KHR_materials_variants/variants: no variant "x" (the variants: 0
// "midnight", 1 "beach", 2 "street")", or that the model has none. Run on the model
// tinygltf built, before the scene graph reads a primitive's material.
void select_variant(tg::Model& model, const std::string& variant, const std::string& file);

}  // namespace softpbr::pbr::gltf
