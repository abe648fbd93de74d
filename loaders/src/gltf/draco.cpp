// KHR_draco_mesh_compression (see draco.h).
#include "gltf/draco.h"

#include <cstring>
#include <memory>
#include <new>
#include <stdexcept>

#include <draco/attributes/attribute_octahedron_transform.h>
#include <draco/attributes/attribute_quantization_transform.h>
#include <draco/compression/attributes/normal_compression_utils.h>
#include <draco/compression/decode.h>

namespace softpbr::pbr::gltf {

namespace {

template <class T>
float raw_value(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return static_cast<float>(v);
}

// One component of a value stored untransformed, as a float (integers by their value).
bool stored_value(draco::DataType type, const std::uint8_t* p, float& out) {
  switch (type) {
    case draco::DT_INT8: out = raw_value<std::int8_t>(p); return true;
    case draco::DT_UINT8: out = raw_value<std::uint8_t>(p); return true;
    case draco::DT_INT16: out = raw_value<std::int16_t>(p); return true;
    case draco::DT_UINT16: out = raw_value<std::uint16_t>(p); return true;
    case draco::DT_INT32: out = raw_value<std::int32_t>(p); return true;
    case draco::DT_UINT32: out = raw_value<std::uint32_t>(p); return true;
    case draco::DT_FLOAT32: out = raw_value<float>(p); return true;
    default: return false;
  }
}

}  // namespace

DracoMesh decode_draco(std::span<const std::uint8_t> bytes, const std::map<std::string, int>& ids, std::size_t max_points,
                       const std::function<void(const std::string&, const std::string&)>& fail_at) {
  auto fail = [&](const std::string& pointer, const std::string& what) {
    fail_at(pointer, what);
    throw std::logic_error("fail_at returned");  // (it throws)
  };
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  // Quantized and octahedral attributes come back as their integers; their inverse
  // transforms are computed below.
  draco::Decoder decoder;
  for (auto type : {draco::GeometryAttribute::POSITION, draco::GeometryAttribute::NORMAL, draco::GeometryAttribute::COLOR,
                    draco::GeometryAttribute::TEX_COORD, draco::GeometryAttribute::GENERIC})
    decoder.SetSkipAttributeTransform(type);
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) {
    std::string why = decoded.status().error_msg_string();
    if (why.size() > 200) why.resize(200);
    fail("", "the Draco data cannot be decoded (" + (why.empty() ? std::string("no reason given") : why) + ")");
  }
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) fail("", "the Draco data holds no mesh");
  DracoMesh out;
  out.points = mesh->num_points();
  if (out.points < 1 || out.points > max_points)
    fail("", "the Draco mesh has " + std::to_string(out.points) + " points (1 … " + std::to_string(max_points) + " allowed)");
  const std::size_t faces = mesh->num_faces();
  if (faces > max_points * 8) fail("", "the Draco mesh has " + std::to_string(faces) + " faces, too many for its points");
  out.indices.reserve(faces * 3);
  for (std::size_t f = 0; f < faces; ++f) {
    const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(static_cast<std::uint32_t>(f)));
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = face[static_cast<std::size_t>(k)].value();
      if (v >= out.points)
        fail("", "face " + std::to_string(f) + " of the Draco mesh names point " + std::to_string(v) + " (" +
                     std::to_string(out.points) + " points)");
      out.indices.push_back(v);
    }
  }
  for (const auto& [name, id] : ids) {
    const std::string where = "/attributes/" + name;
    if (id < 0) fail(where, "must be an integer ≥ 0");
    const draco::PointAttribute* att = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id));
    if (att == nullptr) fail(where, "the Draco data has no attribute " + std::to_string(id));
    const int stored = att->num_components();
    const draco::AttributeTransformData* transform = att->GetAttributeTransformData();
    const auto kind = transform != nullptr ? transform->transform_type() : draco::ATTRIBUTE_INVALID_TRANSFORM;
    DracoAttribute a;
    if (stored < 1 || stored > 4) fail(where, "the Draco attribute has " + std::to_string(stored) + " components");
    auto address = [&](std::size_t p) {
      const draco::AttributeValueIndex avi = att->mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p)));
      if (avi.value() >= att->size()) fail(where, "the Draco attribute's point " + std::to_string(p) + " has no value");
      return att->GetAddress(avi);
    };
    if (kind == draco::ATTRIBUTE_QUANTIZATION_TRANSFORM) {
      draco::AttributeQuantizationTransform q;
      if (!q.InitFromAttribute(*att) || (att->data_type() != draco::DT_INT32 && att->data_type() != draco::DT_UINT32))
        fail(where, "the Draco attribute's quantization cannot be read");
      const int bits = q.quantization_bits();
      if (bits < 1 || bits > 30) fail(where, "the Draco attribute has " + std::to_string(bits) + " quantization bits");
      // libdraco's Dequantizer: delta = range / (2^bits − 1), value = q · delta + min.
      const float delta = q.range() / static_cast<float>((std::int32_t{1} << bits) - 1);
      a.components = stored;
      a.values.resize(out.points * static_cast<std::size_t>(stored));
      for (std::size_t p = 0; p < out.points; ++p) {
        const std::uint8_t* at = address(p);
        for (int c = 0; c < stored; ++c) {
          std::int32_t v;
          std::memcpy(&v, at + 4 * c, 4);
          a.values[p * static_cast<std::size_t>(stored) + static_cast<std::size_t>(c)] =
              static_cast<float>(v) * delta + q.min_value(c);
        }
      }
      a.dequantized = true;
    } else if (kind == draco::ATTRIBUTE_OCTAHEDRON_TRANSFORM) {
      draco::AttributeOctahedronTransform o;
      draco::OctahedronToolBox box;
      if (!o.InitFromAttribute(*att) || stored != 2 ||
          (att->data_type() != draco::DT_INT32 && att->data_type() != draco::DT_UINT32) ||
          !box.SetQuantizationBits(o.quantization_bits()))
        fail(where, "the Draco attribute's octahedral coding cannot be read");
      const std::int32_t max = (std::int32_t{1} << o.quantization_bits()) - 1;
      a.components = 3;
      a.values.resize(out.points * 3);
      for (std::size_t p = 0; p < out.points; ++p) {
        const std::uint8_t* at = address(p);
        std::int32_t s, t;
        std::memcpy(&s, at, 4);
        std::memcpy(&t, at + 4, 4);
        if (s < 0 || s > max || t < 0 || t > max) fail(where, "the Draco attribute holds an octahedral value out of range");
        box.QuantizedOctahedralCoordsToUnitVector(s, t, &a.values[p * 3]);
      }
      a.dequantized = true;
    } else if (kind == draco::ATTRIBUTE_INVALID_TRANSFORM) {
      const draco::DataType type = att->data_type();
      const auto size = static_cast<std::size_t>(draco::DataTypeLength(type));
      a.components = stored;
      a.values.resize(out.points * static_cast<std::size_t>(stored));
      for (std::size_t p = 0; p < out.points; ++p) {
        const std::uint8_t* at = address(p);
        for (int c = 0; c < stored; ++c)
          if (!stored_value(type, at + size * static_cast<std::size_t>(c),
                            a.values[p * static_cast<std::size_t>(stored) + static_cast<std::size_t>(c)]))
            fail(where, "the Draco attribute's data type is not one glTF has");
      }
      a.dequantized = type == draco::DT_FLOAT32;
    } else {
      fail(where, "the Draco attribute's transform is not one softpbr reads");
    }
    out.attributes[name] = std::move(a);
  }
  return out;
}

}  // namespace softpbr::pbr::gltf
