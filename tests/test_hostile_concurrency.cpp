// Concurrency: several renderers rendering at once in one process, each on several
// threads, give the same bits as one renderer on one thread. The suite also runs alone
// under ThreadSanitizer (softpbr_tsan_tests, built by .ci/fuzz), which must report nothing.
#include <doctest/doctest.h>

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace raster = softpbr::raster;
namespace pbr = softpbr::pbr;

namespace {

// The gallery, small: 96 × 72 pixels with 24-segment spheres keeps the TSan run short
// while every tile size below still splits the image into several tiles.
constexpr int kWidth = 96, kHeight = 72;

pbr::Scene small_gallery() {
  pbr::GalleryOptions options;
  options.segments = 24;
  return pbr::make_gallery(options);
}

std::uint64_t render_hash(const pbr::Scene& scene, raster::Renderer& renderer) {
  raster::Target target(kWidth, kHeight);
  pbr::render(scene, renderer, target);
  return raster::hash_colors(target) ^ (raster::hash_depths(target) * 31);
}

struct Config {
  unsigned threads;
  int tile_size;
  int lanes;
};

}  // namespace

TEST_CASE("concurrent renderers on shared scenes give the single-threaded image, frame after frame") {
  const pbr::Scene scene = small_gallery();  // shared, read-only, by every renderer
  raster::Renderer reference_renderer({.threads = 1, .tile_size = 64, .lanes = 1});
  const std::uint64_t reference = render_hash(scene, reference_renderer);

  const Config configs[] = {{2, 8, 1}, {3, 16, 4}, {4, 10, 8}, {2, 64, 16}};
  constexpr int kFrames = 2;  // a second frame reuses each renderer's recycled draw memory
  std::vector<std::uint64_t> hashes(std::size(configs) * kFrames, 0);
  std::vector<std::thread> callers;
  for (std::size_t c = 0; c < std::size(configs); ++c)
    callers.emplace_back([&, c] {
      raster::Renderer renderer({.threads = configs[c].threads, .tile_size = configs[c].tile_size,
                                 .lanes = configs[c].lanes});
      for (int f = 0; f < kFrames; ++f) hashes[c * kFrames + static_cast<std::size_t>(f)] = render_hash(scene, renderer);
    });
  for (std::thread& t : callers) t.join();

  for (std::size_t i = 0; i < hashes.size(); ++i) {
    CAPTURE(i);
    CHECK(hashes[i] == reference);
  }
}

TEST_CASE("one renderer used from different threads in turn gives the same image each time") {
  const pbr::Scene scene = small_gallery();
  raster::Renderer renderer({.threads = 3, .tile_size = 16});
  const std::uint64_t first = render_hash(scene, renderer);
  for (int round = 0; round < 2; ++round) {
    std::uint64_t hash = 0;
    std::thread([&] { hash = render_hash(scene, renderer); }).join();  // join orders the frames
    CHECK(hash == first);
  }
}

TEST_CASE("a cancelled frame throws Cancelled and the renderer's next frame has the uncancelled bits") {
  const pbr::Scene scene = small_gallery();
  raster::Renderer reference({.threads = 1, .tile_size = 16});
  const std::uint64_t expected = render_hash(scene, reference);
  for (const unsigned threads : {1u, 2u, 3u}) {
    CAPTURE(threads);
    // Polled from every thread: cancels from the fourth tile on until `armed` is cleared.
    std::atomic<int> polls{0};
    std::atomic<bool> armed{true};
    raster::Renderer renderer({.threads = threads,
                               .tile_size = 16,
                               .cancel = [&] { return polls.fetch_add(1, std::memory_order_relaxed) >= 3 && armed.load(); }});
    raster::Target target(kWidth, kHeight);
    CHECK_THROWS_AS(pbr::render(scene, renderer, target), raster::Cancelled);
    // 30 tiles: polling stopped once a thread saw the cancellation (at most one poll per thread after it).
    CHECK(polls.load() < 3 + 2 * static_cast<int>(threads));
    armed = false;
    pbr::render(scene, renderer, target);  // the same target: its cleared-tile record must not lie
    CHECK((raster::hash_colors(target) ^ (raster::hash_depths(target) * 31)) == expected);
  }
}
