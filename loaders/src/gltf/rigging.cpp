// The glTF reader's skins and morph targets (see rigging.h).
#include "gltf/rigging.h"

#include <cmath>

namespace softpbr::pbr::gltf {

std::vector<glm::dmat4> Rigging::joint_matrices(int skin, const std::vector<glm::dmat4>& world,
                                                const std::vector<bool>& placed, const std::string& referrer) const {
  if (skin < 0 || static_cast<std::size_t>(skin) >= m_.skins.size())
    fail(referrer, "skin " + std::to_string(skin) + " does not exist");
  const tg::Skin& s = m_.skins[static_cast<std::size_t>(skin)];
  const std::string sp = "/skins/" + std::to_string(skin);
  if (s.joints.empty()) fail(sp + "/joints", "must name at least one joint");
  std::vector<float> ibm;
  if (s.inverseBindMatrices >= 0) {
    ibm = resources_.read_floats(s.inverseBindMatrices, sp + "/inverseBindMatrices", {16});
    if (ibm.size() / 16 < s.joints.size())
      fail(sp + "/inverseBindMatrices", "has " + str(ibm.size() / 16) + " matrices for " + str(s.joints.size()) + " joints");
    for (float x : ibm)
      if (!std::isfinite(x)) fail("/accessors/" + std::to_string(s.inverseBindMatrices), "holds a value that is not finite");
  }
  std::vector<glm::dmat4> out(s.joints.size());
  for (std::size_t j = 0; j < s.joints.size(); ++j) {
    const int node = s.joints[j];
    if (node < 0 || static_cast<std::size_t>(node) >= m_.nodes.size())
      fail(sp + "/joints/" + str(j), "node " + std::to_string(node) + " does not exist");
    if (!placed[static_cast<std::size_t>(node)])
      fail(sp + "/joints/" + str(j), "node " + std::to_string(node) + " is not in the scene");
    glm::dmat4 inverse_bind(1.0);
    if (!ibm.empty())
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) inverse_bind[c][r] = ibm[16 * j + static_cast<std::size_t>(4 * c + r)];  // column-major
    out[j] = world[static_cast<std::size_t>(node)] * inverse_bind;
  }
  return out;
}

SkinInfluences& Rigging::influences(const tg::Primitive& p, std::size_t vertices, std::size_t joints,
                                    const std::string& pointer) {
  if (auto it = influences_.find({&p, joints}); it != influences_.end()) return it->second;
  SkinInfluences k;
  std::vector<std::vector<float>> js, ws;
  for (int set = 0;; ++set) {
    const std::string jn = "JOINTS_" + std::to_string(set), wn = "WEIGHTS_" + std::to_string(set);
    const auto j = p.attributes.find(jn), w = p.attributes.find(wn);
    if (j == p.attributes.end() && w == p.attributes.end()) break;
    if (j == p.attributes.end() || w == p.attributes.end())
      fail(pointer + "/attributes", "has " + (j == p.attributes.end() ? wn + " without " + jn : jn + " without " + wn));
    const std::string ap = pointer + "/attributes/";
    const int jt = j->second >= 0 && static_cast<std::size_t>(j->second) < m_.accessors.size()
                       ? m_.accessors[static_cast<std::size_t>(j->second)].componentType
                       : 0;
    if (jt != 0 && jt != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && jt != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
      fail("/accessors/" + std::to_string(j->second) + "/componentType", "joints must be unsigned bytes or shorts");
    js.push_back(resources_.read_floats(j->second, ap + jn, {4}));
    ws.push_back(resources_.read_floats(w->second, ap + wn, {4}));
    if (js.back().size() != 4 * vertices || ws.back().size() != 4 * vertices)
      fail(ap + (js.back().size() != 4 * vertices ? jn : wn), "must have one element per position (" + str(vertices) + ")");
  }
  if (js.empty()) fail(pointer + "/attributes", "has no JOINTS_0 and WEIGHTS_0 for its node's skin");
  k.influences = 4 * js.size();
  k.joints.resize(vertices * k.influences);
  k.weights.resize(vertices * k.influences);
  const std::string where = pointer + "/attributes/";
  std::vector<double> given(k.influences);
  for (std::size_t v = 0; v < vertices; ++v) {
    double sum = 0.0;
    for (std::size_t set = 0; set < js.size(); ++set)
      for (std::size_t c = 0; c < 4; ++c) {
        const float jf = js[set][4 * v + c];
        const float wf = ws[set][4 * v + c];
        if (!(wf >= 0.0f) || !std::isfinite(wf))
          fail(where + "WEIGHTS_" + str(set), "vertex " + str(v) + " has a weight that is negative or not finite");
        if (wf > 0.0f && !(static_cast<double>(jf) < static_cast<double>(joints)))
          fail(where + "JOINTS_" + str(set), "vertex " + str(v) + " names joint " + std::to_string(static_cast<long>(jf)) +
                                                 " of a skin with " + str(joints) + " joints");
        k.joints[v * k.influences + 4 * set + c] = wf > 0.0f ? static_cast<std::uint32_t>(jf) : 0u;
        given[4 * set + c] = wf;
        sum += wf;
      }
    if (!(sum > 0.0))
      fail(pointer + "/attributes/WEIGHTS_0", "vertex " + str(v) + "'s weights sum to 0 (every vertex of a skinned mesh needs a joint)");
    // §3.7.3.3: the weights are normalised to sum to 1 (in double, then rounded once).
    for (std::size_t c = 0; c < k.influences; ++c)
      k.weights[v * k.influences + c] = static_cast<float>(sum != 1.0 ? given[c] / sum : given[c]);
  }
  return influences_[{&p, joints}] = std::move(k);
}

std::vector<double> Rigging::weights(int node, int mesh, const std::vector<double>* posed) const {
  const tg::Mesh& m = m_.meshes[static_cast<std::size_t>(mesh)];
  const std::size_t targets = m.primitives.empty() ? 0 : m.primitives.front().targets.size();
  const std::string mp = "/meshes/" + std::to_string(mesh);
  for (std::size_t k = 0; k < m.primitives.size(); ++k)
    if (m.primitives[k].targets.size() != targets)
      fail(mp + "/primitives/" + str(k) + "/targets", "has " + str(m.primitives[k].targets.size()) +
                                                          " morph targets; the mesh's first primitive has " + str(targets));
  if (targets == 0) return {};
  const tg::Node& n = m_.nodes[static_cast<std::size_t>(node)];
  const std::vector<double>& given = posed != nullptr ? *posed : !n.weights.empty() ? n.weights : m.weights;
  const std::string where = posed != nullptr ? "/nodes/" + std::to_string(node) + " (animated)"
                            : !n.weights.empty() ? "/nodes/" + std::to_string(node) + "/weights"
                                                 : mp + "/weights";
  if (given.empty()) return std::vector<double>(targets, 0.0);
  if (given.size() != targets) fail(where, "has " + str(given.size()) + " weights for " + str(targets) + " morph targets");
  for (double w : given)
    if (!std::isfinite(w)) fail(where, "holds a weight that is not finite");
  return given;
}

std::vector<MorphTarget> Rigging::targets(const tg::Primitive& p, const std::vector<double>& weights,
                                          std::size_t vertices, const std::string& pointer) {
  std::vector<MorphTarget> out;
  for (std::size_t t = 0; t < p.targets.size() && t < weights.size(); ++t) {
    if (weights[t] == 0.0) continue;
    auto it = deltas_.find({&p, t});
    if (it == deltas_.end()) {
      Deltas d;
      const std::string tp = pointer + "/targets/" + str(t) + "/";
      auto read = [&](const char* name, std::vector<float>& into) {
        const auto a = p.targets[t].find(name);
        if (a == p.targets[t].end()) return;
        into = resources_.read_floats(a->second, tp + name, {3});
        if (into.size() != 3 * vertices)
          fail(tp + name, "has " + str(into.size() / 3) + " elements for " + str(vertices) + " positions");
        for (float x : into)
          if (!std::isfinite(x)) fail("/accessors/" + std::to_string(a->second), "holds a value that is not finite");
      };
      read("POSITION", d.position);
      read("NORMAL", d.normal);
      read("TANGENT", d.tangent);
      it = deltas_.emplace(std::make_pair(&p, t), std::move(d)).first;
    }
    const Deltas& d = it->second;
    MorphTarget m;
    m.weight = weights[t];
    m.position = d.position.empty() ? nullptr : d.position.data();
    m.normal = d.normal.empty() ? nullptr : d.normal.data();
    m.tangent = d.tangent.empty() ? nullptr : d.tangent.data();
    out.push_back(m);
  }
  return out;
}

}  // namespace softpbr::pbr::gltf
