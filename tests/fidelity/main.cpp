// softpbr_fidelity — the README's fidelity table: softpbr against Blender Cycles (256
// samples a pixel) and three.js r187 on ../shared/fidelity's four models, by the protocol of
// its README (fidelity.h). Options: --shared DIR (default: ../shared beside the source
// tree), --out DIR (writes <model>.png, softpbr's frame through three.js's ACES, to look at
// beside the references), --threads N.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "fidelity.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  using namespace softpbr;
  fs::path shared = fidelity::find_shared(SOFTPBR_SOURCE_DIR), out;
  unsigned threads = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--shared" && i + 1 < argc) shared = argv[++i];
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--threads" && i + 1 < argc) threads = static_cast<unsigned>(std::atoi(argv[++i]));
    else {
      std::fprintf(stderr, "usage: softpbr_fidelity [--shared DIR] [--out DIR] [--threads N]\n");
      return 2;
    }
  }
  if (shared.empty()) {
    std::fprintf(stderr, "softpbr_fidelity: ../shared/fidelity not found (give --shared DIR)\n");
    return 2;
  }
  try {
    raster::Renderer renderer({.threads = threads});
    if (!out.empty()) fs::create_directories(out);
    std::printf("| model | softpbr vs Cycles | three.js vs Cycles | softpbr vs three.js | pixels |\n");
    std::printf("|---|---|---|---|---|\n");
    for (const std::string& m : fidelity::models()) {
      const fidelity::Result r = fidelity::measure(shared, m, renderer);
      std::printf("| %s | %.2f dB | %.2f dB | %.2f dB | %zu |\n", m.c_str(), r.vs_cycles, r.threejs_vs_cycles,
                  r.vs_threejs, r.pixels);
      std::fflush(stdout);
      if (out.empty()) continue;
      image::write_file_atomic(out / (m + ".png"), image::encode_png(r.image, m + ".png"));
      // Side by side: softpbr, three.js, Cycles, and |softpbr − Cycles| × 4.
      const fs::path refs = shared / "fidelity" / m;
      const image::Image8 three = image::load_png(refs / "threejs_aces.png");
      const image::Image8 cycles = image::load_png(refs / "cycles_256spp_aces.png");
      const int w = r.image.width, h = r.image.height;
      image::Image8 side(4 * w, h, image::PixelVector<std::uint8_t>(static_cast<std::size_t>(4 * w) * h * 4));
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t p = (static_cast<std::size_t>(y) * w + x) * 4;
          for (int c = 0; c < 4; ++c) {
            const std::size_t row = static_cast<std::size_t>(y) * 4 * w;
            side.rgba[(row + x) * 4 + c] = r.image.rgba[p + c];
            side.rgba[(row + w + x) * 4 + c] = three.rgba[p + c];
            side.rgba[(row + 2 * w + x) * 4 + c] = cycles.rgba[p + c];
            const int d = std::abs(static_cast<int>(r.image.rgba[p + c]) - static_cast<int>(cycles.rgba[p + c])) * 4;
            side.rgba[(row + 3 * w + x) * 4 + c] = c == 3 ? 255 : static_cast<std::uint8_t>(std::min(d, 255));
          }
        }
      image::write_file_atomic(out / (m + "_compare.png"), image::encode_png(side, m + "_compare.png"));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "softpbr_fidelity: %s\n", e.what());
    return 3;
  }
  return 0;
}
