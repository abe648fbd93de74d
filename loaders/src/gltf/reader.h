// What the parts of the glTF reader share (gltf.cpp runs them, in the order of
// scene_graph.h): the file's name, which starts every message, tinygltf's model, the
// options and the scene being filled, and how a part fails or warns. Private to the glTF
// reader (docs/design.md, "glTF").
#pragma once

#include <cstddef>
#include <string>

#include "gltf/tinygltf.h"
#include "softpbr/loaders/gltf.h"

namespace softpbr::pbr::gltf {

namespace tg = tinygltf;

// Most elements one accessor may hold: 2^28 (a VEC4 float accessor of 4 GiB).
inline constexpr std::size_t kMaxElements = std::size_t{1} << 28;

inline std::string str(std::size_t i) { return std::to_string(i); }

// Each part (Resources, Materials, SceneGraph) is a Context: it refers to these, which
// outlive it.
class Context {
 public:
  Context(const std::string& file, const tg::Model& model, const GltfOptions& options, GltfScene& out)
      : file_(file), m_(model), options_(options), out_(out) {}

  // Throws LoadError: "file: /json/pointer: what".
  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const {
    throw LoadError(file_ + ": " + pointer + ": " + what);
  }
  void warn(const std::string& what) const { out_.warnings.push_back(file_ + ": " + what); }

 protected:
  const std::string& file_;
  const tg::Model& m_;
  const GltfOptions& options_;
  GltfScene& out_;
};

}  // namespace softpbr::pbr::gltf
