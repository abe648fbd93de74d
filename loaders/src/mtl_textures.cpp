// MTL texture maps onto texture slots (see mtl_textures.h; the mapping is in obj.h): single
// maps load through the texture cache, map_Pr/map_Pm/map_Ns and map_Kd/map_d are combined
// into one texture each, bump maps are used only when they are normal maps.
#include "mtl_textures.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "softpbr/image/read_file.h"
#include "softpbr/loaders/format_bytes.h"

namespace softpbr::pbr::detail {

namespace fs = std::filesystem;

namespace {

constexpr const char* kDefaultKeyword[kMtlMapCount] = {"map_Kd", "map_Ke", "map_Pr", "map_Pm",
                                                       "map_Ns", "norm",   "bump",   "map_d"};

// A tangent-space normal map, told from a height map: not grey, and its mean colour near
// the flat normal's (0.5, 0.5, 1) — each of x and y within ±0.2 of 0 and z ≥ 0.5 once
// decoded (2c − 1). Normal maps average about (0.5, 0.5, 0.95); height maps are grey.
bool looks_like_normal_map(const TextureImage& im) {
  const std::size_t n = static_cast<std::size_t>(im.width()) * static_cast<std::size_t>(im.height());
  if (im.is_float) {
    double sum[3] = {0, 0, 0};
    bool grey = true;
    for (std::size_t i = 0; i < n; ++i) {
      const float* p = &im.imagef.rgba[i * 4];
      grey = grey && p[0] == p[1] && p[1] == p[2];
      for (int c = 0; c < 3; ++c) sum[c] += p[c];
    }
    const double r = sum[0] / static_cast<double>(n), g = sum[1] / static_cast<double>(n);
    return !grey && r >= 0.4 && r <= 0.6 && g >= 0.4 && g <= 0.6 && sum[2] / static_cast<double>(n) >= 0.75;
  }
  std::uint64_t sum[3] = {0, 0, 0};
  bool grey = true;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = &im.image8.rgba[i * 4];
    grey = grey && p[0] == p[1] && p[1] == p[2];
    for (int c = 0; c < 3; ++c) sum[c] += p[c];
  }
  // Means as codes/255 compared in integers: mean ≥ 0.4 ⇔ 10·sum ≥ 4·255·n.
  const std::uint64_t full = 255u * static_cast<std::uint64_t>(n);
  auto within = [&](std::uint64_t s) { return 10 * s >= 4 * full && 10 * s <= 6 * full; };
  return !grey && within(sum[0]) && within(sum[1]) && 4 * sum[2] >= 3 * full;
}

// Channel c of the texel of `src` nearest to the centre of texel (x, y) of a w × h grid
// laid over it: ⌊(x + ½)·src.width / w⌋, in integers (w ≥ src.width, h ≥ src.height).
std::uint8_t nearest(const image::Image8& src, int w, int h, int x, int y, int c) {
  using U = std::uint64_t;
  const U sx = (2 * U(x) + 1) * U(src.width) / (2 * U(w)), sy = (2 * U(y) + 1) * U(src.height) / (2 * U(h));
  return src.rgba[(sy * U(src.width) + sx) * 4 + U(c)];
}

// A w × h RGBA image with every sample `fill`, and its texel (x, y).
image::Image8 blank(int w, int h, std::uint8_t fill) {
  return {w, h, image::PixelVector<std::uint8_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4, fill)};
}
std::uint8_t* texel(image::Image8& im, int x, int y) {
  return &im.rgba[(static_cast<std::size_t>(y) * static_cast<std::size_t>(im.width) + static_cast<std::size_t>(x)) * 4];
}

bool same_options(const tinyobj::texture_option_t& a, const tinyobj::texture_option_t& b) {
  return a.origin_offset[0] == b.origin_offset[0] && a.origin_offset[1] == b.origin_offset[1] &&
         a.scale[0] == b.scale[0] && a.scale[1] == b.scale[1] && a.clamp == b.clamp;
}

// The maps of one material.
class Mapper {
 public:
  Mapper(const tinyobj::material_t& m, const MtlInfo& info, MtlTextures& textures)
      : m_(m), info_(info), t_(textures),
        name_{&m.diffuse_texname, &m.emissive_texname, &m.roughness_texname, &m.metallic_texname,
              &m.specular_highlight_texname, &m.normal_texname, &m.bump_texname, &m.alpha_texname},
        opt_{&m.diffuse_texopt, &m.emissive_texopt, &m.roughness_texopt, &m.metallic_texopt,
             &m.specular_highlight_texopt, &m.normal_texopt, &m.bump_texopt, &m.alpha_texopt} {
    // tinyobjloader reads three numbers after -o, -s and -t, whatever they are: with two,
    // the file name is taken for the third and the map has none.
    for (std::size_t k = 0; k < kMtlMapCount; ++k)
      if (info_.line[k] != 0 && name_[k]->empty())
        fail(static_cast<MtlMap>(k), "no image file name after the options (-o, -s and -t take three numbers "
                                     "here: write -s 2 2 1, not -s 2 2)");
    // MissingImages::Warn: a map whose file cannot be read is left out, with a warning
    // (a file outside the roots stays an error: cache.read checks them when it loads).
    if (t_.missing_images == MissingImages::Warn)
      for (std::size_t k = 0; k < kMtlMapCount; ++k)
        if (!name_[k]->empty() && detail::outside_roots(path(static_cast<MtlMap>(k)), t_.cache.roots()).empty())
          if (const image::FileProblem p = image::file_problem(path(static_cast<MtlMap>(k)))) {
            missing_[k] = true;
            warn(static_cast<MtlMap>(k), path(static_cast<MtlMap>(k)).string() + ": " + p.reason +
                                             " (a missing image: the map is left out)");
          }
  }

  bool given(MtlMap k) const { return !name_[k]->empty() && !missing_[k]; }
  const tinyobj::texture_option_t& opt(MtlMap k) const { return *opt_[k]; }

  fs::path path(MtlMap k) const {
    const fs::path p(*name_[k]);
    return p.is_absolute() ? p : info_.file.parent_path() / p;
  }

  std::string where(MtlMap k) const {
    std::string s = info_.file.string();
    if (info_.line[k] > 0) {
      s += ':';
      s += std::to_string(info_.line[k]);  // not ":" + string: GCC 12's -Wrestrict false positive
    }
    s += ": ";
    s += info_.keyword[k].empty() ? kDefaultKeyword[k] : info_.keyword[k];
    return s + ": ";
  }
  [[noreturn]] void fail(MtlMap k, const std::string& what) const { throw LoadError(where(k) + what); }
  void warn(MtlMap k, const std::string& what) const { t_.warnings.push_back(where(k) + what); }

  // Runs f, giving the image library's and the texture's errors the map's place.
  template <class F>
  auto at(MtlMap k, F&& f) const {
    try {
      return f();
    } catch (const LoadError&) {
      throw;
    } catch (const std::runtime_error& e) {
      fail(k, e.what());
    }
  }

  std::shared_ptr<const raster::Texture> load(MtlMap k, raster::ColorSpace space) const {
    return at(k, [&] { return t_.cache.load(path(k), space, t_.left()); });
  }
  TextureImage read(MtlMap k) const {
    return at(k, [&] { return t_.cache.read(path(k), t_.left()); });
  }
  // An 8-bit image for a channel of a combined texture.
  image::Image8 read8(MtlMap k) const {
    if (is_float_image_path(path(k)))
      fail(k, path(k).string() + ": a float image cannot be a channel of an 8-bit texture (use a PNG or JPEG)");
    return std::move(read(k).image8);
  }
  // The texture of an image combined from maps, checked against the memory bound first
  // (4 bytes a texel, 4/3 for the mip chain).
  std::shared_ptr<const raster::Texture> combined(MtlMap k, image::Image8&& image, raster::ColorSpace space) const {
    const std::uint64_t bytes = static_cast<std::uint64_t>(image.width) * static_cast<std::uint64_t>(image.height) * 16 / 3;
    if (bytes > t_.left())
      fail(k, "the combined " + std::to_string(image.width) + "x" + std::to_string(image.height) + " texture needs " +
                  format_bytes(bytes) + ", over the " + format_bytes(t_.left()) + " the memory limit leaves");
    TextureImage pixels;
    pixels.image8 = std::move(image);
    return at(k, [&] { return make_texture(pixels, space, path(k).string()); });
  }

  // A slot for `texture` with map k's options: -o and -s as the UV transform, -clamp.
  TextureSlot slot(MtlMap k, std::shared_ptr<const raster::Texture> texture) const {
    const tinyobj::texture_option_t& o = opt(k);
    TextureSlot s;
    s.texture = std::move(texture);
    // MTL's transform is t = s·uv + o in OBJ's v-up coordinates; in the flipped ones
    // (v' = 1 − v, obj.h) it is s·uv' + (o_u, 1 − s_v − o_v).
    s.transform.scale = {o.scale[0], o.scale[1]};
    s.transform.offset = {o.origin_offset[0], 1.0f - o.scale[1] - o.origin_offset[1]};
    if (!std::isfinite(s.transform.scale.x) || !std::isfinite(s.transform.scale.y) ||
        !std::isfinite(s.transform.offset.x) || !std::isfinite(s.transform.offset.y))
      fail(k, "-o and -s take finite numbers");
    if (o.clamp) s.sampler.wrap_u = s.sampler.wrap_v = raster::Wrap::ClampToEdge;
    return s;
  }

  // The map whose options a texture combined from `a` and `b` uses: a's when given.
  MtlMap options_of(MtlMap a, bool has_a, MtlMap b, bool has_b) const {
    if (has_a && has_b && !same_options(opt(a), opt(b)))
      warn(b, std::string("its -o, -s or -clamp differ from ") + kDefaultKeyword[a] + "'s, which the combined texture uses");
    return has_a ? a : b;
  }

  void base_color(Material& out) const {
    const bool kd = given(kMapKd);
    if (kd && !info_.has_kd) out.base_color = glm::vec3(1.0f);  // not tinyobjloader's 0.6
    if (given(kMapD) && kd && is_float_image_path(path(kMapKd))) {
      warn(kMapD, "ignored: alpha cannot be combined with a float map_Kd");
    } else if (given(kMapD)) {
      // map_Kd's RGB (or white) and map_d's alpha in one sRGB texture (alpha stays linear).
      std::string key = "base colour and alpha";
      key += '\0' + (kd ? TextureCache::key(path(kMapKd), "srgb") : std::string()) + '\0' +
             TextureCache::key(path(kMapD), "alpha");
      const MtlMap k = options_of(kMapKd, kd, kMapD, true);
      out.base_color_texture = slot(k, t_.cache.get(key, [&] {
        const image::Image8 rgb = kd ? read8(kMapKd) : image::Image8{};
        const image::Image8 a = read8(kMapD);
        bool has_alpha = false;
        for (std::size_t i = 3; i < a.rgba.size() && !has_alpha; i += 4) has_alpha = a.rgba[i] < 255;
        const int w = std::max(rgb.width, a.width), h = std::max(rgb.height, a.height);
        image::Image8 out_image = blank(w, h, 255);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            std::uint8_t* p = texel(out_image, x, y);
            for (int c = 0; c < 3; ++c) p[c] = kd ? nearest(rgb, w, h, x, y, c) : 255;
            p[3] = nearest(a, w, h, x, y, has_alpha ? 3 : 0);
          }
        return combined(kMapD, std::move(out_image), raster::ColorSpace::Srgb);
      }));
      out.alpha_mode = AlphaMode::Mask;
      return;
    }
    if (kd) out.base_color_texture = slot(kMapKd, load(kMapKd, raster::ColorSpace::Srgb));
  }

  void metallic_roughness(Material& out) const {
    const bool pr = given(kMapPr), pm = given(kMapPm);
    const bool ns = !pr && !info_.has_pr && given(kMapNs);
    if (given(kMapNs) && !ns) warn(kMapNs, "ignored: Pr or map_Pr gives the roughness");
    const bool rough = pr || ns;
    if (!rough && !pm) return;
    const MtlMap rk = pr ? kMapPr : kMapNs;
    // map_Ns holds a fraction of the exponent (code/255 × Ns; Ns 1000, the top of MTL's
    // range, when the material has none), turned into roughness as the constant Ns is.
    const float ns_full = info_.has_ns ? m_.shininess : 1000.0f;
    std::string key = "metallic-roughness";
    const std::string how = pr ? "roughness" : "Ns " + std::to_string(std::bit_cast<std::uint32_t>(ns_full));
    if (rough) key += '\0' + TextureCache::key(path(rk), how);
    if (pm) key += '\0' + TextureCache::key(path(kMapPm), "metallic");
    const MtlMap k = options_of(rk, rough, kMapPm, pm);
    out.metallic_roughness_texture = slot(k, t_.cache.get(key, [&] {
      const image::Image8 g = rough ? read8(rk) : image::Image8{};
      const image::Image8 b = pm ? read8(kMapPm) : image::Image8{};
      std::uint8_t from_ns[256];
      for (int c = 0; c < 256; ++c) {
        const float r = roughness_from_phong_exponent(static_cast<float>(static_cast<double>(ns_full) * c / 255.0));
        from_ns[c] = static_cast<std::uint8_t>(std::lround(255.0f * r));
      }
      const int w = std::max(g.width, b.width), h = std::max(g.height, b.height);
      image::Image8 mr = blank(w, h, 255);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          std::uint8_t* p = texel(mr, x, y);
          if (rough) p[1] = pr ? nearest(g, w, h, x, y, 0) : from_ns[nearest(g, w, h, x, y, 0)];
          if (pm) p[2] = nearest(b, w, h, x, y, 0);
        }
      return combined(k, std::move(mr), raster::ColorSpace::Linear);
    }));
    // The map is the value: a factor of 1 unless the material gives one.
    if (rough && !(pr && info_.has_pr)) out.roughness = 1.0f;
    if (pm && !info_.has_pm) out.metallic = 1.0f;
  }

  void normal(Material& out) const {
    if (given(kMapNorm)) {
      out.normal_texture = slot(kMapNorm, load(kMapNorm, raster::ColorSpace::Linear));
      out.normal_scale = opt(kMapNorm).bump_multiplier;
      if (given(kMapBump)) warn(kMapBump, "ignored: norm gives the normal map");
    } else if (given(kMapBump)) {
      const fs::path p = path(kMapBump);
      // The verdict is cached too: a height map is read once however many materials name it.
      auto texture = t_.cache.get(TextureCache::key(p, "bump"), [&]() -> std::shared_ptr<const raster::Texture> {
        const TextureImage image = read(kMapBump);
        if (!looks_like_normal_map(image)) return nullptr;
        const auto make = [&] { return make_texture(image, raster::ColorSpace::Linear, p.string()); };
        return t_.cache.get(TextureCache::key(p, image.is_float ? "float" : "linear"), [&] { return at(kMapBump, make); });
      });
      if (!texture) {
        warn(kMapBump, p.string() + " is a height map (grey, or its mean colour is not near (0.5, 0.5, 1)); "
                       "bump mapping is not supported: skipped");
        return;
      }
      out.normal_texture = slot(kMapBump, std::move(texture));
      out.normal_scale = opt(kMapBump).bump_multiplier;
    }
    if (!std::isfinite(out.normal_scale)) fail(given(kMapNorm) ? kMapNorm : kMapBump, "-bm takes a finite number");
  }

  void emissive(Material& out) const {
    if (!given(kMapKe)) return;
    out.emissive_texture = slot(kMapKe, load(kMapKe, raster::ColorSpace::Srgb));
    if (!info_.has_ke) out.emissive = glm::vec3(1.0f);
  }

  // Maps no slot takes, in one warning.
  void ignored() const {
    std::string list;
    auto note = [&](const std::string& name, const char* keyword) {
      if (!name.empty()) list += (list.empty() ? "" : ", ") + std::string(keyword);
    };
    note(m_.ambient_texname, "map_Ka");
    note(m_.specular_texname, "map_Ks");
    note(m_.displacement_texname, "disp");
    note(m_.reflection_texname, "refl");
    note(m_.sheen_texname, "map_Ps");
    if (!list.empty())
      t_.warnings.push_back(info_.file.string() + ": material '" + m_.name + "': " + list +
                            " ignored (no texture slot of a metal/roughness material takes them)");
  }

 private:
  const tinyobj::material_t& m_;
  const MtlInfo& info_;
  MtlTextures& t_;
  const std::string* name_[kMtlMapCount];
  const tinyobj::texture_option_t* opt_[kMtlMapCount];
  bool missing_[kMtlMapCount] = {};  // left out: MissingImages::Warn and its file cannot be read
};

}  // namespace

void map_textures(const tinyobj::material_t& m, const MtlInfo& info, Material& material, MtlTextures& textures) {
  const Mapper mapper(m, info, textures);
  mapper.base_color(material);
  mapper.emissive(material);
  mapper.metallic_roughness(material);
  mapper.normal(material);
  mapper.ignored();
}

}  // namespace softpbr::pbr::detail
