// The glTF reader's scene graph (see scene_graph.h): extensions, the scene, nodes,
// cameras and lights, and the mesh primitives the nodes place.
#include "gltf/scene_graph.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "gltf/draco.h"
#include "gltf/meshopt.h"
#include "json_reader.h"
#include "softpbr/loaders/format_bytes.h"

namespace softpbr::pbr::gltf {

namespace {

// Deepest node hierarchy followed.
constexpr int kMaxDepth = 1024;

std::string number_text(double x) { return json_reader::show_number(x); }

}  // namespace

void SceneGraph::load() {
  check_extensions();
  // EXT_meshopt_compression: every compressed view decoded before any accessor is read.
  resources_.decode_compressed_views();
  const int scene = pick_scene();
  std::vector<int> roots;
  if (scene >= 0) {
    roots = m_.scenes[static_cast<std::size_t>(scene)].nodes;
  } else {
    // No scenes: every node that is nobody's child.
    std::vector<bool> child(m_.nodes.size(), false);
    for (const tg::Node& n : m_.nodes)
      for (int c : n.children)
        if (c >= 0 && static_cast<std::size_t>(c) < child.size()) child[static_cast<std::size_t>(c)] = true;
    for (std::size_t i = 0; i < m_.nodes.size(); ++i)
      if (!child[i]) roots.push_back(static_cast<int>(i));
  }
  const std::string where = scene >= 0 ? "/scenes/" + str(static_cast<std::size_t>(scene)) + "/nodes" : "/nodes";
  check_draw_memory(roots, where);
  roots_ = std::move(roots);
  where_ = where;
  // The animations (animation.h): listed, and sampled at the chosen moment into a pose.
  for (const AnimationSummary& a : animations_.summaries()) out_.animations.push_back({a.name, a.duration, a.channels});
  place();
  // The textures (every image decoded once, in parallel), then the objects, now that their
  // materials are complete.
  materials_.make_textures(resources_);
  // A material that transmits light (KHR_materials_transmission, factor > 0: a lamp's paper
  // shade, glass), which softpbr draws opaque, casts no shadow: the light passes through it
  // (docs/design.md, "Shadows").
  const auto transmits = [&](int index) {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.materials.size()) return false;
    const tg::ExtensionMap& e = m_.materials[static_cast<std::size_t>(index)].extensions;
    const auto it = e.find("KHR_materials_transmission");
    if (it == e.end() || !it->second.IsObject() || !it->second.Has("transmissionFactor")) return false;
    const tg::Value& f = it->second.Get("transmissionFactor");
    return f.IsNumber() && f.GetNumberAsDouble() > 0.0;
  };
  for (const Placed& o : placed_)
    out_.objects.push_back({o.mesh, materials_.at(o.material), o.transform, !transmits(o.material)});
}

void SceneGraph::pose() {
  out_.objects.clear();
  out_.cameras.clear();
  out_.lights.clear();
  place();
  for (const Placed& o : placed_) out_.objects.push_back({o.mesh, materials_.at(o.material), o.transform});
}

void SceneGraph::place() {
  pose_ = animations_.pose();
  world_.assign(m_.nodes.size(), glm::dmat4(1.0));
  visited_.assign(m_.nodes.size(), false);
  placed_.clear();
  std::vector<bool> on_path(m_.nodes.size(), false);
  for (std::size_t i = 0; i < roots_.size(); ++i)
    visit(roots_[i], glm::dmat4(1.0), where_ + "/" + str(i), 0, on_path);
  // Skins and morph targets, now that every joint's world transform is known.
  deform_meshes();
}

void SceneGraph::check_extensions() const {
  const std::vector<std::string>& rendered = gltf_extensions_rendered();
  const auto supported = [&](const std::string& e) { return std::binary_search(rendered.begin(), rendered.end(), e); };
  for (std::size_t i = 0; i < m_.extensionsRequired.size(); ++i)
    if (!supported(m_.extensionsRequired[i]))
      fail("/extensionsRequired/" + str(i), "the required extension " + m_.extensionsRequired[i] + " is not supported");
  for (const std::string& e : m_.extensionsUsed)
    if (!supported(e)) warn("the extension " + e + " is not supported and is ignored");
}

int SceneGraph::pick_scene() const {
  if (!options_.scene_name.empty()) {
    const std::string& n = options_.scene_name;
    for (std::size_t i = 0; i < m_.scenes.size(); ++i)
      if (m_.scenes[i].name == n) return static_cast<int>(i);
    const bool digits = n.size() <= 9 && std::all_of(n.begin(), n.end(), [](unsigned char c) { return c >= '0' && c <= '9'; });
    if (digits && std::stoul(n) < m_.scenes.size()) return static_cast<int>(std::stoul(n));
    std::string listed;
    for (std::size_t i = 0; i < m_.scenes.size() && i < 32; ++i)
      listed += (i ? ", " : "") + str(i) + (m_.scenes[i].name.empty() ? "" : " \"" + m_.scenes[i].name + "\"");
    if (m_.scenes.size() > 32) listed += ", …";
    fail("/scenes", "no scene " + (digits ? n : "\"" + n + "\"") + " (the scenes: " + (listed.empty() ? "none" : listed) + ")");
  }
  if (m_.scenes.empty()) {
    if (options_.scene >= 0) fail("/scenes", "the file has no scene " + std::to_string(options_.scene));
    return -1;
  }
  int s = options_.scene >= 0 ? options_.scene : (m_.defaultScene >= 0 ? m_.defaultScene : 0);
  if (static_cast<std::size_t>(s) >= m_.scenes.size())
    fail(options_.scene >= 0 ? "/scenes" : "/scene", "scene " + std::to_string(s) + " does not exist (" +
                                                          str(m_.scenes.size()) + " scenes)");
  return s;
}

// The work of the scene counted before any of it is done: every mesh the scene's nodes
// place, times its triangles (from the accessors' counts), as the draws' memory, against the
// memory limit. 20 000 nodes placing a 130 000-triangle mesh were built, bounded and
// counted first (8.6 s, 35 s for `info`) before the render's estimate refused them.
void SceneGraph::check_draw_memory(const std::vector<int>& roots, const std::string& where) const {
  std::vector<std::uint64_t> instances(m_.meshes.size(), 0);
  std::vector<bool> seen(m_.nodes.size(), false);  // each node once (one parent each: schema.cpp)
  std::vector<int> stack(roots.rbegin(), roots.rend());
  std::uint64_t placed = 0;
  // A skinned or morphed instance owns a deformed copy of its vertices, and reads its
  // targets' deltas (deform.h): counted as if every target were read.
  double deformed = 0.0;
  auto count = [&](int a) -> double {
    return a >= 0 && static_cast<std::size_t>(a) < m_.accessors.size()
               ? static_cast<double>(m_.accessors[static_cast<std::size_t>(a)].count)
               : 0.0;
  };
  auto deform_bytes = [&](int mesh, bool skinned) {
    double bytes = 0.0;
    for (const tg::Primitive& p : m_.meshes[static_cast<std::size_t>(mesh)].primitives) {
      if (!skinned && p.targets.empty()) continue;
      const auto position = p.attributes.find("POSITION");
      const double vertices = position != p.attributes.end() ? count(position->second) : 0.0;
      bytes += vertices * (sizeof(MeshVertex) + sizeof(glm::vec4) + (skinned ? 8.0 * 12.0 : 0.0));
      for (const auto& target : p.targets)
        for (const auto& [name, a] : target) bytes += count(a) * 12.0;
    }
    return bytes;
  };
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (n < 0 || static_cast<std::size_t>(n) >= m_.nodes.size() || seen[static_cast<std::size_t>(n)]) continue;
    seen[static_cast<std::size_t>(n)] = true;
    const tg::Node& node = m_.nodes[static_cast<std::size_t>(n)];
    if (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) < m_.meshes.size()) {
      // EXT_mesh_gpu_instancing: one draw a instance (from its accessors' counts), each
      // with its matrix and Object (256 bytes counted, however small the mesh).
      const std::uint64_t copies = node.skin >= 0 ? 1 : instance_count(static_cast<std::size_t>(n));
      instances[static_cast<std::size_t>(node.mesh)] += copies;
      placed += copies;
      deformed += static_cast<double>(copies) * (deform_bytes(node.mesh, node.skin >= 0) + 256.0);
    }
    stack.insert(stack.end(), node.children.rbegin(), node.children.rend());
  }
  double bytes = deformed;  // (a sum of products: double, which cannot overflow here)
  for (std::size_t m = 0; m < instances.size(); ++m)
    if (instances[m] > 0)
      bytes += static_cast<double>(instances[m]) * static_cast<double>(meshes_.draw_bytes_lower_bound(static_cast<int>(m)));
  if (bytes > static_cast<double>(options_.memory_limit))
    fail(where, "its nodes place " + std::to_string(placed) + " mesh instances, whose draws need an estimated " +
                    format_bytes(static_cast<std::uint64_t>(std::min(bytes, 1.8e19))) + ", over the memory limit of " +
                    format_bytes(options_.memory_limit) + " (counted before any mesh is built)");
}

// ---- Nodes ---------------------------------------------------------------------------

const tg::Value* SceneGraph::instancing(std::size_t node) const {
  const tg::Node& n = m_.nodes[node];
  const auto it = n.extensions.find(kInstancing);
  if (it == n.extensions.end()) return nullptr;
  const std::string ip = "/nodes/" + str(node) + "/extensions/" + kInstancing;
  if (!it->second.IsObject() || !it->second.Has("attributes") || !it->second.Get("attributes").IsObject())
    fail(ip + "/attributes", "must be an object naming TRANSLATION, ROTATION or SCALE accessors");
  return &it->second.Get("attributes");
}

std::uint64_t SceneGraph::instance_count(std::size_t node) const {
  const tg::Value* attributes = instancing(node);
  if (attributes == nullptr) return 1;
  std::uint64_t count = 0;
  for (const char* name : {"TRANSLATION", "ROTATION", "SCALE"}) {
    if (!attributes->Has(name) || !attributes->Get(name).IsInt()) continue;
    const int a = attributes->Get(name).GetNumberAsInt();
    if (a >= 0 && static_cast<std::size_t>(a) < m_.accessors.size())
      count = std::max<std::uint64_t>(count, m_.accessors[static_cast<std::size_t>(a)].count);
  }
  return std::max<std::uint64_t>(count, 1);
}

// EXT_mesh_gpu_instancing: world × T·R·S of each instance (the extension's order), from
// its TRANSLATION, ROTATION (unit quaternions, float or normalised integers) and SCALE
// accessors, all of one count and finite; none of the three: the node alone.
std::vector<glm::dmat4> SceneGraph::instance_worlds(std::size_t node, const glm::dmat4& world) const {
  const tg::Value* attributes = instancing(node);
  if (attributes == nullptr) return {world};
  const std::string ap = "/nodes/" + str(node) + "/extensions/" + kInstancing + "/attributes/";
  std::size_t count = 0;
  bool any = false;
  auto read = [&](const char* name, int comps) -> std::vector<float> {
    if (!attributes->Has(name)) return {};
    const tg::Value& a = attributes->Get(name);
    if (!a.IsInt()) fail(ap + name, "must be an accessor index");
    const int index = a.GetNumberAsInt();
    std::vector<float> v = resources_.read_floats(index, ap + name, {comps});
    for (float x : v)
      if (!std::isfinite(x)) fail("/accessors/" + std::to_string(index), "holds a value that is not finite");
    const std::size_t c = v.size() / static_cast<std::size_t>(comps);
    if (any && c != count)
      fail(ap + name, "has " + str(c) + " instances; the other attributes have " + str(count));
    count = c;
    any = true;
    return v;
  };
  const std::vector<float> t = read("TRANSLATION", 3), r = read("ROTATION", 4), s = read("SCALE", 3);
  if (!any) fail(ap.substr(0, ap.size() - 1), "names none of TRANSLATION, ROTATION and SCALE");
  std::vector<glm::dmat4> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    glm::dmat4 T(1.0), R(1.0), S(1.0);
    if (!t.empty()) T[3] = glm::dvec4(t[3 * i], t[3 * i + 1], t[3 * i + 2], 1.0);
    if (!r.empty()) R = glm::mat4_cast(glm::dquat(r[4 * i + 3], r[4 * i], r[4 * i + 1], r[4 * i + 2]));  // (x, y, z, w)
    if (!s.empty()) {
      S[0][0] = s[3 * i];
      S[1][1] = s[3 * i + 1];
      S[2][2] = s[3 * i + 2];
    }
    out.push_back(world * (T * R * S));
  }
  return out;
}

glm::dmat4 SceneGraph::local_matrix(std::size_t index, const std::string& pointer) const {
  const tg::Node& n = m_.nodes[index];
  const NodePose* posed = index < pose_.size() ? &pose_[index] : nullptr;
  auto finite = [&](const std::vector<double>& v, const char* what) {
    for (double x : v)
      if (!std::isfinite(x)) fail(pointer + "/" + what, "is not finite");
  };
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16) fail(pointer + "/matrix", "must have 16 numbers");
    finite(n.matrix, "matrix");
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[static_cast<std::size_t>(c * 4 + r)];  // column-major
    return m;
  }
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  // An animated part replaces the node's own (animation.h).
  if (posed != nullptr && posed->translation) t[3] = glm::dvec4(*posed->translation, 1.0);
  else if (!n.translation.empty()) {
    if (n.translation.size() != 3) fail(pointer + "/translation", "must have 3 numbers");
    finite(n.translation, "translation");
    t[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
  }
  if (posed != nullptr && posed->rotation) r = glm::mat4_cast(*posed->rotation);
  else if (!n.rotation.empty()) {
    if (n.rotation.size() != 4) fail(pointer + "/rotation", "must have 4 numbers");
    finite(n.rotation, "rotation");
    // glTF stores (x, y, z, w); glm's constructor takes w first.
    const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    r = glm::mat4_cast(q);
  }
  if (posed != nullptr && posed->scale) {
    s[0][0] = posed->scale->x;
    s[1][1] = posed->scale->y;
    s[2][2] = posed->scale->z;
  } else if (!n.scale.empty()) {
    if (n.scale.size() != 3) fail(pointer + "/scale", "must have 3 numbers");
    finite(n.scale, "scale");
    s[0][0] = n.scale[0];
    s[1][1] = n.scale[1];
    s[2][2] = n.scale[2];
  }
  return t * r * s;
}

void SceneGraph::visit(int index, const glm::dmat4& parent, const std::string& referrer, int depth, std::vector<bool>& on_path) {
  if (index < 0 || static_cast<std::size_t>(index) >= m_.nodes.size())
    fail(referrer, "node " + std::to_string(index) + " does not exist");
  const auto i = static_cast<std::size_t>(index);
  const std::string pointer = "/nodes/" + str(i);
  if (on_path[i]) fail(pointer, "is its own ancestor (the node hierarchy has a cycle)");
  if (depth > kMaxDepth) fail(pointer, "the node hierarchy is deeper than " + std::to_string(kMaxDepth));
  on_path[i] = true;
  const tg::Node& n = m_.nodes[i];
  const glm::dmat4 world = parent * local_matrix(i, pointer);
  world_[i] = world;
  visited_[i] = true;
  if (n.mesh >= 0) add_mesh(n.mesh, world, pointer + "/mesh", i);
  if (n.camera >= 0) add_camera(n.camera, world, pointer + "/camera");
  if (auto it = n.extensions.find("KHR_lights_punctual"); it != n.extensions.end() && it->second.Has("light"))
    add_light(it->second.Get("light").GetNumberAsInt(), world, pointer + "/extensions/KHR_lights_punctual/light");
  for (std::size_t c = 0; c < n.children.size(); ++c)
    visit(n.children[c], world, pointer + "/children/" + str(c), depth + 1, on_path);
  on_path[i] = false;
}

void SceneGraph::add_mesh(int index, const glm::dmat4& world, const std::string& referrer, std::size_t node) {
  if (index < 0 || static_cast<std::size_t>(index) >= m_.meshes.size())
    fail(referrer, "mesh " + std::to_string(index) + " does not exist");
  const tg::Mesh& mesh = m_.meshes[static_cast<std::size_t>(index)];
  const std::string pointer = "/meshes/" + std::to_string(index);
  // A skinned node's own transform is ignored (§3.7.3.1): its joints place the vertices
  // in world space. Morph weights other than 0, or a skin: the primitive is deformed
  // (deform_meshes).
  // A skinned node whose mesh has no JOINTS_0 (which §3.7.3 requires) is drawn without its
  // skin, with a warning.
  const bool jointed = !mesh.primitives.empty() && mesh.primitives.front().attributes.count("JOINTS_0") > 0;
  if (m_.nodes[node].skin >= 0 && !jointed)
    warn("/nodes/" + str(node) + "/skin: its mesh has no JOINTS_0 and WEIGHTS_0: drawn without the skin");
  const bool skinned = m_.nodes[node].skin >= 0 && jointed;
  const NodePose* posed = node < pose_.size() ? &pose_[node] : nullptr;
  std::vector<double> weights =
      rigging_.weights(static_cast<int>(node), index, posed != nullptr && posed->weights ? &*posed->weights : nullptr);
  const bool morphed = std::any_of(weights.begin(), weights.end(), [](double w) { return w != 0.0; });
  // EXT_mesh_gpu_instancing: the primitives once per instance. A skinned mesh is placed by
  // its joints alone (§3.7.3.1), so a skinned node's instances are not drawn.
  if (skinned && instancing(node) != nullptr)
    warn("/nodes/" + str(node) + "/extensions/" + kInstancing + ": a skinned node's instances are not drawn (only its skin)");
  const std::vector<glm::dmat4> worlds = skinned ? std::vector<glm::dmat4>{world} : instance_worlds(node, world);
  for (std::size_t instance = 0; instance < worlds.size(); ++instance) {
    const glm::mat4 transform = skinned ? glm::mat4(1.0f) : glm::mat4(worlds[instance]);
    const bool mirrored = !skinned && glm::determinant(glm::dmat3(worlds[instance])) < 0.0;
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
      const tg::Primitive& p = mesh.primitives[k];
      const std::string pp = pointer + "/primitives/" + str(k);
      const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        if (mode >= 0 && mode <= 3) {
          if (instance == 0) warn(pp + ": points and lines are not drawn");
          continue;
        }
        fail(pp + "/mode", "unknown mode " + std::to_string(mode));
      }
      // A Draco primitive's indices accessor only describes the Draco data's triangles.
      meshes_.check_draco_indices(static_cast<std::size_t>(index), k, pp);
      // The material is validated (and prepared, once) in the order its primitives come.
      materials_.material(p.material, pp + "/material");
      // Tangents, generated when the file has none, for a normal map, a coat's normal map or
      // an anisotropic lobe (KHR_materials_anisotropy: "tangents are computed" then).
      bool normal_mapped = false;
      if (p.material >= 0) {
        const tg::Material& gm = m_.materials[static_cast<std::size_t>(p.material)];
        normal_mapped = gm.normalTexture.index >= 0 || gm.extensions.count("KHR_materials_anisotropy") != 0;
        const auto coat = gm.extensions.find("KHR_materials_clearcoat");
        if (coat != gm.extensions.end() && coat->second.IsObject() && coat->second.Has("clearcoatNormalTexture"))
          normal_mapped = true;
      }
      placed_.push_back({meshes_.primitive(index, k, mirrored, pp, normal_mapped), p.material, transform});
      if (skinned || morphed) {
        placed_.back().node = static_cast<int>(node);
        placed_.back().mesh_index = index;
        placed_.back().primitive = k;
        placed_.back().weights = weights;
        placed_.back().skinned = skinned;
      }
    }
  }
}

// Each skinned or morphed primitive's mesh deformed (deform.h), in the order placed; the
// joint matrices made once per skin.
void SceneGraph::deform_meshes() {
  std::map<int, JointPalette> joints;
  for (Placed& o : placed_) {
    if (o.node < 0) continue;
    const tg::Node& n = m_.nodes[static_cast<std::size_t>(o.node)];
    const tg::Primitive& p = m_.meshes[static_cast<std::size_t>(o.mesh_index)].primitives[o.primitive];
    const std::string pp = "/meshes/" + std::to_string(o.mesh_index) + "/primitives/" + str(o.primitive);
    if (p.extensions.count(kDraco))
      fail(pp + "/extensions/" + kDraco, "skins and morph targets of a Draco-compressed primitive are not supported");
    const std::size_t vertices = m_.accessors[static_cast<std::size_t>(p.attributes.at("POSITION"))].count;
    const Meshes::VertexSources& sources = meshes_.vertex_sources(o.mesh_index, o.primitive);
    Deformation d;
    d.sources = &sources.sources;
    d.flat = sources.flat;
    d.targets = rigging_.targets(p, o.weights, vertices, pp);
    if (o.skinned) {
      auto it = joints.find(n.skin);
      if (it == joints.end())
        it = joints.emplace(n.skin, joint_palette(rigging_.joint_matrices(n.skin, world_, visited_,
                                                                          "/nodes/" + std::to_string(o.node) + "/skin")))
                 .first;
      SkinInfluences& influences = rigging_.influences(p, vertices, it->second.size(), pp);
      influences.palette = &it->second;
      d.skin = &influences;
    }
    o.mesh = std::make_shared<const Mesh>(deform(*o.mesh, d, options_.pool));
  }
}

// ---- Cameras and lights ----------------------------------------------------------------

void SceneGraph::add_camera(int index, const glm::dmat4& world, const std::string& referrer) {
  if (index < 0 || static_cast<std::size_t>(index) >= m_.cameras.size())
    fail(referrer, "camera " + std::to_string(index) + " does not exist");
  const tg::Camera& c = m_.cameras[static_cast<std::size_t>(index)];
  const std::string pointer = "/cameras/" + std::to_string(index);
  GltfCamera g;
  g.name = c.name;
  const glm::dvec3 eye(world * glm::dvec4(0, 0, 0, 1));
  const glm::dvec3 forward(world * glm::dvec4(0, 0, -1, 0));
  const glm::dvec3 up(world * glm::dvec4(0, 1, 0, 0));
  g.camera.position = glm::vec3(eye);
  g.camera.target = glm::vec3(eye + forward);
  g.camera.up = glm::vec3(up);
  if (c.type == "orthographic") {
    // glTF 2.0 §5.13: xmag and ymag not zero (and not negative: a mirrored view is not
    // drawn), znear ≥ 0, zfar > znear.
    const tg::OrthographicCamera& o = c.orthographic;
    const std::string op = pointer + "/orthographic";
    auto magnification = [&](double x, const char* name) {
      if (!(x > 0.0) || !(x <= 1e30)) fail(op + "/" + name, "must be a number in (0, 1e30], got " + number_text(x));
      if (!(static_cast<float>(x) >= 1e-30f)) fail(op + "/" + name, "must be at least 1e-30, got " + number_text(x));
      return static_cast<float>(x);
    };
    g.camera.orthographic = true;
    g.camera.xmag = magnification(o.xmag, "xmag");
    g.camera.ymag = magnification(o.ymag, "ymag");
    if (!(o.znear >= 0.0) || !(o.znear <= 1e30)) fail(op + "/znear", "must be a number in [0, 1e30], got " + number_text(o.znear));
    if (!(o.zfar > o.znear) || !(o.zfar <= 1e30))
      fail(op + "/zfar", "must be above znear and at most 1e30, got " + number_text(o.zfar));
    g.camera.near = static_cast<float>(o.znear);
    g.camera.far = static_cast<float>(o.zfar);
    if (!(g.camera.far - g.camera.near >= 1e-30f))
      fail(op + "/zfar", "must be at least 1e-30 beyond znear in float precision, got " + number_text(o.zfar));
  } else if (c.type == "perspective") {
    const tg::PerspectiveCamera& p = c.perspective;
    if (!(p.yfov > 0.0 && p.yfov < 3.14159)) fail(pointer + "/perspective/yfov", "must be in (0, π)");
    if (!(p.znear > 0.0) || !std::isfinite(p.znear)) fail(pointer + "/perspective/znear", "must be > 0");
    if (p.zfar != 0.0 && !(p.zfar > p.znear)) fail(pointer + "/perspective/zfar", "must be above znear");
    g.camera.fovy = static_cast<float>(p.yfov);
    g.camera.near = static_cast<float>(p.znear);
    // An infinite far plane (zfar absent) becomes a far one: 10^5 × znear keeps the depth
    // buffer's precision usable.
    g.camera.far = static_cast<float>(p.zfar != 0.0 ? p.zfar : p.znear * 1e5);
    g.aspect_ratio = static_cast<float>(p.aspectRatio);
  } else {
    fail(pointer + "/type", "must be perspective or orthographic");  // (tinygltf refuses others first)
  }
  out_.cameras.push_back(g);
}

void SceneGraph::add_light(int index, const glm::dmat4& world, const std::string& referrer) {
  if (index < 0 || static_cast<std::size_t>(index) >= m_.lights.size())
    fail(referrer, "light " + std::to_string(index) + " does not exist");
  const tg::Light& l = m_.lights[static_cast<std::size_t>(index)];
  const std::string pointer = "/extensions/KHR_lights_punctual/lights/" + std::to_string(index);
  Light out;
  if (l.type == "point") out.type = LightType::Point;
  else if (l.type == "spot") out.type = LightType::Spot;
  else if (l.type == "directional") out.type = LightType::Directional;
  else fail(pointer + "/type", "must be point, spot or directional, got " + l.type);
  if (!l.color.empty()) {
    if (l.color.size() != 3) fail(pointer + "/color", "must have 3 numbers");
    for (double c : l.color)
      if (!(c >= 0.0) || !std::isfinite(c)) fail(pointer + "/color", "must be finite and non-negative");
    out.color = {static_cast<float>(l.color[0]), static_cast<float>(l.color[1]), static_cast<float>(l.color[2])};
  }
  if (!(l.intensity >= 0.0) || !std::isfinite(l.intensity)) fail(pointer + "/intensity", "must be finite and ≥ 0");
  // KHR_lights_punctual: candela (point, spot) and lux (directional) scale the light's
  // radiance directly, as the glTF Sample Viewer applies them (docs/scene-format.md).
  out.intensity = static_cast<float>(l.intensity);
  if (!(l.range >= 0.0) || !std::isfinite(l.range)) fail(pointer + "/range", "must be finite and ≥ 0");
  out.range = static_cast<float>(l.range);
  out.position = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
  const glm::dvec3 d(world * glm::dvec4(0, 0, -1, 0));
  const double len = std::sqrt(glm::dot(d, d));
  if (!(len > 0.0)) fail(referrer, "the light's node has a degenerate transform");
  out.direction = glm::vec3(d / len);
  if (out.type == LightType::Spot) {
    out.inner_cone = static_cast<float>(l.spot.innerConeAngle);
    out.outer_cone = static_cast<float>(l.spot.outerConeAngle);
  }
  out.shadows = true;  // glTF's lights cast shadows (docs/scene-format.md; --shadows off turns them off)
  out_.lights.push_back(out);
}

}  // namespace softpbr::pbr::gltf

namespace softpbr::pbr {

const std::vector<std::string>& gltf_extensions_rendered() {
  static const std::vector<std::string> kRendered = [] {
    std::vector<std::string> v = {"KHR_texture_transform", "KHR_texture_basisu", "EXT_texture_webp", "EXT_texture_avif",
                                  "KHR_materials_emissive_strength", "KHR_materials_variants",
                                  "KHR_materials_pbrSpecularGlossiness",
                                  "KHR_mesh_quantization", "KHR_lights_punctual", "KHR_materials_unlit",
                                  "KHR_materials_ior", "KHR_materials_specular", "KHR_materials_clearcoat",
                                  "KHR_materials_sheen", "KHR_materials_anisotropy", "KHR_materials_iridescence",
                                  "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_dispersion",
                                  gltf::kMeshopt, gltf::kDraco, gltf::kInstancing};
    std::sort(v.begin(), v.end());
    return v;
  }();
  return kRendered;
}

}  // namespace softpbr::pbr
