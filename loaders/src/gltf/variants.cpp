// KHR_materials_variants (see variants.h).
#include "gltf/variants.h"

#include <algorithm>

#include "softpbr/loaders/load_error.h"

namespace softpbr::pbr::gltf {

namespace {
constexpr const char* kVariants = "KHR_materials_variants";

// A name as a message quotes it: at most 40 bytes, control characters as '?'.
std::string quoted(const std::string& name) {
  std::string s = name.size() > 40 ? name.substr(0, 40) + "…" : name;
  std::replace_if(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }, '?');
  return "\"" + s + "\"";
}
}  // namespace

std::vector<std::string> variant_names(const tg::Model& model) {
  std::vector<std::string> names;
  const auto it = model.extensions.find(kVariants);
  if (it == model.extensions.end() || !it->second.IsObject() || !it->second.Has("variants")) return names;
  const tg::Value& list = it->second.Get("variants");
  if (!list.IsArray()) return names;
  for (std::size_t i = 0; i < list.ArrayLen(); ++i) {
    const tg::Value& v = list.Get(static_cast<int>(i));
    names.push_back(v.IsObject() && v.Has("name") && v.Get("name").IsString() ? v.Get("name").Get<std::string>() : "");
  }
  return names;
}

void select_variant(tg::Model& model, const std::string& variant, const std::string& file) {
  const std::vector<std::string> names = variant_names(model);
  int chosen = -1;
  for (std::size_t i = 0; i < names.size() && chosen < 0; ++i)
    if (names[i] == variant) chosen = static_cast<int>(i);
  if (chosen < 0 && !variant.empty() && variant.size() <= 9 &&
      std::all_of(variant.begin(), variant.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
      std::stoul(variant) < names.size())
    chosen = static_cast<int>(std::stoul(variant));
  if (chosen < 0) {
    if (names.empty())
      throw LoadError(file + ": the model has no material variants (no " + std::string(kVariants) + "), so no variant " +
                      quoted(variant));
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i) list += (i == 0 ? "" : ", ") + std::to_string(i) + " " + quoted(names[i]);
    throw LoadError(file + ": /extensions/" + kVariants + "/variants: no variant " + quoted(variant) + " (the variants: " +
                    list + ")");
  }
  for (tg::Mesh& mesh : model.meshes)
    for (tg::Primitive& p : mesh.primitives) {
      const auto it = p.extensions.find(kVariants);
      if (it == p.extensions.end() || !it->second.IsObject() || !it->second.Has("mappings")) continue;
      const tg::Value& mappings = it->second.Get("mappings");
      bool mapped = false;
      for (std::size_t i = 0; i < mappings.ArrayLen() && !mapped; ++i) {
        const tg::Value& m = mappings.Get(static_cast<int>(i));
        const tg::Value& used = m.Get("variants");
        for (std::size_t j = 0; j < used.ArrayLen() && !mapped; ++j)
          if (used.Get(static_cast<int>(j)).IsNumber() && used.Get(static_cast<int>(j)).GetNumberAsInt() == chosen) {
            p.material = m.Get("material").GetNumberAsInt();
            mapped = true;
          }
      }
    }
}

}  // namespace softpbr::pbr::gltf
