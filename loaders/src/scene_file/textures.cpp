// Scene files: a material's textures — an image path or an object with the image, its
// sampler, UV set and UV transform — loaded through the scene's texture cache and charged
// to its memory budget (see scene_file/loader.h).
#include "loader.h"

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr::scene_file {

namespace {

raster::Wrap read_wrap(const Reader& r, const Node& spec) {
  const std::string w = r.choice(spec, {"repeat", "clamp_to_edge", "mirrored_repeat"});
  return w == "repeat" ? raster::Wrap::Repeat : w == "clamp_to_edge" ? raster::Wrap::ClampToEdge : raster::Wrap::MirroredRepeat;
}

raster::Filter read_filter(const Reader& r, const Node& spec) {
  return r.choice(spec, {"nearest", "linear"}) == "nearest" ? raster::Filter::Nearest : raster::Filter::Linear;
}

// {"wrap" | "wrap_u", "wrap_v", "mag_filter", "min_filter", "mip_filter", "anisotropy",
// "lod_bias", "min_lod", "max_lod"}; what is not given keeps raster::Sampler's default.
raster::Sampler read_sampler(const Reader& r, const Node& spec) {
  r.object(spec, {"wrap", "wrap_u", "wrap_v", "mag_filter", "min_filter", "mip_filter", "anisotropy", "lod_bias",
                  "min_lod", "max_lod"});
  raster::Sampler s;
  if (auto w = r.member(spec, "wrap")) {
    for (const char* key : {"wrap_u", "wrap_v"})
      if (auto both = r.member(spec, key))
        r.fail(*both, std::string("\"wrap\" sets wrap_u and wrap_v already: give \"wrap\" or \"") + key + "\", not both");
    s.wrap_u = s.wrap_v = read_wrap(r, *w);
  }
  if (auto w = r.member(spec, "wrap_u")) s.wrap_u = read_wrap(r, *w);
  if (auto w = r.member(spec, "wrap_v")) s.wrap_v = read_wrap(r, *w);
  if (auto f = r.member(spec, "mag_filter")) s.mag_filter = read_filter(r, *f);
  if (auto f = r.member(spec, "min_filter")) s.min_filter = read_filter(r, *f);
  if (auto f = r.member(spec, "mip_filter")) {
    const std::string m = r.choice(*f, {"none", "nearest", "linear"});
    s.mip_filter = m == "none" ? raster::MipFilter::None : m == "nearest" ? raster::MipFilter::Nearest : raster::MipFilter::Linear;
  }
  if (auto a = r.member(spec, "anisotropy")) s.max_anisotropy = static_cast<int>(r.integer(*a, 1, raster::kMaxAnisotropy));
  if (auto b = r.member(spec, "lod_bias")) s.lod_bias = r.number_f(*b, -1e30, 1e30);
  if (auto l = r.member(spec, "min_lod")) s.min_lod = r.number_f(*l, -1e30, 1e30);
  if (auto l = r.member(spec, "max_lod")) s.max_lod = r.number_f(*l, -1e30, 1e30);
  if (s.min_lod > s.max_lod) {
    const auto where = r.member(spec, "min_lod");  // one of the two is given: the defaults are ordered
    r.fail(where ? *where : *r.member(spec, "max_lod"), "expected min_lod <= max_lod (" + json_reader::show_number(s.min_lod) +
                                                         " > " + json_reader::show_number(s.max_lod) + ")");
  }
  check_at(r, spec, [&] { raster::validate(s); });  // every field is checked above; this keeps the two in step
  return s;
}

// {"offset": [u, v], "rotation": degrees, "scale": [u, v]}, as KHR_texture_transform but in
// degrees like every angle of the format.
UvTransform read_uv_transform(const Reader& r, const Node& spec) {
  r.object(spec, {"offset", "rotation", "scale"});
  UvTransform t;
  if (auto o = r.member(spec, "offset")) {
    const std::vector<float> v = r.numbers(*o, 2, -1e30, 1e30);
    t.offset = {v[0], v[1]};
  }
  if (auto rot = r.member(spec, "rotation")) {
    r.number_f(*rot, -360, 360);
    t.rotation = static_cast<float>(dmath::radians(rot->value.get<double>()));
  }
  if (auto s = r.member(spec, "scale")) {
    const std::vector<float> v = r.numbers(*s, 2, -1e30, 1e30);
    t.scale = {v[0], v[1]};
  }
  return t;
}

}  // namespace

TextureSlot TextureLibrary::slot(const Node& spec, raster::ColorSpace space) {
  if (!spec.value.is_string() && !spec.value.is_object())
    r_.fail(spec, "expected an image path or a texture object {\"image\": …}, got " + json_reader::show(spec.value));
  TextureSlot slot;
  std::optional<Node> image;
  if (spec.value.is_string()) {
    image.emplace(spec);
  } else {
    r_.object(spec, {"image", "sampler", "uv_set", "uv_transform"});
    image.emplace(r_.required(spec, "image"));
    if (auto s = r_.member(spec, "sampler")) slot.sampler = read_sampler(r_, *s);
    if (auto u = r_.member(spec, "uv_set")) slot.uv_set = static_cast<int>(r_.integer(*u, 0, 1));
    if (auto t = r_.member(spec, "uv_transform")) slot.transform = read_uv_transform(r_, *t);
  }
  const std::filesystem::path rel = r_.string(*image);
  if (rel.empty()) r_.fail(*image, "expected a file name, got \"\"");
  const std::filesystem::path path = rel.is_absolute() ? rel : base_dir_ / rel;
  const std::uint64_t before = cache_.bytes();
  check_at(r_, *image, [&] { slot.texture = cache_.load(path, space, budget_.left()); });
  if (cache_.bytes() > before) budget_.charge(*image, cache_.bytes() - before, "this texture");
  return slot;
}

}  // namespace softpbr::pbr::scene_file
