// Loading PNG and Radiance .hdr images through stb_image, writing .hdr through
// stb_image_write, and the conversions between images and render targets.
#include "softpbr/golden/image.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include <stb_image.h>
#include <stb_image_write.h>

#include "softpbr/raster/color.h"
#include "hdr_scan.h"
#include "png_scan.h"
#include "samples.h"

namespace softpbr::golden {

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw std::runtime_error(path.string() + ": " + what);
}

// PNG and Radiance files by their first bytes (the PNG signature; stb_image's HDR test).
bool starts_with(const std::string& head, std::string_view magic) { return head.compare(0, magic.size(), magic) == 0; }
bool is_png_signature(const std::string& head) { return starts_with(head, "\x89PNG\r\n\x1a\n"); }
bool is_hdr_signature(const std::string& head) {
  return starts_with(head, "#?RADIANCE\n") || starts_with(head, "#?RGBE\n");
}

// Opens `path` and checks its header: a PNG or .hdr file as the caller wants, readable by
// stb_image, a size a Target could have (each side at most raster::kMaxTargetSize, so a
// hostile header cannot ask for more memory than the largest render).
//
// Only PNG and .hdr reach stb_image, by their signatures: its other decoders misbehave on
// hostile files (fuzz_image found a 24-byte TGA claiming 3340x3854 pixels that it decodes
// for seconds from zeros read past the end, as its BMP, PSD, PIC and PNM decoders would,
// and a signed overflow in its PNM header parser, which stbi_info reaches for any file).
File open_checked(const std::filesystem::path& path, bool want_hdr) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "no such file");
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) fail(path, "cannot open for reading");
  std::string head(16, '\0');
  head.resize(std::fread(head.data(), 1, head.size(), f.get()));
  if (std::fseek(f.get(), 0, SEEK_SET) != 0) fail(path, "cannot seek back to the start");
  if (is_hdr_signature(head) && !want_hdr) fail(path, "is a Radiance .hdr (float) image; load it with load_hdr");
  if (is_png_signature(head) && want_hdr) fail(path, "is an 8-bit image, not a Radiance .hdr; load it with load_png");
  if (!(want_hdr ? is_hdr_signature(head) : is_png_signature(head)))
    fail(path, want_hdr ? "not a readable image (no Radiance .hdr signature)" : "not a readable image (no PNG signature)");
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_file(f.get(), &w, &h, &channels))
    fail(path, std::string("not a readable image (") + stbi_failure_reason() + ")");
  if (w < 1 || h < 1 || w > raster::kMaxTargetSize || h > raster::kMaxTargetSize)
    fail(path, "image size " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1x1 .. " +
                   std::to_string(raster::kMaxTargetSize) + "x" + std::to_string(raster::kMaxTargetSize));
  const bool is_hdr = stbi_is_hdr_from_file(f.get()) != 0;
  if (is_hdr && !want_hdr) fail(path, "is a Radiance .hdr (float) image; load it with load_hdr");
  if (!is_hdr && want_hdr) fail(path, "is an 8-bit image, not a Radiance .hdr; load it with load_png");
  return f;
}

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

// The RGB that write_hdr stores: pbr::write_hdr's rule (non-finite and negative → 0).
std::vector<float> hdr_rgb(const ImageF& image) {
  std::vector<float> rgb;
  rgb.reserve(image.rgba.size() / 4 * 3);
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c) {
      const float v = image.rgba[i + c];
      rgb.push_back(std::isfinite(v) && v > 0.0f ? v : 0.0f);
    }
  return rgb;
}

std::vector<unsigned char> encode_hdr(const ImageF& image, const std::filesystem::path& name) {
  detail::check_pixel_data(image, name.string());
  if (image.width < 1 || image.height < 1) fail(name, "cannot write an empty image");
  std::vector<float> rgb = hdr_rgb(image);
  std::vector<unsigned char> bytes;
  if (!stbi_write_hdr_to_func(append_bytes, &bytes, image.width, image.height, 3, rgb.data()))
    fail(name, "HDR encoding failed");
  return bytes;
}

ImageF decode_hdr(const float* rgb, int w, int h) {
  ImageF image{w, h, {}};
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  image.rgba.resize(n * 4);
  for (std::size_t i = 0; i < n; ++i) {
    image.rgba[4 * i + 0] = rgb[3 * i + 0];
    image.rgba[4 * i + 1] = rgb[3 * i + 1];
    image.rgba[4 * i + 2] = rgb[3 * i + 2];
    image.rgba[4 * i + 3] = 1.0f;
  }
  return image;
}

}  // namespace

Image8 load_png(const std::filesystem::path& path) {
  File f = open_checked(path, false);
  int w = 0, h = 0, channels = 0;
  // stb_image allocates what a chunk claims before reading it (png_scan.h).
  if (const std::string problem = detail::png_truncation(f.get()); !problem.empty())
    fail(path, "cannot decode (" + problem + ")");
  if (std::fseek(f.get(), 0, SEEK_SET) != 0) fail(path, "cannot seek back to the start");
  std::unique_ptr<stbi_uc, StbFree> data(stbi_load_from_file(f.get(), &w, &h, &channels, 4));
  if (!data) fail(path, std::string("cannot decode (") + stbi_failure_reason() + ")");
  Image8 image{w, h, {}};
  image.rgba.assign(data.get(), data.get() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  return image;
}

ImageF load_hdr(const std::filesystem::path& path) {
  File f = open_checked(path, true);
  int w = 0, h = 0, channels = 0;
  // stb_image hangs on some truncated files (hdr_scan.h): check the data is all there.
  if (!stbi_info_from_file(f.get(), &w, &h, &channels)) fail(path, "not a readable image");
  const long start = std::ftell(f.get());
  if (const std::string problem = detail::hdr_truncation(f.get(), w, h); !problem.empty()) fail(path, problem);
  if (start < 0 || std::fseek(f.get(), start, SEEK_SET) != 0) fail(path, "cannot seek back to the start");
  std::unique_ptr<float, StbFree> data(stbi_loadf_from_file(f.get(), &w, &h, &channels, 3));
  if (!data) fail(path, std::string("cannot decode (") + stbi_failure_reason() + ")");
  return decode_hdr(data.get(), w, h);
}

void write_hdr(const std::filesystem::path& path, const ImageF& image) {
  raster::write_file_atomic(path, encode_hdr(image, path));
}

ImageF hdr_round_trip(const ImageF& image) {
  const std::vector<unsigned char> bytes = encode_hdr(image, "hdr_round_trip");
  int w = 0, h = 0, channels = 0;
  std::unique_ptr<float, StbFree> data(
      stbi_loadf_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &channels, 3));
  if (!data) throw std::runtime_error(std::string("hdr_round_trip: cannot decode (") + stbi_failure_reason() + ")");
  return decode_hdr(data.get(), w, h);
}

ImageF to_image(const raster::Target& target) {
  ImageF image{target.width(), target.height(), {}};
  image.rgba.reserve(target.colors().size() * 4);
  for (const glm::vec4& c : target.colors()) image.rgba.insert(image.rgba.end(), {c.r, c.g, c.b, c.a});
  return image;
}

ImageF to_float(const Image8& image) {
  ImageF out{image.width, image.height, {}};
  out.rgba.reserve(image.rgba.size());
  for (std::uint8_t code : image.rgba) out.rgba.push_back(static_cast<float>(code) / 255.0f);
  return out;
}

Image8 to_srgb8(const ImageF& image) {
  detail::check_pixel_data(image, "to_srgb8");
  Image8 out{image.width, image.height, {}};
  out.rgba.resize(image.rgba.size());
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
    out.rgba[i + 0] = raster::linear_to_srgb8(image.rgba[i + 0]);
    out.rgba[i + 1] = raster::linear_to_srgb8(image.rgba[i + 1]);
    out.rgba[i + 2] = raster::linear_to_srgb8(image.rgba[i + 2]);
    out.rgba[i + 3] = raster::unorm8(image.rgba[i + 3]);
  }
  return out;
}

}  // namespace softpbr::golden
